// Turns a validated spec into what the renderer consumes: the environment in
// the working colour space with its SH irradiance, the material with its
// colours converted, per-frame uniforms, and the camera-distance range that
// decides which material features a run needs.
#pragma once

#include "core/scene/environment.h"
#include "core/render/surface_pass.h"
#include "core/material/sand_material.h"
#include "experiments/spec/experiment_spec.h"
#include "metrics/color/color_manager.h"

namespace glintlab {

// Sky map and sun converted to `working_space` (OCIO), SH irradiance computed.
core::Environment prepare_environment(const ExperimentSpec& spec, const metrics::ColorManager& cm);
core::EnvironmentTexture environment_texture(const core::Environment& env);

// Palette and glint gain converted from their named space to the working space.
core::SandParams to_working_space(core::SandParams p, const std::string& working_space,
                                  const metrics::ColorManager& cm);

core::FrameUniforms frame_uniforms(const core::FrameCamera& cam, const core::Environment& env, int width, int height,
                                   size_t env_mip_levels);

// Bounds of the distance from the eye to any point of the mesh over the run's
// frames (conservative: from the mesh's bounding box).
core::SandFeatures distance_range(const ExperimentSpec& spec, const core::Mesh& mesh);

}  // namespace glintlab

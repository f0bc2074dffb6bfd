// Turns a validated spec into what the renderer consumes: the environment in
// the working colour space with its SH irradiance, the material with its
// colours converted, per-frame uniforms, and the camera-distance range that
// decides which material features a run needs.
#pragma once

#include "core/scene/environment.h"
#include "core/scene/mesh.h"
#include "core/render/frame_uniforms.h"
#include "core/render/scene_gpu.h"
#include "core/scene/object_motion.h"
#include "core/material/sand_material.h"
#include "experiments/spec/experiment_spec.h"
#include "metrics/color/color_manager.h"

#include <map>
#include <memory>

namespace glintlab {

// Sky map and sun converted to `working_space` (OCIO), SH irradiance computed.
core::Environment prepare_environment(const ExperimentSpec& spec, const metrics::ColorManager& cm);
core::EnvironmentTexture environment_texture(const core::Environment& env);

// Palette and glint gain converted from their named space to the working space.
core::SandParams to_working_space(core::SandParams p, const std::string& working_space,
                                  const metrics::ColorManager& cm);

// Frame uniforms of camera frame `cam`; `motion` moves the mesh (model and
// previous model matrices from cam.time and cam.prev_time).
core::FrameUniforms frame_uniforms(const core::FrameCamera& cam, const core::Environment& env, int width, int height,
                                   size_t env_mip_levels, const core::ObjectMotion& motion = {});

// Checks every colour-space, display and view name of the spec against the
// OCIO config before anything renders: a ConfigError names the file, the key
// and the names the config has.
void check_color_names(const ExperimentSpec& spec, const metrics::ColorManager& cm);

// What is wrong with a display/view pair for the OCIO config ("unknown display ...; allowed: ...",
// "display ... has no view ...; allowed: ..."), or "" when the config has both.
std::string display_view_problem(const metrics::ColorManager& cm, const std::string& display, const std::string& view);

// Everything about the scene that is built once per run, CPU side.
struct SceneData {
  core::Mesh mesh;  // as the run's (output) resolution adapts it: what the truth and native variants draw
  // The adaptive grid at each render scale below 1 that a variant draws it at ("mesh_lod" "render";
  // nothing for a grid that does not adapt).
  std::map<double, core::Mesh> render_lods;
  core::Environment env;
  core::EnvironmentTexture env_texture;
  core::SandFeatures range;  // camera distances the run reaches (pruning)
};
SceneData build_scene(const ExperimentSpec& spec, const metrics::ColorManager& cm);

// The OCIO config of a run: `ocio_config` (--ocio-config) if given, else $OCIO, else the shipped one.
// One that is missing or does not load is bad input (ConfigError naming the option and the file).
metrics::ColorManager load_color_manager(const std::string& ocio_config);

// The camera positions an adaptive grid ("max_edge_px") serves: every frame of the path, at the
// spec's resolution times `render_scale` (the pixels the grid's bounds count), in the mesh's object
// space. Empty when the grid does not adapt.
std::vector<core::MeshView> mesh_views(const ExperimentSpec& spec, double render_scale = 1.0);

// The scene on the GPU: SceneData's mesh and its render-scale levels of detail, which share its
// environment map.
class SceneGpus {
 public:
  SceneGpus(const core::VkContext& ctx, const SceneData& data);
  const core::SceneGpu& display() const { return *display_; }
  // What variant `v` draws: its render scale's level of detail where SceneData has one and the variant
  // asks for it (mesh_lod "render"), else the display mesh.
  const core::SceneGpu& of(const VariantSpec& v) const;

 private:
  std::unique_ptr<core::SceneGpu> display_;
  std::map<double, std::unique_ptr<core::SceneGpu>> lods_;
};

// Frame uniforms of frame `k` of the spec's path (unjittered camera, mesh motion).
core::FrameUniforms frame_uniforms(const ExperimentSpec& spec, const SceneData& scene, int k);

// Bounds of the distance from the eye to any point of the mesh over the run's
// frames (conservative: from the mesh's bounding box).
core::SandFeatures distance_range(const ExperimentSpec& spec, const core::Mesh& mesh);

}  // namespace glintlab

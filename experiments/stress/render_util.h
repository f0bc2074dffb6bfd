// What the render and TAA stress cases share: a scene on the GPU with a
// constant sky, frame uniforms from a camera, and one frame of a graph.
#pragma once

#include "core/render/frame_graph.h"
#include "core/render/frame_uniforms.h"
#include "core/render/scene_gpu.h"
#include "core/scene/camera.h"
#include "core/scene/mesh.h"

#include <glm/glm.hpp>

#include <memory>
#include <vector>

namespace glintlab::stress {

// A constant environment (every texel `sky`) with its mip chain.
core::EnvironmentTexture constant_env(float sky);

struct Lighting {
  glm::vec3 sun_dir{0.3f, 0.8f, 0.2f};  // towards the sun (normalised by frame_uniforms)
  glm::vec3 sun_L{6.0f};                // sun radiance (normal irradiance)
  float sun_radius = 0.0046f;           // angular radius (rad)
  glm::vec3 sky{0.5f};                  // L_sky^Omega of eq. 4.2 for every normal
};

// Uniforms of an unjittered camera (prev = this frame: no motion). `model`
// moves the mesh (object -> world).
core::FrameUniforms frame_uniforms(const core::CameraState& cam, int width, int height, const Lighting& light,
                                   const glm::mat4& model = glm::mat4(1.0f));

// The samples of a frame: one per offset (pixels), weight 1 / count.
std::vector<core::SamplePush> samples(const core::CameraState& cam, int width, int height,
                                      const std::vector<glm::vec2>& offsets = {glm::vec2(0.0f)});

// A plane (type "plane") of `size` units with `tess` quads per edge.
core::Mesh plane_mesh(float size, int tess = 4);

}  // namespace glintlab::stress

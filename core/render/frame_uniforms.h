// What every pass of a frame sees from the host: the per-frame uniform block
// (std140 mirror of FrameUBO in shaders/common/frame.glsl) and the per-sample
// push constants. Keep the C++ and GLSL copies in the same order; a test
// checks the offsets glslang gives the GLSL block.
#pragma once

#include <glm/glm.hpp>

namespace glintlab::core {

struct FrameUniforms {
  glm::mat4 model{1.0f};           // object -> world, this frame
  glm::mat4 normal_matrix{1.0f};   // inverse transpose of model
  glm::mat4 prev_model{1.0f};      // object -> world, previous frame (object motion)
  glm::mat4 view_proj{1.0f};       // this frame, unjittered (motion vectors)
  glm::mat4 prev_view_proj{1.0f};  // previous frame, unjittered (motion vectors)
  glm::mat4 inv_view_proj{1.0f};   // inverse of view_proj (sky rays)
  glm::vec4 camera_pos{0.0f};      // xyz world eye, w = time (s)
  glm::vec4 prev_camera_pos{0.0f}; // xyz previous frame's eye
  glm::vec4 sun_dir{0.0f, 1.0f, 0.0f, 0.0f};  // xyz unit vector to the sun, w = angular radius (rad)
  glm::vec4 sun_L{0.0f};           // rgb sun radiance, working space
  glm::vec4 resolution{0.0f};      // width, height, 1/width, 1/height
  glm::vec4 env_sh[9] = {};        // SH irradiance coefficients, rgb
  glm::vec4 env_params{1.0f, 1.0f, 0.0f, 0.0f};  // x = env_map mip levels, y = sky radiance scale
};
static_assert(sizeof(FrameUniforms) == 6 * 64 + 5 * 16 + 9 * 16 + 16, "FrameUniforms must match frame.glsl");

// One sample of a frame: the surface pass draws the scene once per sample and
// accumulates weight * radiance.
struct SamplePush {
  glm::mat4 view_proj{1.0f};                           // this sample's jittered view-projection
  glm::vec4 jitter_weight{0.0f, 0.0f, 1.0f, 0.0f};     // jitter (px), weight, sample index
};
static_assert(sizeof(SamplePush) == 80, "SamplePush must match frame.glsl");

}  // namespace glintlab::core

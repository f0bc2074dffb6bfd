// The forward renderer: a GPU copy of the scene (mesh + environment), and a
// surface pass that draws it with one fragment shader (the sand material, a
// debug/test shader, ...) into an RGBA32F target. A frame is the mean of one
// draw per sample: one sample for a normal frame, N jittered samples for a
// supersampled or reference frame (fp32 additive blending, box filter). Each
// sample is a depth pre-pass, then shading with depth EQUAL, so exactly the
// nearest surface is shaded and accumulated, whatever the draw order.
#pragma once

#include "core/vk/gpu_resources.h"
#include "core/util/image.h"
#include "core/vk/pipeline.h"
#include "core/vk/vk_context.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace glintlab::core {

struct Mesh;

// std140 mirror of FrameUBO in shaders/common/frame.glsl.
struct FrameUniforms {
  glm::mat4 model{1.0f};
  glm::mat4 normal_matrix{1.0f};
  glm::mat4 prev_view_proj{1.0f};
  glm::mat4 inv_view_proj{1.0f};
  glm::vec4 camera_pos{0.0f};
  glm::vec4 sun_dir{0.0f, 1.0f, 0.0f, 0.0f};
  glm::vec4 sun_L{0.0f};
  glm::vec4 resolution{0.0f};
  glm::vec4 env_sh[9] = {};
  glm::vec4 env_params{1.0f, 1.0f, 0.0f, 0.0f};
};
static_assert(sizeof(FrameUniforms) == 4 * 64 + 4 * 16 + 9 * 16 + 16, "FrameUniforms must match frame.glsl");

// Push constants of shaders/common/frame.glsl.
struct SamplePush {
  glm::mat4 view_proj{1.0f};
  glm::vec4 jitter_weight{0.0f, 0.0f, 1.0f, 0.0f};  // jitter px, weight, sample index
};
static_assert(sizeof(SamplePush) == 80, "SamplePush must match frame.glsl");

// Environment as the GPU needs it: an RGBA32F lat-long mip chain (level 0
// first, each level half the size of the previous, rounded down, at least 1).
struct EnvironmentTexture {
  uint32_t width = 0, height = 0;
  std::vector<std::vector<float>> mips_rgba;
};

// Everything that is uploaded once per run and shared by every variant.
class SceneGpu {
 public:
  SceneGpu(const VkContext& ctx, const Mesh& mesh, const EnvironmentTexture& env);

  const Buffer& vertices() const { return vertices_; }
  const Buffer& indices() const { return indices_; }
  uint32_t index_count() const { return index_count_; }
  const Image2D& env_map() const { return env_map_; }
  VkSampler env_sampler() const { return sampler_.get(); }

 private:
  Buffer vertices_, indices_;
  uint32_t index_count_ = 0;
  Image2D env_map_;
  Sampler sampler_;
};

struct SurfaceShader {
  std::string fragment;               // path under shaders/, e.g. "passes/sand.frag"
  std::vector<std::string> defines;   // compile-time features ("NAME" or "NAME=VALUE")
  std::vector<std::byte> material;    // contents of the material UBO (set 0, binding 1); may be empty
};

struct PassTiming {
  std::string pass;
  double gpu_ms = 0;  // from GPU timestamps; 0 if the device has none
};

struct FrameOutput {
  Image color;  // RGBA32F scene-linear; alpha = surface coverage
  std::vector<PassTiming> timings;
};

class SurfacePass {
 public:
  SurfacePass(const VkContext& ctx, const SceneGpu& scene, int width, int height, const SurfaceShader& shader,
              bool draw_sky = true);

  // Renders the mean of one draw per sample and reads it back. `label` names
  // the pass in the timings ("forward", "reference").
  FrameOutput render(const FrameUniforms& frame, const std::vector<SamplePush>& samples,
                     const std::string& label = "forward");

  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& fragment_source_hash() const { return fragment_hash_; }

 private:
  const VkContext& ctx_;
  const SceneGpu& scene_;
  int width_, height_;
  bool draw_sky_;
  std::string fragment_hash_;
  Image2D color_, depth_;
  RenderPass render_pass_;
  Framebuffer framebuffer_;
  DescriptorSetLayout set_layout_;
  PipelineLayout layout_;
  Pipeline depth_pipeline_, surface_pipeline_, sky_pipeline_;
  Buffer frame_ubo_, material_ubo_;
  DescriptorSet descriptors_;
  QueryPool queries_;
};

// Sample offsets of an n x n stratified grid in [-0.5, 0.5)^2 pixels, each
// jittered inside its stratum by a fixed-seed generator (reproducible).
std::vector<glm::vec2> stratified_offsets(int n, uint32_t seed);

}  // namespace glintlab::core

// The surface pass: draws the scene's mesh with a material program
// (core/material/program.h) into the "color" target, RGBA32F scene-linear,
// alpha = surface coverage. A frame is the mean of one draw per sample of
// FrameInputs::samples (fp32 additive blending, box filter): one sample for a
// normal frame, N jittered ones for supersampling or the reference. Exactly one
// nearest surface per pixel and sample is shaded and added, whatever the draw
// order, ties included, in one of three ways:
//  - option `single_sample`: one opaque draw, depth test LESS, into the colour
//    target; with the sky on nothing is cleared first (every pixel is written
//    once);
//  - several samples, no motion vectors, not supersampled (SSAA): each sample
//    the same opaque draw into the pass's own image, which a full-screen draw
//    (passes/add_sample.frag) adds to the colour target by blending: no depth
//    pre-pass;
//  - otherwise (option `supersample`, or motion with several samples): per
//    sample a depth pre-pass, then shading with depth test EQUAL and a stencil
//    test that passes one fragment per pixel, blended into the target.
// Then (option `sky`) the environment fills what no surface covers.
//
// With option `glint` (and `motion`) it also writes the "glint" target (the glint layer).
// With option `motion` it also writes the "motion" target (RGBA32F, layout in
// shaders/common/motion.glsl: motion vector in pixels, distance now, distance
// in the previous frame) from the last sample's nearest surface. Where the
// pass draws into the graph's targets (one opaque sample, or blended samples
// with motion), the "depth" target (D32; D32S8 when blending) is the last
// sample's depth buffer; summed and supersampled samples use the pass's own.
//
// With option `supersample` = f > 1 (the reference's many samples) it renders
// at f times the resolution and box-filters into "color": f^2 samples per
// pixel from each geometry pass, so geometry work drops by f^2.
#pragma once

#include "core/material/program.h"
#include "core/render/frame_graph.h"
#include "core/render/pass.h"
#include "core/render/scene_gpu.h"
#include "core/vk/pipeline.h"

#include <array>
#include <string>
#include <vector>

namespace glintlab::core {

struct SurfacePassOptions {
  std::string name = "surface";  // the pass's name in timings
  MaterialProgram program;
  bool sky = true;               // draw the environment where no surface is
  bool motion = false;           // also write motion vectors and distances
  // The colour target: RGBA32F (default; fp32 accumulation) or RGBA16F
  // (what a real-time renderer would use; stress cases check it stays finite).
  VkFormat color_format = VK_FORMAT_R32G32B32A32_SFLOAT;
  // f > 1: the pass renders at f times the resolution into its own images
  // and box-filters every f x f block into the colour target (one geometry
  // pass serves f^2 samples per pixel; samples' jitters then lie within one
  // high-resolution pixel). RGBA32F colour, no motion, no "depth" target.
  int supersample = 1;
  // With supersample >= 2: also write the means of each block's two checkerboard halves into
  // half_targets (RGBA32F; passes/downsample.comp): two independent estimates at half the samples,
  // whose difference measures the noise of the colour target's own estimate. The colour target is
  // the same bits with or without them.
  bool halves = false;
  std::string half_targets[2] = {"color.a", "color.b"};
  // One sample per frame (no AA, TAA, motion): no depth pre-pass; the shading
  // draw tests LESS and writes depth and colour unblended, so the nearest
  // surface's colour is what remains (a farther fragment drawn first is
  // shaded, then overwritten: overdraw instead of a second geometry pass).
  bool single_sample = false;
  // Draw only the mesh chunks each sample's view can see (core/render/chunk_culling.h);
  // the image is the same either way, off only to compare.
  bool cull = true;
  // With motion: also write the "glint" target (RGBA32F, accumulated like the colour): rgb = the
  // glint term's part of the radiance, a = its share of the luma (passes/sand.frag; shaders without
  // glints write 0). What the glint-aware TAA options read.
  bool glint = false;
  // The size it renders at where it is not the graph's (0: the graph's): a variant's render scale
  // below its output resolution (its targets are this size; the TAA pass resolves them to the graph's).
  int width = 0, height = 0;
  // The glint models' pixel footprint (the uv derivatives) times this: below the output resolution,
  // s makes it the display pixel's instead of the render pixel's (SURFACE_FOOTPRINT_SCALE).
  float footprint_scale = 1.0f;
  // The sky along each sample's jittered ray rather than the pixel centre's (passes/sky.vert): where a
  // resolve places every sample where it was taken (rendering below the output resolution).
  bool sky_jittered = false;
  std::string color_target = "color";
  std::string motion_target = "motion";
  std::string depth_target = "depth";
  std::string glint_target = "glint";
};

class SurfacePass final : public Pass {
 public:
  SurfacePass(const VkContext& ctx, const SceneGpu& scene, SurfacePassOptions options);

  std::string name() const override { return opt_.name; }
  void declare(PassIO& io) const override;
  void setup(const TargetSet& targets) override;
  void record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& targets) override;

  const SurfacePassOptions& options() const { return opt_; }
  // Colour attachments of the shading draws: colour, then motion and the glint layer where on.
  int color_attachments() const { return 1 + (opt_.motion ? 1 : 0) + (opt_.glint ? 1 : 0); }
  // Hash of the preprocessed fragment source (part of a reference's cache key).
  const std::string& fragment_source_hash() const { return fragment_hash_; }
  // Triangles the last recorded frame drew per geometry pass, summed over its samples, and the
  // mesh's triangle count times the samples: what culling left out is the difference.
  uint64_t triangles_drawn() const { return triangles_drawn_; }
  uint64_t triangles_submitted_without_culling() const { return triangles_all_; }

 private:
  const VkContext& ctx_;
  const SceneGpu& scene_;
  SurfacePassOptions opt_;
  std::string fragment_hash_;
  RenderPass render_pass_;
  Framebuffer framebuffer_;
  DescriptorSetLayout set_layout_;
  PipelineLayout layout_;
  void build_surface_pipeline(const std::vector<std::string>& fragment_defines);
  void resolve(VkCommandBuffer cmd);
  void add_sample(VkCommandBuffer cmd, bool add, const VkRect2D& scissor);

  ShaderModule vertex_module_;
  std::vector<std::string> fragment_defines_;  // without the lighting constants
  std::array<glm::vec4, 11> built_lighting_{};  // what the surface pipeline was built with (frame_lighting_constants)
  Pipeline depth_pipeline_, surface_pipeline_, sky_pipeline_;
  VkFormat depth_format_ = VK_FORMAT_D32_SFLOAT;  // with a stencil when samples accumulate
  bool sum_opaque_ = false;  // several samples, each drawn opaque and added by a blended draw
  bool opaque_ = false;      // one opaque draw per sample (single_sample or sum_opaque_)
  Buffer frame_ubo_, material_ubo_;
  Buffer glint_table_;  // the glint model's data table, when it has one
  DescriptorSet descriptors_;
  int width_ = 0, height_ = 0;
  // supersample > 1 or a sum of opaque samples: the pass's own images (at f
  // times the resolution), and what reads the colour one into the target (the
  // box filter's compute pipeline, or the add pass's set and layout)
  Image2D hi_color_, hi_depth_;
  DescriptorSetLayout resolve_set_layout_;
  PipelineLayout resolve_layout_;
  Pipeline resolve_pipeline_;
  Sampler resolve_sampler_;
  DescriptorSet resolve_set_;
  // a sum of opaque samples: the pass that adds each to the colour target
  RenderPass add_render_pass_;
  Framebuffer add_framebuffer_;
  Pipeline add_pipeline_[2];  // write (the first sample), add
  bool hi_written_ = false;  // the high-resolution images were used by an earlier frame
  uint64_t triangles_drawn_ = 0, triangles_all_ = 0;
};

// One frame of a graph holding only a surface pass with `options`: the
// convenience tests and tools use. Reads back the colour (and the motion
// target when options.motion is set).
class SurfaceRenderer {
 public:
  SurfaceRenderer(const VkContext& ctx, const SceneGpu& scene, int width, int height, SurfacePassOptions options);
  FrameResult render(const FrameUniforms& frame, const std::vector<SamplePush>& samples);
  const SurfacePass& pass() const { return *pass_; }

 private:
  FrameGraph graph_;
  SurfacePass* pass_ = nullptr;
};

}  // namespace glintlab::core

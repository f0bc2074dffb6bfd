// The TAA resolve pass (a full-screen fragment pass, shaders/passes/taa.frag): blends this frame's
// jittered colour with the reprojected history that the frame graph keeps
// across frames. Reads "color" and "motion" (the surface pass with motion on);
// keeps "taa.history" (rgb = resolved colour, a = the surface distance at the
// pixel: with the disocclusion test, the nearest of its 3x3) and, with anti_flicker, "taa.luma" (the
// last lumas of the pixel) and, with `accumulate` or `glint_layer`, "taa.extra" (rgb = the glint
// layer's history, a = the frames accumulated at the pixel); with a glint-aware option it reads
// "glint" (the surface pass's glint layer); writes "taa.color" (rgb resolved, a = coverage).
// History restarts at camera cuts (the graph drops it), at off-screen
// reprojections (per pixel), wherever it is not finite and, with the option
// `disocclusion`, where the surface it holds is not the one seen now.
#pragma once

#include "core/render/pass.h"
#include "core/render/taa_settings.h"
#include "core/vk/pipeline.h"

#include <string>

namespace glintlab::core {

class TaaPass final : public Pass {
 public:
  // share_quads: where the image's width and height are even and the device has quad operations in
  // fragment shaders, the pixels of each 2x2 quad share their neighbourhood fetches (TAA_QUAD_SHARE in
  // passes/taa.frag; the same bits as fetching every texel, tested); false always fetches.
  TaaPass(const VkContext& ctx, TaaSettings settings, bool share_quads = true);

  std::string name() const override { return "taa"; }
  void declare(PassIO& io) const override;
  void setup(const TargetSet& targets) override;
  void record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& targets) override;

  const TaaSettings& settings() const { return s_; }
  // Whether the pipeline built for the current targets shares fetches within quads.
  bool shares_quads() const { return quad_share_; }
  // The compile-time defines of the resolve shader for these settings.
  static std::vector<std::string> defines(const TaaSettings& s, bool quad_share);

 private:
  void build_pipeline(bool quad_share);

  const VkContext& ctx_;
  TaaSettings s_;
  bool allow_quad_share_ = true;
  bool quad_share_ = false;
  std::vector<VkFormat> outputs_;
  DescriptorSetLayout set_layout_;
  PipelineLayout layout_;
  RenderPass render_pass_;
  Framebuffer framebuffers_[2];  // one per history slot parity
  Pipeline pipeline_;
  Sampler sampler_;
  DescriptorSet sets_[2];  // one per history slot parity
  glm::vec2 prev_jitter_{0.0f};  // the jitter of the frame last recorded
};

}  // namespace glintlab::core

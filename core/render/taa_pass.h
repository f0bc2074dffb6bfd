// The TAA pass: a full-screen fragment pass (shaders/passes/taa.frag) that runs a temporal resolve
// file (core/render/taa_resolve.h, shaders/taa/interface.glsl) once per pixel. Reads "color" and, where
// the resolve uses them, "motion" (the surface pass with motion on) and "glint" (its glint layer);
// keeps "taa.history" (rgb = TaaResult.history) and, where the resolve reads them back, "taa.state",
// "taa.state2" and "taa.history2" across frames; writes "taa.color" (rgb resolved, a = coverage).
// History is invalid (TaaPixel.history_valid false) in the first frame and after camera cuts and
// resets (the graph drops it).
#pragma once

#include "core/render/pass.h"
#include "core/render/taa_resolve.h"
#include "core/vk/pipeline.h"

#include <string>

namespace glintlab::core {

class TaaPass final : public Pass {
 public:
  // share_quads: where the image's width and height are even and the device has quad operations in
  // fragment shaders, the host tells the resolve that 2x2 quads are whole (TAA_QUAD_SHARE; falcor then
  // shares its neighbourhood fetches within quads: the same bits, tested); false never does.
  // std::invalid_argument for a parameter value out of its declared range.
  TaaPass(const VkContext& ctx, TaaSettings settings, bool share_quads = true);

  std::string name() const override { return "taa"; }
  void declare(PassIO& io) const override;
  void setup(const TargetSet& targets) override;
  void record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& targets) override;

  const TaaSettings& settings() const { return s_; }
  // Whether the pipeline built for the current targets shares fetches within quads.
  bool shares_quads() const { return quad_share_; }
  // Compiles the resolve as the pass would (no quad sharing), at and below the output resolution:
  // ShaderCompileError naming the file and line.
  static void compile(const TaaSettings& s);
  // What the resolve reads, for these settings.
  const TaaUses& uses() const { return uses_; }
  // The compile-time defines of passes/taa.frag for these settings.
  // scaled: the inputs are below the output resolution (TAA_RENDER_SCALED).
  static std::vector<std::string> defines(const TaaSettings& s, const TaaUses& uses, bool quad_share, bool scaled);

 private:
  void build_pipeline(bool quad_share, bool scaled);

  const VkContext& ctx_;
  TaaSettings s_;
  TaaUses uses_;
  bool allow_quad_share_ = true;
  bool quad_share_ = false;
  bool scaled_ = false;
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

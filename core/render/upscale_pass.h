// A spatial upscale (a full-screen fragment pass, shaders/passes/upscale.frag): reads a target rendered
// below the graph's resolution and writes it at the graph's by bilinear interpolation between render
// texel centres (alpha too). What a variant rendered at a "render_scale" below 1 without a temporal
// resolve is shown as: the baseline a temporal upscaler is measured beside.
#pragma once

#include "core/render/pass.h"
#include "core/vk/pipeline.h"

#include <string>

namespace glintlab::core {

class UpscalePass final : public Pass {
 public:
  UpscalePass(const VkContext& ctx, std::string input = "color", std::string output = "upscaled");

  std::string name() const override { return "upscale"; }
  void declare(PassIO& io) const override;
  void setup(const TargetSet& targets) override;
  void record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& targets) override;

 private:
  const VkContext& ctx_;
  std::string input_, output_;
  DescriptorSetLayout set_layout_;
  PipelineLayout layout_;
  RenderPass render_pass_;
  Framebuffer framebuffer_;
  Pipeline pipeline_;
  Sampler sampler_;
  DescriptorSet set_;
};

}  // namespace glintlab::core

#include "core/render/upscale_pass.h"

#include "core/vk/shader_compiler.h"

namespace glintlab::core {

namespace {
constexpr VkFormat kFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
struct UpscalePush {
  float out_width, out_height, in_width, in_height;
};
}  // namespace

UpscalePass::UpscalePass(const VkContext& ctx, std::string input, std::string output)
    : ctx_(ctx), input_(std::move(input)), output_(std::move(output)) {
  const std::vector<VkDescriptorSetLayoutBinding> b = {
      {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  set_layout_ = make_set_layout(ctx, b);
  layout_ = make_pipeline_layout(ctx, set_layout_.get(), sizeof(UpscalePush), VK_SHADER_STAGE_FRAGMENT_BIT);
  render_pass_ = make_color_render_pass(ctx, {kFormat}, VK_ATTACHMENT_LOAD_OP_DONT_CARE);
  ShaderCompiler& sc = default_shader_compiler();
  ShaderModule vm = make_shader_module(ctx, sc.compile("passes/fullscreen.vert", ShaderStage::Vertex).spirv);
  ShaderModule fm = make_shader_module(ctx, sc.compile("passes/upscale.frag", ShaderStage::Fragment).spirv);
  VkPipelineColorBlendAttachmentState write{};
  write.colorWriteMask = 0xf;
  pipeline_ = make_fullscreen_pipeline(ctx, layout_.get(), render_pass_.get(), vm.get(), fm.get(), {write});
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};  // texelFetch only
  si.magFilter = si.minFilter = VK_FILTER_NEAREST;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkSampler smp;
  vk_check(vkCreateSampler(ctx.device(), &si, nullptr, &smp), "vkCreateSampler");
  sampler_ = Sampler(ctx.device(), smp);
  set_ = make_descriptor_set(ctx, set_layout_.get(), b);
}

void UpscalePass::declare(PassIO& io) const {
  io.read(input_);
  io.write(output_, kFormat, TargetUse::ColorAttachment);
}

void UpscalePass::setup(const TargetSet& t) {
  write_image_descriptor(ctx_, set_.set, 0, t.image(input_).view(), sampler_.get(),
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  VkImageView view = t.image(output_).view();
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = render_pass_.get();
  fi.attachmentCount = 1;
  fi.pAttachments = &view;
  fi.width = uint32_t(t.width());
  fi.height = uint32_t(t.height());
  fi.layers = 1;
  VkFramebuffer fb;
  vk_check(vkCreateFramebuffer(ctx_.device(), &fi, nullptr, &fb), "vkCreateFramebuffer");
  framebuffer_ = Framebuffer(ctx_.device(), fb);
}

void UpscalePass::record(VkCommandBuffer cmd, const FrameInputs&, const TargetSet& t) {
  const Image2D& in = t.image(input_);
  const UpscalePush p{float(t.width()), float(t.height()), float(in.width()), float(in.height())};
  record_fullscreen_draw(cmd, {render_pass_.get(), framebuffer_.get(),
                               {{0, 0}, {uint32_t(t.width()), uint32_t(t.height())}}, pipeline_.get(), layout_.get(),
                               set_.set, &p, sizeof p});
}

}  // namespace glintlab::core

#include "core/render/taa_pass.h"

#include "core/vk/shader_compiler.h"

namespace glintlab::core {

namespace {
constexpr VkFormat kFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

struct TaaPush {
  float width, height, alpha, gamma;
  float history_valid, disocclusion_tolerance, jitter_change_x, jitter_change_y;
  float reactive, glint_alpha, unused0, unused1;
};
static_assert(sizeof(TaaPush) == 48, "TaaPush must match taa.frag");

enum Binding : uint32_t { kColor = 0, kMotion, kHistoryIn, kLumaIn, kGlint, kExtraIn };
}  // namespace

std::vector<std::string> TaaPass::defines(const TaaSettings& s, bool quad_share) {
  return {"TAA_CLAMP=" + std::to_string(int(s.clamp)),
          "TAA_SPACE=" + std::to_string(int(s.space)),
          "TAA_FILTER=" + std::to_string(int(s.history_filter)),
          std::string("TAA_DERING=") + (s.dering ? "1" : "0"),
          "TAA_VELOCITY=" + std::to_string(int(s.velocity)),
          "TAA_FEEDBACK=" + std::to_string(int(s.feedback)),
          "TAA_HDR=" + std::to_string(int(s.hdr)),
          std::string("TAA_ANTI_FLICKER=") + (s.anti_flicker ? "1" : "0"),
          std::string("TAA_GLINT=") + (s.reads_glints() ? "1" : "0"),
          std::string("TAA_EXTRA=") + (s.keeps_extra() ? "1" : "0"),
          std::string("TAA_ACCUMULATE=") + (s.accumulate ? "1" : "0"),
          std::string("TAA_REACTIVE=") + (s.reactive > 0.0 ? "1" : "0"),
          std::string("TAA_GLINT_LAYER=") + (s.glint_layer ? "1" : "0"),
          "TAA_GLINT_CLAMP=" + std::to_string(int(s.glint_clamp)),
          std::string("TAA_GLINT_LOCK=") + (s.glint_lock ? "1" : "0"),
          std::string("TAA_DISOCCLUSION=") + (s.disocclusion ? "1" : "0"),
          std::string("TAA_QUAD_SHARE=") + (quad_share ? "1" : "0")};
}

TaaPass::TaaPass(const VkContext& ctx, TaaSettings settings, bool share_quads)
    : ctx_(ctx), s_(settings), allow_quad_share_(share_quads) {
  if (!(s_.alpha > 0.0 && s_.alpha <= 1.0)) throw std::invalid_argument("taa: alpha must be in (0, 1]");
  if (!(s_.glint_alpha > 0.0 && s_.glint_alpha <= 1.0)) throw std::invalid_argument("taa: glint_alpha must be in (0, 1]");
  if (!(s_.reactive >= 0.0 && s_.reactive <= 1.0)) throw std::invalid_argument("taa: reactive must be in [0, 1]");
  std::vector<VkDescriptorSetLayoutBinding> b;
  for (uint32_t i = kColor; i <= kExtraIn; ++i)
    b.push_back({i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
  set_layout_ = make_set_layout(ctx, b);
  layout_ = make_pipeline_layout(ctx, set_layout_.get(), sizeof(TaaPush), VK_SHADER_STAGE_FRAGMENT_BIT);
  // A full-screen fragment pass rather than compute: on llvmpipe a compute pass has a cost per pixel
  // before any work that a fragment pass does not (tests/bench/README.md).
  // Every pixel's targets are written, so their old contents are not loaded.
  outputs_ = {kFormat, kFormat};                 // taa.color, taa.history
  if (s_.anti_flicker) outputs_.push_back(kFormat);  // taa.luma
  if (s_.keeps_extra()) outputs_.push_back(kFormat);   // taa.extra
  render_pass_ = make_color_render_pass(ctx, outputs_, VK_ATTACHMENT_LOAD_OP_DONT_CARE);
  // The pipeline waits for setup(): whether quads can share fetches depends on the image size.
  // texelFetch only: the sampler never filters, but combined image samplers need one.
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = si.minFilter = VK_FILTER_NEAREST;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkSampler smp;
  vk_check(vkCreateSampler(ctx.device(), &si, nullptr, &smp), "vkCreateSampler");
  sampler_ = Sampler(ctx.device(), smp);
  for (auto& set : sets_) set = make_descriptor_set(ctx, set_layout_.get(), b);
}

void TaaPass::declare(PassIO& io) const {
  io.read("color");
  io.read("motion");
  io.read_previous("taa.history");
  io.keep("taa.history", kFormat, TargetUse::ColorAttachment);
  io.write("taa.color", kFormat, TargetUse::ColorAttachment);
  if (s_.anti_flicker) {
    io.read_previous("taa.luma");
    io.keep("taa.luma", kFormat, TargetUse::ColorAttachment);
  }
  if (s_.reads_glints()) io.read("glint");
  if (s_.keeps_extra()) {
    io.read_previous("taa.extra");
    io.keep("taa.extra", kFormat, TargetUse::ColorAttachment);
  }
}

void TaaPass::build_pipeline(bool quad_share) {
  ShaderCompiler& sc = default_shader_compiler();
  CompiledShader vs = sc.compile("passes/fullscreen.vert", ShaderStage::Vertex);
  CompiledShader fs = sc.compile("passes/taa.frag", ShaderStage::Fragment, defines(s_, quad_share));
  ShaderModule vm = make_shader_module(ctx_, vs.spirv), fm = make_shader_module(ctx_, fs.spirv);
  VkPipelineColorBlendAttachmentState write{};
  write.colorWriteMask = 0xf;
  pipeline_ = make_fullscreen_pipeline(ctx_, layout_.get(), render_pass_.get(), vm.get(), fm.get(),
                                       std::vector<VkPipelineColorBlendAttachmentState>(outputs_.size(), write));
  quad_share_ = quad_share;
}

void TaaPass::setup(const TargetSet& t) {
  // Whole 2x2 quads cover an image of even width and height exactly (passes/taa.frag, TAA_QUAD_SHARE).
  const bool quad = allow_quad_share_ && ctx_.fragment_quad_operations() && t.width() % 2 == 0 && t.height() % 2 == 0;
  if (!pipeline_.get() || quad != quad_share_) build_pipeline(quad);
  for (int slot = 0; slot < 2; ++slot) {
    VkDescriptorSet set = sets_[slot].set;
    auto sampled = [&](uint32_t binding, const Image2D& img) {
      write_image_descriptor(ctx_, set, binding, img.view(), sampler_.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    };
    sampled(kColor, t.image("color"));
    sampled(kMotion, t.image("motion"));
    sampled(kHistoryIn, t.slot("taa.history", 1 - slot));
    // Without anti_flicker the luma binding is unused; it points at the history (never accessed).
    sampled(kLumaIn, s_.anti_flicker ? t.slot("taa.luma", 1 - slot) : t.slot("taa.history", 1 - slot));
    // Likewise the glint layer and the second history where no option reads them.
    sampled(kGlint, s_.reads_glints() ? t.image("glint") : t.slot("taa.history", 1 - slot));
    sampled(kExtraIn, s_.keeps_extra() ? t.slot("taa.extra", 1 - slot) : t.slot("taa.history", 1 - slot));
    std::vector<VkImageView> views = {t.image("taa.color").view(), t.slot("taa.history", slot).view()};
    if (s_.anti_flicker) views.push_back(t.slot("taa.luma", slot).view());
    if (s_.keeps_extra()) views.push_back(t.slot("taa.extra", slot).view());
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = render_pass_.get();
    fi.attachmentCount = uint32_t(views.size());
    fi.pAttachments = views.data();
    fi.width = uint32_t(t.width());
    fi.height = uint32_t(t.height());
    fi.layers = 1;
    VkFramebuffer fb;
    vk_check(vkCreateFramebuffer(ctx_.device(), &fi, nullptr, &fb), "vkCreateFramebuffer");
    framebuffers_[slot] = Framebuffer(ctx_.device(), fb);
  }
}

void TaaPass::record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& t) {
  // This frame's jitter (TAA renders one sample a pixel) and its change since the frame the history
  // holds, for the disocclusion test's lookup of the history's point-sampled distances.
  const glm::vec2 jitter = in.samples.empty() ? glm::vec2(0.0f) : glm::vec2(in.samples[0].jitter_weight);
  const bool history = t.history_valid("taa.history");
  const glm::vec2 change = history ? prev_jitter_ - jitter : glm::vec2(0.0f);
  prev_jitter_ = jitter;
  TaaPush p{float(t.width()), float(t.height()), float(s_.alpha), float(s_.gamma),
            history ? 1.0f : 0.0f, float(s_.disocclusion_tolerance), change.x, change.y,
            float(s_.reactive), float(s_.glint_alpha), 0.0f, 0.0f};
  const int slot = t.current_slot("taa.history");
  const VkRect2D area{{0, 0}, {uint32_t(t.width()), uint32_t(t.height())}};
  const VkViewport viewport{0, 0, float(t.width()), float(t.height()), 0, 1};
  VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rb.renderPass = render_pass_.get();
  rb.framebuffer = framebuffers_[slot].get();
  rb.renderArea = area;
  vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &area);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &sets_[slot].set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof p, &p);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRenderPass(cmd);
}

}  // namespace glintlab::core

#include "core/render/taa_pass.h"

#include "core/vk/shader_compiler.h"

namespace glintlab::core {

namespace {
constexpr VkFormat kFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

struct TaaPush {
  float width, height, history_valid, frame;
  float jitter_x, jitter_y, jitter_prev_x, jitter_prev_y;  // output pixels
  float render_width, render_height, scale_x, scale_y;     // scale = render size / output size
  float values[kMaxTaaParameters];
};
static_assert(sizeof(TaaPush) == 112, "TaaPush must match passes/taa.frag");

enum Binding : uint32_t { kColor = 0, kMotion, kHistoryIn, kStateIn, kState2In, kHistory2In, kGlint };

// The kept targets beyond taa.history, in the order of their colour outputs (passes/taa.frag), each
// where the resolve uses it.
std::vector<std::pair<const char*, uint32_t>> kept_targets(const TaaUses& u) {
  std::vector<std::pair<const char*, uint32_t>> out;
  if (u.state) out.push_back({"taa.state", kStateIn});
  if (u.state2) out.push_back({"taa.state2", kState2In});
  if (u.history2) out.push_back({"taa.history2", kHistory2In});
  return out;
}
}  // namespace

std::vector<std::string> TaaPass::defines(const TaaSettings& s, const TaaUses& u, bool quad_share, bool scaled) {
  std::vector<std::string> d = s.defines();
  auto flag = [&](const char* name, bool on) { d.push_back(std::string(name) + "=" + (on ? "1" : "0")); };
  flag("TAA_USES_MOTION", u.motion);
  flag("TAA_USES_GLINT", u.glint);
  flag("TAA_USES_STATE", u.state);
  flag("TAA_USES_STATE2", u.state2);
  flag("TAA_USES_HISTORY2", u.history2);
  flag("TAA_QUAD_SHARE", quad_share);
  flag("TAA_RENDER_SCALED", scaled);
  return d;
}

void TaaPass::compile(const TaaSettings& s) {
  for (bool scaled : {false, true})
    default_shader_compiler().compile("passes/taa.frag", ShaderStage::Fragment, defines(s, s.uses(), false, scaled));
}

TaaPass::TaaPass(const VkContext& ctx, TaaSettings settings, bool share_quads)
    : ctx_(ctx), s_(std::move(settings)), allow_quad_share_(share_quads) {
  for (size_t i = 0; i < s_.resolve->parameters.size(); ++i) s_.set(s_.resolve->parameters[i].name, s_.values[i]);
  uses_ = s_.uses();
  std::vector<VkDescriptorSetLayoutBinding> b;
  for (uint32_t i = kColor; i <= kGlint; ++i)
    b.push_back({i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
  set_layout_ = make_set_layout(ctx, b);
  layout_ = make_pipeline_layout(ctx, set_layout_.get(), sizeof(TaaPush), VK_SHADER_STAGE_FRAGMENT_BIT);
  // A full-screen fragment pass rather than compute: on llvmpipe a compute pass has a cost per pixel
  // before any work that a fragment pass does not (tests/bench/README.md).
  // Every pixel's targets are written, so their old contents are not loaded.
  outputs_ = {kFormat, kFormat};  // taa.color, taa.history
  for (size_t i = 0; i < kept_targets(uses_).size(); ++i) outputs_.push_back(kFormat);
  render_pass_ = make_color_render_pass(ctx, outputs_, VK_ATTACHMENT_LOAD_OP_DONT_CARE);
  // The pipeline waits for setup(): whether quads are whole depends on the image size.
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
  if (uses_.motion) io.read("motion");
  if (uses_.glint) io.read("glint");
  io.read_previous("taa.history");
  io.keep("taa.history", kFormat, TargetUse::ColorAttachment);
  for (const auto& [name, binding] : kept_targets(uses_)) {
    io.read_previous(name);
    io.keep(name, kFormat, TargetUse::ColorAttachment);
  }
  io.write("taa.color", kFormat, TargetUse::ColorAttachment);
}

void TaaPass::build_pipeline(bool quad_share, bool scaled) {
  ShaderCompiler& sc = default_shader_compiler();
  CompiledShader vs = sc.compile("passes/fullscreen.vert", ShaderStage::Vertex);
  CompiledShader fs = sc.compile("passes/taa.frag", ShaderStage::Fragment, defines(s_, uses_, quad_share, scaled));
  ShaderModule vm = make_shader_module(ctx_, vs.spirv), fm = make_shader_module(ctx_, fs.spirv);
  VkPipelineColorBlendAttachmentState write{};
  write.colorWriteMask = 0xf;
  pipeline_ = make_fullscreen_pipeline(ctx_, layout_.get(), render_pass_.get(), vm.get(), fm.get(),
                                       std::vector<VkPipelineColorBlendAttachmentState>(outputs_.size(), write));
  quad_share_ = quad_share;
  scaled_ = scaled;
}

void TaaPass::setup(const TargetSet& t) {
  // Whole 2x2 quads cover an image of even width and height exactly (passes/taa.frag, TAA_QUAD_SHARE).
  // Below the output resolution neighbouring pixels read other render texels than their offsets say:
  // no sharing. The resolve is compiled for the one case (TAA_RENDER_SCALED): llvmpipe runs both sides
  // of a branch, so a run-time test of the scale would cost the path not taken.
  const bool scaled = int(t.image("color").width()) != t.width() || int(t.image("color").height()) != t.height();
  const bool quad = allow_quad_share_ && !scaled && ctx_.fragment_quad_operations() && t.width() % 2 == 0 &&
                    t.height() % 2 == 0;
  if (!pipeline_.get() || quad != quad_share_ || scaled != scaled_) build_pipeline(quad, scaled);
  for (int slot = 0; slot < 2; ++slot) {
    VkDescriptorSet set = sets_[slot].set;
    auto sampled = [&](uint32_t binding, const Image2D& img) {
      write_image_descriptor(ctx_, set, binding, img.view(), sampler_.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    };
    // A binding the resolve does not use points at the history (never accessed).
    const Image2D& unused = t.slot("taa.history", 1 - slot);
    sampled(kColor, t.image("color"));
    sampled(kMotion, uses_.motion ? t.image("motion") : unused);
    sampled(kGlint, uses_.glint ? t.image("glint") : unused);
    sampled(kHistoryIn, t.slot("taa.history", 1 - slot));
    for (uint32_t b : {kStateIn, kState2In, kHistory2In}) sampled(b, unused);
    std::vector<VkImageView> views = {t.image("taa.color").view(), t.slot("taa.history", slot).view()};
    for (const auto& [name, binding] : kept_targets(uses_)) {
      sampled(binding, t.slot(name, 1 - slot));
      views.push_back(t.slot(name, slot).view());
    }
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
  // This frame's jitter (TAA renders one sample a pixel; in render pixels, given to the resolve in
  // output pixels) and that of the frame the history holds.
  const Image2D& color = t.image("color");
  const glm::vec2 scale(float(color.width()) / float(t.width()), float(color.height()) / float(t.height()));
  const glm::vec2 jitter =
      (in.samples.empty() ? glm::vec2(0.0f) : glm::vec2(in.samples[0].jitter_weight)) / scale;
  const bool history = t.history_valid("taa.history");
  const glm::vec2 prev = history ? prev_jitter_ : jitter;
  prev_jitter_ = jitter;
  TaaPush p{float(t.width()), float(t.height()), history ? 1.0f : 0.0f, float(in.frame),
            jitter.x, jitter.y, prev.x, prev.y,
            float(color.width()), float(color.height()), scale.x, scale.y, {}};
  for (size_t i = 0; i < s_.values.size(); ++i) p.values[i] = float(s_.values[i]);
  const int slot = t.current_slot("taa.history");
  record_fullscreen_draw(cmd, {render_pass_.get(), framebuffers_[slot].get(),
                               {{0, 0}, {uint32_t(t.width()), uint32_t(t.height())}}, pipeline_.get(), layout_.get(),
                               sets_[slot].set, &p, sizeof p});
}

}  // namespace glintlab::core

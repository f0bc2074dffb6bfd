#include "core/render/taa_pass.h"

#include "core/vk/shader_compiler.h"

namespace glintlab::core {

namespace {
constexpr VkFormat kFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

struct TaaPush {
  float width, height, alpha, gamma;
  float history_valid, disocclusion_tolerance, pad0, pad1;
};
static_assert(sizeof(TaaPush) == 32, "TaaPush must match taa.comp");

enum Binding : uint32_t { kColor = 0, kMotion, kHistoryIn, kLumaIn, kOut, kHistoryOut, kLumaOut };

// The workgroup: a row of 64 pixels. Measured on llvmpipe (bench, TAA at 640x360, 30 frames, three
// interleaved runs): 8x8 17.1-18.6 ms, 16x4 13.1-15.6, 32x2 14.1-16.8, 64x1 12.3-14.0. The resolve has
// no shared memory, so the shape changes nothing but speed.
constexpr uint32_t kGroupX = 64, kGroupY = 1;
}  // namespace

std::vector<std::string> TaaPass::defines(const TaaSettings& s) {
  return {"TAA_CLAMP=" + std::to_string(int(s.clamp)),
          "TAA_SPACE=" + std::to_string(int(s.space)),
          "TAA_FILTER=" + std::to_string(int(s.history_filter)),
          std::string("TAA_DERING=") + (s.dering ? "1" : "0"),
          "TAA_VELOCITY=" + std::to_string(int(s.velocity)),
          "TAA_FEEDBACK=" + std::to_string(int(s.feedback)),
          "TAA_HDR=" + std::to_string(int(s.hdr)),
          std::string("TAA_ANTI_FLICKER=") + (s.anti_flicker ? "1" : "0"),
          "TAA_GROUP_X=" + std::to_string(kGroupX), "TAA_GROUP_Y=" + std::to_string(kGroupY)};
}

TaaPass::TaaPass(const VkContext& ctx, TaaSettings settings) : ctx_(ctx), s_(settings) {
  if (!(s_.alpha > 0.0 && s_.alpha <= 1.0)) throw std::invalid_argument("taa: alpha must be in (0, 1]");
  std::vector<VkDescriptorSetLayoutBinding> b;
  for (uint32_t i = kColor; i <= kLumaIn; ++i)
    b.push_back({i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
  for (uint32_t i = kOut; i <= kLumaOut; ++i)
    b.push_back({i, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
  set_layout_ = make_set_layout(ctx, b);
  layout_ = make_pipeline_layout(ctx, set_layout_.get(), sizeof(TaaPush), VK_SHADER_STAGE_COMPUTE_BIT);
  CompiledShader cs = default_shader_compiler().compile("passes/taa.comp", ShaderStage::Compute, defines(s_));
  ShaderModule m = make_shader_module(ctx, cs.spirv);
  pipeline_ = make_compute_pipeline(ctx, layout_.get(), m.get());
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
  io.keep("taa.history", kFormat, TargetUse::Storage);
  io.write("taa.color", kFormat, TargetUse::Storage);
  if (s_.anti_flicker) {
    io.read_previous("taa.luma");
    io.keep("taa.luma", kFormat, TargetUse::Storage);
  }
}

void TaaPass::setup(const TargetSet& t) {
  for (int slot = 0; slot < 2; ++slot) {
    VkDescriptorSet set = sets_[slot].set;
    auto sampled = [&](uint32_t binding, const Image2D& img) {
      write_image_descriptor(ctx_, set, binding, img.view(), sampler_.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    };
    auto storage = [&](uint32_t binding, const Image2D& img) {
      VkDescriptorImageInfo ii{VK_NULL_HANDLE, img.view(), VK_IMAGE_LAYOUT_GENERAL};
      VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      w.dstSet = set;
      w.dstBinding = binding;
      w.descriptorCount = 1;
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      w.pImageInfo = &ii;
      vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
    };
    sampled(kColor, t.image("color"));
    sampled(kMotion, t.image("motion"));
    sampled(kHistoryIn, t.slot("taa.history", 1 - slot));
    storage(kOut, t.image("taa.color"));
    storage(kHistoryOut, t.slot("taa.history", slot));
    // Without anti_flicker the luma bindings are unused; they point at the history (never accessed).
    sampled(kLumaIn, s_.anti_flicker ? t.slot("taa.luma", 1 - slot) : t.slot("taa.history", 1 - slot));
    storage(kLumaOut, s_.anti_flicker ? t.slot("taa.luma", slot) : t.slot("taa.history", slot));
  }
}

void TaaPass::record(VkCommandBuffer cmd, const FrameInputs&, const TargetSet& t) {
  TaaPush p{float(t.width()), float(t.height()), float(s_.alpha), float(s_.gamma),
            t.history_valid("taa.history") ? 1.0f : 0.0f, float(s_.disocclusion_tolerance), 0.0f, 0.0f};
  const int slot = t.current_slot("taa.history");
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &sets_[slot].set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof p, &p);
  vkCmdDispatch(cmd, (uint32_t(t.width()) + kGroupX - 1) / kGroupX, (uint32_t(t.height()) + kGroupY - 1) / kGroupY, 1);
}

}  // namespace glintlab::core

#include "core/render/surface_pass.h"

#include "core/render/chunk_culling.h"
#include "core/material/glint_table.h"
#include "core/scene/mesh.h"
#include "core/vk/shader_compiler.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <iterator>

namespace glintlab::core {

namespace {
uint32_t float_bits(float x) {
  uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
}  // namespace

namespace {

constexpr VkFormat kMotionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kGlintFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;  // one opaque sample: depth decides alone
// Accumulated samples: depth, and a stencil that lets one fragment per pixel
// through the EQUAL shading draw (see Draw).
constexpr VkFormat kDepthStencilFormat = VK_FORMAT_D32_SFLOAT_S8_UINT;

VkPipelineShaderStageCreateInfo stage_info(VkShaderStageFlagBits stage, VkShaderModule m) {
  VkPipelineShaderStageCreateInfo s{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  s.stage = stage;
  s.module = m;
  s.pName = "main";
  return s;
}

// The three draws of one sample. Accumulating samples by additive blending is
// only correct if each pixel receives exactly one fragment per sample, so the
// surface is first drawn depth-only, then shaded with depth test EQUAL (only
// the nearest depth survives, whatever the draw order), then the sky fills
// what is still at the far plane. Fragments of different triangles can tie at
// exactly the nearest depth (coincident surfaces; at a fold seen edge-on, two
// triangles round to the same depth): the shading draw and the sky also test
// the stencil EQUAL 0 and increment it, so the first of them is added and the
// rest are not. With one sample per frame the surface is one opaque draw
// (depth test LESS: the first of equal fragments stays) and the sky writes,
// not adds, its colour.
enum class Draw { DepthPrepass, Shade, Sky, ShadeOpaque, SkyOpaque };

Pipeline make_graphics_pipeline(const VkContext& ctx, VkPipelineLayout layout, VkRenderPass rp, VkShaderModule vs,
                                VkShaderModule fs, Draw draw, int color_attachments) {
  const bool sky = draw == Draw::Sky || draw == Draw::SkyOpaque;
  const bool with_vertices = !sky;
  VkPipelineShaderStageCreateInfo stages[] = {stage_info(VK_SHADER_STAGE_VERTEX_BIT, vs),
                                              stage_info(VK_SHADER_STAGE_FRAGMENT_BIT, fs)};
  VkVertexInputBindingDescription binding{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription attrs[] = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(Vertex, position))},
      {1, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(Vertex, normal))},
      {2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, uint32_t(offsetof(Vertex, tangent))},
      {3, 0, VK_FORMAT_R32G32_SFLOAT, uint32_t(offsetof(Vertex, uv))}};
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  if (with_vertices) {
    vi.vertexBindingDescriptionCount = 1;
    vi.pVertexBindingDescriptions = &binding;
    vi.vertexAttributeDescriptionCount = 4;
    vi.pVertexAttributeDescriptions = attrs;
  }
  const FixedFunctionState fixed;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = VK_TRUE;
  const bool writes_depth = draw == Draw::DepthPrepass || draw == Draw::ShadeOpaque;
  ds.depthWriteEnable = writes_depth ? VK_TRUE : VK_FALSE;
  ds.depthCompareOp = writes_depth         ? VK_COMPARE_OP_LESS
                      : draw == Draw::Shade ? VK_COMPARE_OP_EQUAL
                                            : VK_COMPARE_OP_LESS_OR_EQUAL;
  if (draw == Draw::Shade || draw == Draw::Sky) {  // accumulating: one fragment per pixel and sample
    ds.stencilTestEnable = VK_TRUE;
    ds.front.failOp = VK_STENCIL_OP_KEEP;
    ds.front.passOp = VK_STENCIL_OP_INCREMENT_AND_CLAMP;
    ds.front.depthFailOp = VK_STENCIL_OP_KEEP;
    ds.front.compareOp = VK_COMPARE_OP_EQUAL;
    ds.front.compareMask = 0xff;
    ds.front.writeMask = 0xff;
    ds.front.reference = 0;
    ds.back = ds.front;
  }
  VkPipelineColorBlendAttachmentState blend[3] = {};
  // Accumulate weighted samples; one opaque sample (and its sky) overwrites what a farther fragment wrote.
  blend[0].blendEnable = draw == Draw::Shade || draw == Draw::Sky ? VK_TRUE : VK_FALSE;
  blend[0].srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
  blend[0].dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
  blend[0].colorBlendOp = VK_BLEND_OP_ADD;
  blend[0].srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend[0].dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend[0].alphaBlendOp = VK_BLEND_OP_ADD;
  blend[0].colorWriteMask = draw == Draw::DepthPrepass ? 0 : 0xf;
  blend[1].blendEnable = VK_FALSE;  // motion: the last sample's value
  blend[1].colorWriteMask = draw == Draw::DepthPrepass ? 0 : 0xf;
  blend[2] = blend[0];  // the glint layer accumulates as the colour does
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = uint32_t(color_attachments);
  cb.pAttachments = blend;
  VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  ci.stageCount = draw == Draw::DepthPrepass ? 1 : 2;  // depth only: no fragment shader
  ci.pStages = stages;
  ci.pVertexInputState = &vi;
  fixed.apply(ci);
  ci.pDepthStencilState = &ds;
  ci.pColorBlendState = &cb;
  return create_graphics_pipeline(ctx, ci, layout, rp);
}

// Colour (and motion) attachments are loaded and kept: samples accumulate
// across one render-pass instance per sample; the pass clears them itself in
// the first instance. The frame graph puts every attachment in its attachment
// layout before the pass and expects it there after.
RenderPass make_render_pass(const VkContext& ctx, VkFormat color_format, VkFormat depth_format, bool motion,
                            bool glint) {
  std::vector<VkAttachmentDescription> att;
  att.push_back(kept_attachment(color_format, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_LOAD));
  if (motion)
    att.push_back(kept_attachment(kMotionFormat, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_LOAD));
  if (glint)
    att.push_back(kept_attachment(kGlintFormat, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_LOAD));
  VkAttachmentDescription depth =
      kept_attachment(depth_format, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_CLEAR);
  if (aspects_of(depth_format) & VK_IMAGE_ASPECT_STENCIL_BIT) depth.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  att.push_back(depth);
  VkAttachmentReference color_refs[3] = {{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL},
                                         {1, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL},
                                         {2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL}};
  VkAttachmentReference depth_ref{uint32_t(att.size() - 1), VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = uint32_t(att.size() - 1);
  sub.pColorAttachments = color_refs;
  sub.pDepthStencilAttachment = &depth_ref;
  // Orders this sample's blending and depth clear after the previous sample's
  // writes (the instances follow each other in one command buffer).
  VkSubpassDependency dep{};
  dep.srcSubpass = VK_SUBPASS_EXTERNAL;
  dep.dstSubpass = 0;
  dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                     VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  return create_render_pass(ctx, att, sub, dep);
}

}  // namespace

SurfacePass::SurfacePass(const VkContext& ctx, const SceneGpu& scene, SurfacePassOptions options)
    : ctx_(ctx), scene_(scene), opt_(std::move(options)) {
  if (opt_.color_format != VK_FORMAT_R32G32B32A32_SFLOAT && opt_.color_format != VK_FORMAT_R16G16B16A16_SFLOAT)
    throw VulkanError("surface pass: the colour target must be RGBA32F or RGBA16F");
  if (!ctx.format_supports(opt_.color_format, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
    throw VulkanError(ctx.info().name + " cannot blend into the colour target's format, which sample accumulation needs");
  if (opt_.supersample < 1 || opt_.supersample > 256)
    throw VulkanError("surface pass: supersample must be in 1..256");
  if (opt_.supersample > 1 && (opt_.motion || opt_.color_format != VK_FORMAT_R32G32B32A32_SFLOAT))
    throw VulkanError("surface pass: supersample needs an RGBA32F colour target and no motion vectors");
  if (opt_.halves && opt_.supersample < 2)
    throw VulkanError("surface pass: halves need supersample >= 2 (the halves split each pixel's block)");
  if (opt_.motion && !ctx.independent_blend())
    throw VulkanError(ctx.info().name + " lacks the independentBlend feature that motion vectors beside accumulated "
                      "colour need");
  if (opt_.glint && !opt_.motion)
    throw VulkanError("surface pass: the glint layer is written beside motion vectors only (option motion)");
  // Several samples without motion vectors, not supersampled: each sample is one opaque draw into the
  // pass's own image, which a blended full-screen draw adds to the colour target (see the header).
  sum_opaque_ = !opt_.single_sample && opt_.supersample == 1 && !opt_.motion &&
                opt_.color_format == VK_FORMAT_R32G32B32A32_SFLOAT;
  opaque_ = opt_.single_sample || sum_opaque_;
  depth_format_ = opaque_ ? kDepthFormat : kDepthStencilFormat;
  if (!ctx.format_supports(depth_format_, VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
    throw VulkanError(ctx.info().name + " cannot render depth to " +
                      (opaque_ ? "D32_SFLOAT" : "D32_SFLOAT_S8_UINT (depth and the stencil blended samples need)"));
  render_pass_ = make_render_pass(ctx, opt_.color_format, depth_format_, opt_.motion, opt_.glint);
  const int attachments = color_attachments();

  std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  if (opt_.program.glint_table_model)  // the glint model's data table, read-only (glint/query.glsl)
    bindings.push_back({3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
  set_layout_ = make_set_layout(ctx, bindings);
  layout_ = make_pipeline_layout(ctx, set_layout_.get(), sizeof(SamplePush),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);

  ShaderCompiler& sc = default_shader_compiler();
  std::vector<std::string> defines = opt_.program.defines;
  defines.push_back(std::string("SURFACE_MOTION=") + (opt_.motion ? "1" : "0"));
  defines.push_back(std::string("SURFACE_GLINT=") + (opt_.glint ? "1" : "0"));
  defines.push_back(std::string("COLOR_HALF=") + (opt_.color_format == VK_FORMAT_R16G16B16A16_SFLOAT ? "1" : "0"));
  if (opt_.footprint_scale != 1.0f) {  // as a float's bits: the shader multiplies by exactly this value
    char text[64];
    std::snprintf(text, sizeof text, "SURFACE_FOOTPRINT_SCALE=uintBitsToFloat(%uu)", float_bits(opt_.footprint_scale));
    defines.push_back(text);
  }
  CompiledShader vs = sc.compile("passes/surface.vert", ShaderStage::Vertex, defines);
  vertex_module_ = make_shader_module(ctx, vs.spirv);
  fragment_defines_ = defines;
  fragment_hash_ = sc.source_hash(opt_.program.fragment, ShaderStage::Fragment, defines);
  depth_pipeline_ = make_graphics_pipeline(ctx, layout_.get(), render_pass_.get(), vertex_module_.get(),
                                           VK_NULL_HANDLE, Draw::DepthPrepass, attachments);
  // With the frame's lighting as constants, the shading pipeline waits for the first frame's values.
  if (!opt_.program.frame_lighting_constants) build_surface_pipeline(defines);
  if (opt_.sky) {
    std::vector<std::string> sky_defines = {std::string("SURFACE_MOTION=") + (opt_.motion ? "1" : "0"),
                                            std::string("SURFACE_GLINT=") + (opt_.glint ? "1" : "0"),
                                            std::string("SKY_JITTERED=") + (opt_.sky_jittered ? "1" : "0")};
    CompiledShader svs = sc.compile("passes/sky.vert", ShaderStage::Vertex, sky_defines);
    CompiledShader sfs = sc.compile("passes/sky.frag", ShaderStage::Fragment, sky_defines);
    ShaderModule svm = make_shader_module(ctx, svs.spirv), sfm = make_shader_module(ctx, sfs.spirv);
    sky_pipeline_ = make_graphics_pipeline(ctx, layout_.get(), render_pass_.get(), svm.get(), sfm.get(),
                                           opaque_ ? Draw::SkyOpaque : Draw::Sky, attachments);
  }

  frame_ubo_ = Buffer(ctx, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  const size_t mat_bytes = std::max<size_t>(opt_.program.block.size(), 16);
  material_ubo_ = Buffer(ctx, mat_bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  std::memset(material_ubo_.mapped(), 0, mat_bytes);
  if (!opt_.program.block.empty()) material_ubo_.upload(opt_.program.block.data(), opt_.program.block.size());
  descriptors_ = make_descriptor_set(ctx, set_layout_.get(), bindings);
  write_buffer_descriptor(ctx, descriptors_.set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_ubo_.handle(),
                          sizeof(FrameUniforms));
  write_buffer_descriptor(ctx, descriptors_.set, 1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, material_ubo_.handle(),
                          mat_bytes);
  write_image_descriptor(ctx, descriptors_.set, 2, scene.env_map().view(), scene.env_sampler(),
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  if (opt_.program.glint_table_model) {
    auto table = glint_table(ctx, *opt_.program.glint_table_model);
    const size_t bytes = table->size() * sizeof(float);
    glint_table_ = Buffer(ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    glint_table_.upload(table->data(), bytes);
    write_buffer_descriptor(ctx, descriptors_.set, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, glint_table_.handle(), bytes);
  }

  if (opt_.supersample > 1 || sum_opaque_) {
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    VkSampler smp;
    vk_check(vkCreateSampler(ctx.device(), &si, nullptr, &smp), "vkCreateSampler");
    resolve_sampler_ = Sampler(ctx.device(), smp);
  }
  if (opt_.supersample > 1) {  // the box filter: a compute pass
    std::vector<VkDescriptorSetLayoutBinding> db = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
    for (uint32_t b = 2; opt_.halves && b < 4; ++b)
      db.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    resolve_set_layout_ = make_set_layout(ctx, db);
    resolve_layout_ = make_pipeline_layout(ctx, resolve_set_layout_.get(), 16, VK_SHADER_STAGE_COMPUTE_BIT);
    CompiledShader cs = sc.compile("passes/downsample.comp", ShaderStage::Compute,
                                   {std::string("HALVES=") + (opt_.halves ? "1" : "0")});
    ShaderModule m = make_shader_module(ctx, cs.spirv);
    resolve_pipeline_ = make_compute_pipeline(ctx, resolve_layout_.get(), m.get());
    resolve_set_ = make_descriptor_set(ctx, resolve_set_layout_.get(), db);
  }
  // The sum: a full-screen draw per sample, blending; on llvmpipe several times cheaper than a compute add
  // (imageLoad + imageStore): `glintlab_bench`, "floor, as one sample of SSAA" minus "floor"
  // (tests/bench/README.md).
  if (sum_opaque_) {
    std::vector<VkDescriptorSetLayoutBinding> ab = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    resolve_set_layout_ = make_set_layout(ctx, ab);
    resolve_layout_ = make_pipeline_layout(ctx, resolve_set_layout_.get(), 0, VK_SHADER_STAGE_FRAGMENT_BIT);
    add_render_pass_ = make_color_render_pass(ctx, {opt_.color_format}, VK_ATTACHMENT_LOAD_OP_LOAD);
    CompiledShader avs = sc.compile("passes/fullscreen.vert", ShaderStage::Vertex);
    CompiledShader afs = sc.compile("passes/add_sample.frag", ShaderStage::Fragment);
    ShaderModule avm = make_shader_module(ctx, avs.spirv), afm = make_shader_module(ctx, afs.spirv);
    for (int add = 0; add < 2; ++add) {  // the first sample is written, the others added (ONE + ONE)
      VkPipelineColorBlendAttachmentState blend{};
      blend.blendEnable = add ? VK_TRUE : VK_FALSE;
      blend.srcColorBlendFactor = blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
      blend.srcAlphaBlendFactor = blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      blend.colorBlendOp = blend.alphaBlendOp = VK_BLEND_OP_ADD;
      blend.colorWriteMask = 0xf;
      add_pipeline_[add] =
          make_fullscreen_pipeline(ctx, resolve_layout_.get(), add_render_pass_.get(), avm.get(), afm.get(), {blend});
    }
    resolve_set_ = make_descriptor_set(ctx, resolve_set_layout_.get(), ab);
  }
}

void SurfacePass::declare(PassIO& io) const {
  const int w = opt_.width, h = opt_.height;  // 0: the graph's
  if (opt_.supersample > 1 || sum_opaque_) {  // the resolve writes the colour target; the rest is the pass's own
    io.write(opt_.color_target, opt_.color_format, sum_opaque_ ? TargetUse::ColorAttachment : TargetUse::Storage, true, w, h);
    for (int k = 0; opt_.halves && k < 2; ++k) io.write(opt_.half_targets[k], opt_.color_format, TargetUse::Storage, true, w, h);
    return;
  }
  // The pass clears colour and motion itself, so their old contents are dropped.
  io.write(opt_.color_target, opt_.color_format, TargetUse::ColorAttachment, true, w, h);
  if (opt_.motion) io.write(opt_.motion_target, kMotionFormat, TargetUse::ColorAttachment, true, w, h);
  if (opt_.glint) io.write(opt_.glint_target, kGlintFormat, TargetUse::ColorAttachment, true, w, h);
  io.write(opt_.depth_target, depth_format_, TargetUse::DepthAttachment, true, w, h);
}

void SurfacePass::setup(const TargetSet& t) {
  width_ = opt_.width > 0 ? opt_.width : t.width();
  height_ = opt_.height > 0 ? opt_.height : t.height();
  const int f = opt_.supersample;
  std::vector<VkImageView> views;
  if (f > 1 || sum_opaque_) {
    const uint32_t hw = uint32_t(width_ * f), hh = uint32_t(height_ * f);
    hi_color_ = Image2D(ctx_, hw, hh, opt_.color_format,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    hi_depth_ = Image2D(ctx_, hw, hh, depth_format_, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, 1,
                        aspects_of(depth_format_));
    views = {hi_color_.view(), hi_depth_.view()};
    write_image_descriptor(ctx_, resolve_set_.set, 0, hi_color_.view(), resolve_sampler_.get(),
                           VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    if (sum_opaque_) {  // the add pass draws into the colour target
      VkImageView target = t.image(opt_.color_target).view();
      VkFramebufferCreateInfo ai{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
      ai.renderPass = add_render_pass_.get();
      ai.attachmentCount = 1;
      ai.pAttachments = &target;
      ai.width = uint32_t(width_);
      ai.height = uint32_t(height_);
      ai.layers = 1;
      VkFramebuffer afb;
      vk_check(vkCreateFramebuffer(ctx_.device(), &ai, nullptr, &afb), "vkCreateFramebuffer");
      add_framebuffer_ = Framebuffer(ctx_.device(), afb);
    } else {  // the box filter writes the colour target (and the halves) as storage images
      std::vector<std::string> outputs = {opt_.color_target};
      if (opt_.halves) outputs.insert(outputs.end(), {opt_.half_targets[0], opt_.half_targets[1]});
      for (size_t b = 0; b < outputs.size(); ++b) {
        VkDescriptorImageInfo ii{VK_NULL_HANDLE, t.image(outputs[b]).view(), VK_IMAGE_LAYOUT_GENERAL};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = resolve_set_.set;
        w.dstBinding = uint32_t(1 + b);
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        w.pImageInfo = &ii;
        vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
      }
    }
  } else {
    views.push_back(t.image(opt_.color_target).view());
    if (opt_.motion) views.push_back(t.image(opt_.motion_target).view());
    if (opt_.glint) views.push_back(t.image(opt_.glint_target).view());
    views.push_back(t.image(opt_.depth_target).view());
  }
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = render_pass_.get();
  fi.attachmentCount = uint32_t(views.size());
  fi.pAttachments = views.data();
  fi.width = uint32_t(width_ * f);
  fi.height = uint32_t(height_ * f);
  fi.layers = 1;
  VkFramebuffer fb;
  vk_check(vkCreateFramebuffer(ctx_.device(), &fi, nullptr, &fb), "vkCreateFramebuffer");
  framebuffer_ = Framebuffer(ctx_.device(), fb);
}

void SurfacePass::record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet&) {
  if (in.samples.empty()) throw VulkanError("surface pass \"" + opt_.name + "\": a frame needs at least one sample");
  if (opt_.single_sample && in.samples.size() != 1)
    throw VulkanError("surface pass \"" + opt_.name + "\": single_sample, but the frame has " +
                      std::to_string(in.samples.size()) + " samples");
  if (opt_.program.frame_lighting_constants) {
    // The lighting fields in frame.glsl's order (FRAME_LIGHTING_WORDS); a frame
    // that brings other values than the last gets a pipeline compiled for them
    // (no earlier frame's commands are pending: the graph waits for each frame).
    static_assert(sizeof(glm::vec4) == 16 && sizeof(FrameUniforms::env_sh) == 9 * 16);
    std::array<glm::vec4, 11> lighting;
    lighting[0] = in.uniforms.sun_dir;
    lighting[1] = in.uniforms.sun_L;
    std::copy(std::begin(in.uniforms.env_sh), std::end(in.uniforms.env_sh), lighting.begin() + 2);
    if (surface_pipeline_.get() == VK_NULL_HANDLE ||
        std::memcmp(lighting.data(), built_lighting_.data(), sizeof lighting) != 0) {  // bitwise, NaN too
      std::vector<std::string> defines = fragment_defines_;
      defines.push_back(words_define("FRAME_LIGHTING_WORDS", lighting.data(), sizeof lighting));
      build_surface_pipeline(defines);
      built_lighting_ = lighting;
    }
  }
  frame_ubo_.upload(&in.uniforms, sizeof in.uniforms);
  const int attachments = color_attachments();
  VkClearValue clears[4] = {};
  clears[attachments].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rb.renderPass = render_pass_.get();
  rb.framebuffer = framebuffer_.get();
  const int f = opt_.supersample;
  const uint32_t rw = uint32_t(width_ * f), rh = uint32_t(height_ * f);
  rb.renderArea = {{0, 0}, {rw, rh}};
  rb.clearValueCount = uint32_t(attachments + 1);
  rb.pClearValues = clears;
  VkViewport viewport{0, 0, float(rw), float(rh), 0, 1};
  VkRect2D scissor{{0, 0}, {rw, rh}};
  if (f > 1 || sum_opaque_) {
    // The pass's own images: after last frame's box filter read the colour and
    // its depth tests used the depth, their old contents are dropped.
    transition(cmd, hi_color_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
               !hi_written_ ? VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT
               : sum_opaque_ ? VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT
                             : VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
               0,
               VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
               VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    transition(cmd, hi_depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
               hi_written_ ? VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT : VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
               VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
               VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    hi_written_ = true;
  }
  // One opaque sample with the sky on writes every pixel once: the nearest
  // surface, or the sky wherever depth is still the cleared far plane (it tests
  // LESS_OR_EQUAL at z = 1). Clearing colour and motion first would only cost
  // time (a quarter of the bench's "floor" on lavapipe, tests/bench/README.md);
  // accumulated samples, and frames without sky, start from the clear (each
  // opaque sample of a sum its own).
  const bool clear_colour = !(opaque_ && opt_.sky);
  triangles_drawn_ = triangles_all_ = 0;
  VkDeviceSize zero_offset = 0;
  VkBuffer vb = scene_.vertices().handle();
  for (size_t i = 0; i < in.samples.size(); ++i) {
    if (sum_opaque_ && i > 0)  // the add pass has read the last sample: this one overwrites it
      transition(cmd, hi_color_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                 VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                 VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
    if ((i == 0 || sum_opaque_) && clear_colour) {  // the accumulation starts from zero; motion from "no surface"
      VkClearAttachment ca[3] = {};
      for (int a = 0; a < attachments; ++a) {
        ca[a].aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
        ca[a].colorAttachment = uint32_t(a);
      }
      ca[1].clearValue.color = {{0.0f, 0.0f, 0.0f, -1.0f}};  // motion (the glint layer, attachment 2, is 0)
      VkClearRect rect{scissor, 0, 1};
      vkCmdClearAttachments(cmd, uint32_t(attachments), ca, 1, &rect);
    }
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &descriptors_.set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                       sizeof(SamplePush), &in.samples[i]);
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero_offset);
    vkCmdBindIndexBuffer(cmd, scene_.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
    const std::vector<DrawRange> ranges =
        opt_.cull ? visible_ranges(scene_.chunks(), in.samples[i].view_proj * in.uniforms.model)
                  : std::vector<DrawRange>{{0, scene_.index_count()}};
    auto draw_mesh = [&] {
      for (const DrawRange& r : ranges) vkCmdDrawIndexed(cmd, r.index_count, 1, r.first_index, 0, 0);
    };
    for (const DrawRange& r : ranges) triangles_drawn_ += r.index_count / 3;
    triangles_all_ += scene_.index_count() / 3;
    if (!opaque_) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depth_pipeline_.get());
      draw_mesh();
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, surface_pipeline_.get());
    draw_mesh();
    if (opt_.sky) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sky_pipeline_.get());
      vkCmdDraw(cmd, 3, 1, 0, 0);
    }
    vkCmdEndRenderPass(cmd);
    if (sum_opaque_) add_sample(cmd, i > 0, scissor);
  }
  if (f > 1) resolve(cmd);
}

// Adds (or, the first, writes) the sample in the pass's own image to the
// colour target: a full-screen draw with blending ONE + ONE, the same fp32
// additions the blended path makes.
void SurfacePass::add_sample(VkCommandBuffer cmd, bool add, const VkRect2D& scissor) {
  transition(cmd, hi_color_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
             VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
             VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
  record_fullscreen_draw(cmd, {add_render_pass_.get(), add_framebuffer_.get(), scissor, add_pipeline_[add ? 1 : 0].get(),
                               resolve_layout_.get(), resolve_set_.set});
}

// The box filter of the supersampled image into the colour target (which the
// graph put in GENERAL for us).
void SurfacePass::resolve(VkCommandBuffer cmd) {
  transition(cmd, hi_color_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
             VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
  const int32_t push[4] = {width_, height_, opt_.supersample, 0};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_pipeline_.get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_layout_.get(), 0, 1, &resolve_set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, resolve_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, push);
  vkCmdDispatch(cmd, (uint32_t(width_) + 7) / 8, (uint32_t(height_) + 7) / 8, 1);
}

void SurfacePass::build_surface_pipeline(const std::vector<std::string>& defines) {
  CompiledShader fs = default_shader_compiler().compile(opt_.program.fragment, ShaderStage::Fragment, defines);
  ShaderModule fsm = make_shader_module(ctx_, fs.spirv);
  surface_pipeline_ = make_graphics_pipeline(ctx_, layout_.get(), render_pass_.get(), vertex_module_.get(), fsm.get(),
                                             opaque_ ? Draw::ShadeOpaque : Draw::Shade, color_attachments());
}

// ---------------------------------------------------------------- SurfaceRenderer
SurfaceRenderer::SurfaceRenderer(const VkContext& ctx, const SceneGpu& scene, int width, int height,
                                 SurfacePassOptions options)
    : graph_(ctx, width, height) {
  std::vector<std::string> readback = {options.color_target};
  if (options.motion) readback.push_back(options.motion_target);
  if (options.glint) readback.push_back(options.glint_target);
  if (options.halves) readback.insert(readback.end(), {options.half_targets[0], options.half_targets[1]});
  pass_ = static_cast<SurfacePass*>(&graph_.add(std::make_unique<SurfacePass>(ctx, scene, std::move(options))));
  graph_.build(readback);
}

FrameResult SurfaceRenderer::render(const FrameUniforms& frame, const std::vector<SamplePush>& samples) {
  FrameInputs in;
  in.uniforms = frame;
  in.samples = samples;
  return graph_.execute(in);
}

}  // namespace glintlab::core

#include "core/render/surface_pass.h"

#include "core/scene/mesh.h"
#include "core/vk/shader_compiler.h"

#include <cstring>
#include <random>

namespace glintlab::core {

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

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
// the nearest fragment survives, whatever the draw order), then the sky fills
// what is still at the far plane.
enum class Draw { DepthPrepass, Shade, Sky };

Pipeline make_graphics_pipeline(const VkContext& ctx, VkPipelineLayout layout, VkRenderPass rp, VkShaderModule vs,
                                VkShaderModule fs, Draw draw, int w, int h) {
  const bool with_vertices = draw != Draw::Sky;
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
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkViewport viewport{0, 0, float(w), float(h), 0, 1};
  VkRect2D scissor{{0, 0}, {uint32_t(w), uint32_t(h)}};
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.pViewports = &viewport;
  vp.scissorCount = 1;
  vp.pScissors = &scissor;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;  // surfaces are seen from both sides (grazing, below the plane)
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = VK_TRUE;
  ds.depthWriteEnable = draw == Draw::DepthPrepass ? VK_TRUE : VK_FALSE;
  ds.depthCompareOp = draw == Draw::DepthPrepass ? VK_COMPARE_OP_LESS
                      : draw == Draw::Shade      ? VK_COMPARE_OP_EQUAL
                                                 : VK_COMPARE_OP_LESS_OR_EQUAL;
  VkPipelineColorBlendAttachmentState blend{};
  blend.blendEnable = draw == Draw::DepthPrepass ? VK_FALSE : VK_TRUE;
  blend.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.colorBlendOp = VK_BLEND_OP_ADD;
  blend.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.alphaBlendOp = VK_BLEND_OP_ADD;
  blend.colorWriteMask = draw == Draw::DepthPrepass ? 0 : 0xf;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = 1;
  cb.pAttachments = &blend;
  VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  ci.stageCount = draw == Draw::DepthPrepass ? 1 : 2;  // depth only: no fragment shader
  ci.pStages = stages;
  ci.pVertexInputState = &vi;
  ci.pInputAssemblyState = &ia;
  ci.pViewportState = &vp;
  ci.pRasterizationState = &rs;
  ci.pMultisampleState = &ms;
  ci.pDepthStencilState = &ds;
  ci.pColorBlendState = &cb;
  ci.layout = layout;
  ci.renderPass = rp;
  VkPipeline p;
  vk_check(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &p), "vkCreateGraphicsPipelines");
  return Pipeline(ctx.device(), p);
}

RenderPass make_render_pass(const VkContext& ctx) {
  VkAttachmentDescription att[2] = {};
  att[0].format = kColorFormat;
  att[0].samples = VK_SAMPLE_COUNT_1_BIT;
  att[0].loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // cleared once per frame, accumulated over samples
  att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[0].initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  att[0].finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  att[1].format = kDepthFormat;
  att[1].samples = VK_SAMPLE_COUNT_1_BIT;
  att[1].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[1].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  att[1].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[1].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &color_ref;
  sub.pDepthStencilAttachment = &depth_ref;
  // Orders this sample's blending and depth clear after the previous sample's
  // (and the colour clear) writes.
  VkSubpassDependency dep{};
  dep.srcSubpass = VK_SUBPASS_EXTERNAL;
  dep.dstSubpass = 0;
  dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                     VK_PIPELINE_STAGE_TRANSFER_BIT;
  dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                     VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                      VK_ACCESS_TRANSFER_WRITE_BIT;
  dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  VkRenderPassCreateInfo ci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  ci.attachmentCount = 2;
  ci.pAttachments = att;
  ci.subpassCount = 1;
  ci.pSubpasses = &sub;
  ci.dependencyCount = 1;
  ci.pDependencies = &dep;
  VkRenderPass rp;
  vk_check(vkCreateRenderPass(ctx.device(), &ci, nullptr, &rp), "vkCreateRenderPass");
  return RenderPass(ctx.device(), rp);
}

}  // namespace

// ---------------------------------------------------------------- SceneGpu
SceneGpu::SceneGpu(const VkContext& ctx, const Mesh& mesh, const EnvironmentTexture& env) {
  if (mesh.vertices.empty() || mesh.indices.empty()) throw VulkanError("SceneGpu: the mesh is empty");
  vertices_ = Buffer(ctx, mesh.vertices.size() * sizeof(Vertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  vertices_.upload(mesh.vertices.data(), mesh.vertices.size() * sizeof(Vertex));
  indices_ = Buffer(ctx, mesh.indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  indices_.upload(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  index_count_ = uint32_t(mesh.indices.size());

  if (env.width == 0 || env.height == 0 || env.mips_rgba.empty())
    throw VulkanError("SceneGpu: the environment texture is empty");
  env_map_ = Image2D(ctx, env.width, env.height, kColorFormat,
                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, uint32_t(env.mips_rgba.size()));
  upload_rgba32f_mips(ctx, env_map_, env.mips_rgba);
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = VK_FILTER_LINEAR;
  si.minFilter = VK_FILTER_LINEAR;
  si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  si.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;         // azimuth wraps
  si.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;  // poles clamp
  si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  si.maxLod = float(env.mips_rgba.size());
  VkSampler s;
  vk_check(vkCreateSampler(ctx.device(), &si, nullptr, &s), "vkCreateSampler");
  sampler_ = Sampler(ctx.device(), s);
}

// ---------------------------------------------------------------- SurfacePass
SurfacePass::SurfacePass(const VkContext& ctx, const SceneGpu& scene, int width, int height,
                         const SurfaceShader& shader, bool draw_sky)
    : ctx_(ctx), scene_(scene), width_(width), height_(height), draw_sky_(draw_sky) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw VulkanError("SurfacePass: resolution " + std::to_string(width) + "x" + std::to_string(height) +
                      " is outside 1..16384");
  if (!ctx.format_supports(kColorFormat, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
    throw VulkanError(ctx.info().name + " cannot blend into RGBA32F attachments, which sample accumulation needs");

  color_ = Image2D(ctx, uint32_t(width), uint32_t(height), kColorFormat,
                   VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                       VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
  depth_ = Image2D(ctx, uint32_t(width), uint32_t(height), kDepthFormat,
                   VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, 1, VK_IMAGE_ASPECT_DEPTH_BIT);
  render_pass_ = make_render_pass(ctx);
  VkImageView views[] = {color_.view(), depth_.view()};
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = render_pass_.get();
  fi.attachmentCount = 2;
  fi.pAttachments = views;
  fi.width = uint32_t(width);
  fi.height = uint32_t(height);
  fi.layers = 1;
  VkFramebuffer fb;
  vk_check(vkCreateFramebuffer(ctx.device(), &fi, nullptr, &fb), "vkCreateFramebuffer");
  framebuffer_ = Framebuffer(ctx.device(), fb);

  std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  set_layout_ = make_set_layout(ctx, bindings);
  layout_ = make_pipeline_layout(ctx, set_layout_.get(), sizeof(SamplePush),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);

  ShaderCompiler& sc = default_shader_compiler();
  CompiledShader vs = sc.compile("passes/surface.vert", ShaderStage::Vertex, shader.defines);
  CompiledShader fs = sc.compile(shader.fragment, ShaderStage::Fragment, shader.defines);
  fragment_hash_ = fs.source_hash;
  ShaderModule vsm = make_shader_module(ctx, vs.spirv), fsm = make_shader_module(ctx, fs.spirv);
  depth_pipeline_ = make_graphics_pipeline(ctx, layout_.get(), render_pass_.get(), vsm.get(), VK_NULL_HANDLE,
                                           Draw::DepthPrepass, width, height);
  surface_pipeline_ = make_graphics_pipeline(ctx, layout_.get(), render_pass_.get(), vsm.get(), fsm.get(),
                                             Draw::Shade, width, height);
  if (draw_sky_) {
    CompiledShader svs = sc.compile("passes/fullscreen.vert", ShaderStage::Vertex);
    CompiledShader sfs = sc.compile("passes/sky.frag", ShaderStage::Fragment);
    ShaderModule svm = make_shader_module(ctx, svs.spirv), sfm = make_shader_module(ctx, sfs.spirv);
    sky_pipeline_ = make_graphics_pipeline(ctx, layout_.get(), render_pass_.get(), svm.get(), sfm.get(), Draw::Sky,
                                           width, height);
  }

  frame_ubo_ = Buffer(ctx, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  size_t mat_bytes = std::max<size_t>(shader.material.size(), 16);
  material_ubo_ = Buffer(ctx, mat_bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  std::memset(material_ubo_.mapped(), 0, mat_bytes);
  if (!shader.material.empty()) material_ubo_.upload(shader.material.data(), shader.material.size());
  descriptors_ = make_descriptor_set(ctx, set_layout_.get(), bindings);
  write_buffer_descriptor(ctx, descriptors_.set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_ubo_.handle(),
                          sizeof(FrameUniforms));
  write_buffer_descriptor(ctx, descriptors_.set, 1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, material_ubo_.handle(),
                          mat_bytes);
  write_image_descriptor(ctx, descriptors_.set, 2, scene.env_map().view(), scene.env_sampler(),
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

  if (ctx.timestamps_supported()) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = 2;
    VkQueryPool qp;
    vk_check(vkCreateQueryPool(ctx.device(), &qi, nullptr, &qp), "vkCreateQueryPool");
    queries_ = QueryPool(ctx.device(), qp);
  }
}

FrameOutput SurfacePass::render(const FrameUniforms& frame, const std::vector<SamplePush>& samples,
                                const std::string& label) {
  if (samples.empty()) throw VulkanError("SurfacePass::render: no samples");
  frame_ubo_.upload(&frame, sizeof frame);
  ctx_.submit_and_wait([&](VkCommandBuffer cmd) {
    if (queries_.get()) {
      vkCmdResetQueryPool(cmd, queries_.get(), 0, 2);
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_.get(), 0);
    }
    transition(cmd, color_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkClearColorValue zero{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, color_.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &range);
    transition(cmd, color_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
               VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    VkClearValue clears[2] = {};
    clears[1].depthStencil = {1.0f, 0};
    VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rb.renderPass = render_pass_.get();
    rb.framebuffer = framebuffer_.get();
    rb.renderArea = {{0, 0}, {uint32_t(width_), uint32_t(height_)}};
    rb.clearValueCount = 2;
    rb.pClearValues = clears;
    VkDeviceSize zero_offset = 0;
    VkBuffer vb = scene_.vertices().handle();
    for (const SamplePush& s : samples) {
      vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &descriptors_.set, 0,
                              nullptr);
      vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                         sizeof(SamplePush), &s);
      vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero_offset);
      vkCmdBindIndexBuffer(cmd, scene_.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depth_pipeline_.get());
      vkCmdDrawIndexed(cmd, scene_.index_count(), 1, 0, 0, 0);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, surface_pipeline_.get());
      vkCmdDrawIndexed(cmd, scene_.index_count(), 1, 0, 0, 0);
      if (draw_sky_) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sky_pipeline_.get());
        vkCmdDraw(cmd, 3, 1, 0, 0);
      }
      vkCmdEndRenderPass(cmd);
    }
    if (queries_.get()) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(), 1);
    transition(cmd, color_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
               VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  });

  FrameOutput out;
  out.color = Image(width_, height_, 4);
  out.color.data = read_back(ctx_, color_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  PassTiming t{label, 0.0};
  if (queries_.get()) {
    uint64_t ts[2] = {0, 0};
    vk_check(vkGetQueryPoolResults(ctx_.device(), queries_.get(), 0, 2, sizeof ts, ts, sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
             "vkGetQueryPoolResults");
    uint32_t bits = ctx_.timestamp_valid_bits();
    uint64_t mask = bits >= 64 ? ~uint64_t(0) : ((uint64_t(1) << bits) - 1);
    uint64_t ticks = (ts[1] - ts[0]) & mask;
    t.gpu_ms = double(ticks) * ctx_.timestamp_period_ns() * 1e-6;
  }
  out.timings.push_back(t);
  return out;
}

std::vector<glm::vec2> stratified_offsets(int n, uint32_t seed) {
  std::vector<glm::vec2> out;
  if (n <= 0) return out;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  out.reserve(size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      out.emplace_back((float(i) + u(rng)) / float(n) - 0.5f, (float(j) + u(rng)) / float(n) - 0.5f);
  return out;
}

}  // namespace glintlab::core

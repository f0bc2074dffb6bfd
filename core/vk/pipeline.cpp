#include "core/vk/pipeline.h"

#include <map>

namespace glintlab::core {

ShaderModule make_shader_module(const VkContext& ctx, const std::vector<uint32_t>& spirv) {
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = spirv.size() * sizeof(uint32_t);
  ci.pCode = spirv.data();
  VkShaderModule m;
  vk_check(vkCreateShaderModule(ctx.device(), &ci, nullptr, &m), "vkCreateShaderModule");
  return ShaderModule(ctx.device(), m);
}

DescriptorSetLayout make_set_layout(const VkContext& ctx, const std::vector<VkDescriptorSetLayoutBinding>& bindings) {
  VkDescriptorSetLayoutCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  ci.bindingCount = uint32_t(bindings.size());
  ci.pBindings = bindings.data();
  VkDescriptorSetLayout l;
  vk_check(vkCreateDescriptorSetLayout(ctx.device(), &ci, nullptr, &l), "vkCreateDescriptorSetLayout");
  return DescriptorSetLayout(ctx.device(), l);
}

PipelineLayout make_pipeline_layout(const VkContext& ctx, VkDescriptorSetLayout set_layout,
                                    uint32_t push_constant_bytes, VkShaderStageFlags push_stages) {
  VkPushConstantRange range{push_stages, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  ci.setLayoutCount = 1;
  ci.pSetLayouts = &set_layout;
  ci.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
  ci.pPushConstantRanges = push_constant_bytes ? &range : nullptr;
  VkPipelineLayout l;
  vk_check(vkCreatePipelineLayout(ctx.device(), &ci, nullptr, &l), "vkCreatePipelineLayout");
  return PipelineLayout(ctx.device(), l);
}

Pipeline make_compute_pipeline(const VkContext& ctx, VkPipelineLayout layout, VkShaderModule module) {
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module;
  ci.stage.pName = "main";
  ci.layout = layout;
  VkPipeline p;
  vk_check(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &p), "vkCreateComputePipelines");
  return Pipeline(ctx.device(), p);
}

DescriptorSet make_descriptor_set(const VkContext& ctx, VkDescriptorSetLayout layout,
                                  const std::vector<VkDescriptorSetLayoutBinding>& bindings) {
  std::map<VkDescriptorType, uint32_t> counts;
  for (const auto& b : bindings) counts[b.descriptorType] += b.descriptorCount;
  std::vector<VkDescriptorPoolSize> sizes;
  for (auto [t, n] : counts) sizes.push_back({t, n});
  VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pci.maxSets = 1;
  pci.poolSizeCount = uint32_t(sizes.size());
  pci.pPoolSizes = sizes.data();
  VkDescriptorPool pool;
  vk_check(vkCreateDescriptorPool(ctx.device(), &pci, nullptr, &pool), "vkCreateDescriptorPool");
  DescriptorSet ds;
  ds.pool = DescriptorPool(ctx.device(), pool);
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &layout;
  vk_check(vkAllocateDescriptorSets(ctx.device(), &ai, &ds.set), "vkAllocateDescriptorSets");
  return ds;
}

void write_buffer_descriptor(const VkContext& ctx, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                             VkBuffer buffer, VkDeviceSize size) {
  VkDescriptorBufferInfo bi{buffer, 0, size};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pBufferInfo = &bi;
  vkUpdateDescriptorSets(ctx.device(), 1, &w, 0, nullptr);
}

void write_image_descriptor(const VkContext& ctx, VkDescriptorSet set, uint32_t binding, VkImageView view,
                            VkSampler sampler, VkImageLayout layout) {
  VkDescriptorImageInfo ii{sampler, view, layout};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  w.pImageInfo = &ii;
  vkUpdateDescriptorSets(ctx.device(), 1, &w, 0, nullptr);
}

FixedFunctionState::FixedFunctionState() {
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  vp.viewportCount = 1;
  vp.scissorCount = 1;
  dyn.dynamicStateCount = 2;
  dyn.pDynamicStates = dynamic;
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
}

void FixedFunctionState::apply(VkGraphicsPipelineCreateInfo& ci) const {
  ci.pInputAssemblyState = &ia;
  ci.pViewportState = &vp;
  ci.pRasterizationState = &rs;
  ci.pMultisampleState = &ms;
  ci.pDynamicState = &dyn;
}

Pipeline create_graphics_pipeline(const VkContext& ctx, VkGraphicsPipelineCreateInfo& ci, VkPipelineLayout layout,
                                  VkRenderPass rp) {
  ci.layout = layout;
  ci.renderPass = rp;
  VkPipeline p;
  vk_check(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &p), "vkCreateGraphicsPipelines");
  return Pipeline(ctx.device(), p);
}

Pipeline make_fullscreen_pipeline(const VkContext& ctx, VkPipelineLayout layout, VkRenderPass rp, VkShaderModule vs,
                                  VkShaderModule fs, const std::vector<VkPipelineColorBlendAttachmentState>& blends) {
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vs;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = fs;
  stages[1].pName = "main";
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  const FixedFunctionState fixed;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = uint32_t(blends.size());
  cb.pAttachments = blends.data();
  VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  ci.stageCount = 2;
  ci.pStages = stages;
  ci.pVertexInputState = &vi;
  fixed.apply(ci);
  ci.pColorBlendState = &cb;
  return create_graphics_pipeline(ctx, ci, layout, rp);
}

void record_fullscreen_draw(VkCommandBuffer cmd, const FullscreenDraw& d) {
  const VkViewport viewport{float(d.area.offset.x), float(d.area.offset.y), float(d.area.extent.width),
                            float(d.area.extent.height), 0, 1};
  VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rb.renderPass = d.render_pass;
  rb.framebuffer = d.framebuffer;
  rb.renderArea = d.area;
  vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &d.area);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, d.pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, d.layout, 0, 1, &d.set, 0, nullptr);
  if (d.push) vkCmdPushConstants(cmd, d.layout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, d.push_size, d.push);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRenderPass(cmd);
}

VkAttachmentDescription kept_attachment(VkFormat format, VkImageLayout layout, VkAttachmentLoadOp load) {
  VkAttachmentDescription a{};
  a.format = format;
  a.samples = VK_SAMPLE_COUNT_1_BIT;
  a.loadOp = load;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  a.initialLayout = a.finalLayout = layout;
  return a;
}

RenderPass create_render_pass(const VkContext& ctx, const std::vector<VkAttachmentDescription>& attachments,
                              const VkSubpassDescription& subpass, const VkSubpassDependency& dependency) {
  VkRenderPassCreateInfo ci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  ci.attachmentCount = uint32_t(attachments.size());
  ci.pAttachments = attachments.data();
  ci.subpassCount = 1;
  ci.pSubpasses = &subpass;
  ci.dependencyCount = 1;
  ci.pDependencies = &dependency;
  VkRenderPass rp;
  vk_check(vkCreateRenderPass(ctx.device(), &ci, nullptr, &rp), "vkCreateRenderPass");
  return RenderPass(ctx.device(), rp);
}

RenderPass make_color_render_pass(const VkContext& ctx, const std::vector<VkFormat>& formats, VkAttachmentLoadOp load) {
  std::vector<VkAttachmentDescription> att;
  std::vector<VkAttachmentReference> refs;
  for (VkFormat f : formats) {
    refs.push_back({uint32_t(att.size()), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
    att.push_back(kept_attachment(f, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, load));
  }
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = uint32_t(refs.size());
  sub.pColorAttachments = refs.data();
  VkSubpassDependency dep{};
  dep.srcSubpass = VK_SUBPASS_EXTERNAL;
  dep.dstSubpass = 0;
  dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  return create_render_pass(ctx, att, sub, dep);
}

}  // namespace glintlab::core

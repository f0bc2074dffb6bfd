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

}  // namespace glintlab::core

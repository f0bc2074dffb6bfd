// RAII owners of shader modules, descriptor/pipeline layouts and pipelines,
// plus builders for the two pipeline shapes the renderer uses.
#pragma once

#include "core/vk/handle.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/vk_context.h"

#include <string>
#include <vector>

namespace glintlab::core {

ShaderModule make_shader_module(const VkContext& ctx, const std::vector<uint32_t>& spirv);
DescriptorSetLayout make_set_layout(const VkContext& ctx, const std::vector<VkDescriptorSetLayoutBinding>& bindings);
PipelineLayout make_pipeline_layout(const VkContext& ctx, VkDescriptorSetLayout set_layout,
                                    uint32_t push_constant_bytes = 0,
                                    VkShaderStageFlags push_stages = VK_SHADER_STAGE_ALL);
Pipeline make_compute_pipeline(const VkContext& ctx, VkPipelineLayout layout, VkShaderModule module);

// Allocates one descriptor set from a pool sized for exactly these bindings.
struct DescriptorSet {
  DescriptorPool pool;
  VkDescriptorSet set = VK_NULL_HANDLE;
};
DescriptorSet make_descriptor_set(const VkContext& ctx, VkDescriptorSetLayout layout,
                                  const std::vector<VkDescriptorSetLayoutBinding>& bindings);
void write_buffer_descriptor(const VkContext& ctx, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                             VkBuffer buffer, VkDeviceSize size);
void write_image_descriptor(const VkContext& ctx, VkDescriptorSet set, uint32_t binding, VkImageView view,
                            VkSampler sampler, VkImageLayout layout);

}  // namespace glintlab::core

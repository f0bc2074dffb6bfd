// RAII owners of shader modules, descriptor/pipeline layouts and pipelines,
// plus builders for the pipeline shapes the renderer uses.
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

// The fixed-function state every draw of the renderer shares: triangle lists,
// one dynamic viewport and scissor, no culling (surfaces are seen from both
// sides: grazing, below the plane), one sample per pixel. It points into
// itself, so it is neither copied nor moved.
struct FixedFunctionState {
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  VkDynamicState dynamic[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dyn{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};

  FixedFunctionState();
  FixedFunctionState(const FixedFunctionState&) = delete;
  FixedFunctionState& operator=(const FixedFunctionState&) = delete;
  void apply(VkGraphicsPipelineCreateInfo& ci) const;  // sets the five state pointers
};

// vkCreateGraphicsPipelines for `ci` with this layout and render pass.
Pipeline create_graphics_pipeline(const VkContext& ctx, VkGraphicsPipelineCreateInfo& ci, VkPipelineLayout layout,
                                  VkRenderPass rp);

// A full-screen pass: one triangle from passes/fullscreen.vert (no vertex
// input, no depth), a fragment shader and one blend state per colour attachment.
Pipeline make_fullscreen_pipeline(const VkContext& ctx, VkPipelineLayout layout, VkRenderPass rp, VkShaderModule vs,
                                  VkShaderModule fs, const std::vector<VkPipelineColorBlendAttachmentState>& blends);

// Records one draw of such a pipeline: render pass `render_pass` on `framebuffer` over `area` (its
// viewport and scissor too), the pipeline with descriptor set `set` of `layout`, and `push_size` bytes
// of fragment-stage push constants from `push` where given.
struct FullscreenDraw {
  VkRenderPass render_pass = VK_NULL_HANDLE;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VkRect2D area{};
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  const void* push = nullptr;
  uint32_t push_size = 0;
};
void record_fullscreen_draw(VkCommandBuffer cmd, const FullscreenDraw& d);

// An attachment that stays in `layout` before and after the pass (the frame
// graph's convention), loaded with `load` and stored; no stencil.
VkAttachmentDescription kept_attachment(VkFormat format, VkImageLayout layout, VkAttachmentLoadOp load);

// vkCreateRenderPass of one subpass over `attachments` with one dependency.
RenderPass create_render_pass(const VkContext& ctx, const std::vector<VkAttachmentDescription>& attachments,
                              const VkSubpassDescription& subpass, const VkSubpassDependency& dependency);

// A render pass of colour attachments only, each in COLOR_ATTACHMENT_OPTIMAL
// before and after (as the frame graph expects), loaded with `load`, stored;
// ordered after earlier colour writes to them.
RenderPass make_color_render_pass(const VkContext& ctx, const std::vector<VkFormat>& formats, VkAttachmentLoadOp load);

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

// The Vulkan functions glintlab calls, loaded from the Vulkan loader (libvulkan.so.1) with dlopen by the
// first Vulkan instance a process creates (core/vk/vk_context.cpp), not linked: a command that renders
// nothing (`compare`, `measure`, `check`) never maps the loader, one library fewer for the dynamic
// loader to load and search at its start.
//
// Every target that includes Vulkan's header is compiled with VK_NO_PROTOTYPES (glintlab_core's public
// definition), so the names below are this file's: one function pointer each, called as the function
// would be (`vkCreateBuffer(device, &info, nullptr, &buffer)`), null until load_vulkan(). A function
// glintlab starts to call is added to GLINTLAB_VULKAN_FUNCTIONS.
#pragma once

#ifndef VK_NO_PROTOTYPES
#error "compile with VK_NO_PROTOTYPES (glintlab_core's public compile definition)"
#endif
#include <vulkan/vulkan.h>

#define GLINTLAB_VULKAN_FUNCTIONS(X) \
  X(vkAllocateCommandBuffers) X(vkAllocateDescriptorSets) X(vkAllocateMemory) X(vkBeginCommandBuffer) \
  X(vkBindBufferMemory) X(vkBindImageMemory) X(vkCmdBeginRenderPass) X(vkCmdBindDescriptorSets) \
  X(vkCmdBindIndexBuffer) X(vkCmdBindPipeline) X(vkCmdBindVertexBuffers) X(vkCmdClearAttachments) \
  X(vkCmdClearColorImage) X(vkCmdCopyBufferToImage) X(vkCmdCopyImageToBuffer) X(vkCmdDispatch) X(vkCmdDraw) \
  X(vkCmdDrawIndexed) X(vkCmdEndRenderPass) X(vkCmdPipelineBarrier) X(vkCmdPushConstants) \
  X(vkCmdResetQueryPool) X(vkCmdSetScissor) X(vkCmdSetViewport) X(vkCmdWriteTimestamp) X(vkCreateBuffer) \
  X(vkCreateCommandPool) X(vkCreateComputePipelines) X(vkCreateDescriptorPool) X(vkCreateDescriptorSetLayout) \
  X(vkCreateDevice) X(vkCreateFence) X(vkCreateFramebuffer) X(vkCreateGraphicsPipelines) X(vkCreateImage) \
  X(vkCreateImageView) X(vkCreateInstance) X(vkCreatePipelineLayout) X(vkCreateQueryPool) X(vkCreateRenderPass) \
  X(vkCreateSampler) X(vkCreateShaderModule) X(vkDestroyBuffer) X(vkDestroyCommandPool) \
  X(vkDestroyDescriptorPool) X(vkDestroyDescriptorSetLayout) X(vkDestroyDevice) X(vkDestroyFence) \
  X(vkDestroyFramebuffer) X(vkDestroyImage) X(vkDestroyImageView) X(vkDestroyInstance) X(vkDestroyPipeline) \
  X(vkDestroyPipelineLayout) X(vkDestroyQueryPool) X(vkDestroyRenderPass) X(vkDestroySampler) \
  X(vkDestroyShaderModule) X(vkDeviceWaitIdle) X(vkEndCommandBuffer) X(vkEnumerateInstanceLayerProperties) \
  X(vkEnumeratePhysicalDevices) X(vkFreeCommandBuffers) X(vkFreeMemory) X(vkGetBufferMemoryRequirements) \
  X(vkGetDeviceQueue) X(vkGetImageMemoryRequirements) X(vkGetInstanceProcAddr) X(vkGetPhysicalDeviceFeatures) \
  X(vkGetPhysicalDeviceFormatProperties) X(vkGetPhysicalDeviceMemoryProperties) \
  X(vkGetPhysicalDeviceProperties) X(vkGetPhysicalDeviceProperties2) \
  X(vkGetPhysicalDeviceQueueFamilyProperties) X(vkGetQueryPoolResults) X(vkMapMemory) X(vkQueueSubmit) \
  X(vkUpdateDescriptorSets) X(vkWaitForFences)

namespace glintlab::vulkan {
#define GLINTLAB_VULKAN_DECLARE(name) extern PFN_##name name;
GLINTLAB_VULKAN_FUNCTIONS(GLINTLAB_VULKAN_DECLARE)
#undef GLINTLAB_VULKAN_DECLARE

// Loads libvulkan.so.1 and every function above, once per process (thread-safe). Throws
// core::VulkanError naming the library or the function and the Debian package when it cannot.
void load_vulkan();
}  // namespace glintlab::vulkan

// The names as Vulkan's header would declare them, for every caller.
#define GLINTLAB_VULKAN_USING(name) using glintlab::vulkan::name;
GLINTLAB_VULKAN_FUNCTIONS(GLINTLAB_VULKAN_USING)
#undef GLINTLAB_VULKAN_USING

// The one RAII owner of every Vulkan object that is destroyed with
// `vkDestroy*(device, handle, nullptr)` (or freed alike, such as memory):
// move-only, destroyed exactly once, null after a move. Composite owners
// (Buffer, Image2D) hold several Handles, so a failure half-way through
// their construction releases what was already created.
#pragma once

#include "core/vk/vulkan_functions.h"

namespace glintlab::core {

// Owns one Vulkan handle destroyed with `vkDestroy*(device, h, nullptr)`; Destroy is the function's
// pointer (core/vk/vulkan_functions.h), read when the handle is released.
template <typename H, void (VKAPI_PTR** Destroy)(VkDevice, H, const VkAllocationCallbacks*)>
class Handle {
 public:
  Handle() = default;
  Handle(VkDevice d, H h) : device_(d), h_(h) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : device_(o.device_), h_(o.h_) { o.h_ = VK_NULL_HANDLE; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      device_ = o.device_;
      h_ = o.h_;
      o.h_ = VK_NULL_HANDLE;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  H get() const { return h_; }
  void reset() {
    if (h_ != VK_NULL_HANDLE) (*Destroy)(device_, h_, nullptr);
    h_ = VK_NULL_HANDLE;
  }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  H h_ = VK_NULL_HANDLE;
};

using ShaderModule = Handle<VkShaderModule, &vkDestroyShaderModule>;
using DescriptorSetLayout = Handle<VkDescriptorSetLayout, &vkDestroyDescriptorSetLayout>;
using PipelineLayout = Handle<VkPipelineLayout, &vkDestroyPipelineLayout>;
using Pipeline = Handle<VkPipeline, &vkDestroyPipeline>;
using DescriptorPool = Handle<VkDescriptorPool, &vkDestroyDescriptorPool>;
using RenderPass = Handle<VkRenderPass, &vkDestroyRenderPass>;
using Framebuffer = Handle<VkFramebuffer, &vkDestroyFramebuffer>;
using Sampler = Handle<VkSampler, &vkDestroySampler>;
using QueryPool = Handle<VkQueryPool, &vkDestroyQueryPool>;
using BufferHandle = Handle<VkBuffer, &vkDestroyBuffer>;
using ImageHandle = Handle<VkImage, &vkDestroyImage>;
using ImageViewHandle = Handle<VkImageView, &vkDestroyImageView>;
using MemoryHandle = Handle<VkDeviceMemory, &vkFreeMemory>;

}  // namespace glintlab::core

// Headless Vulkan context: instance (+ validation when asked), one physical
// device (lavapipe by default), one queue that does graphics, compute and
// transfer, a command pool and a validation-message counter. Explicit Vulkan
// in the style of Sascha Willems' renderheadless, with small RAII helpers.
#pragma once

#include "core/vk/vulkan_functions.h"

#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace glintlab::core {

class VulkanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws VulkanError naming the call and the VkResult.
void vk_check(VkResult r, const char* what);

struct ContextOptions {
  // "" = default (lavapipe if present, else the first device); a decimal
  // number = index in `list_devices()`; otherwise a case-insensitive
  // substring of the device name.
  std::string device;
  // Enables VK_LAYER_KHRONOS_validation (core + synchronization). Every
  // warning or error it reports is counted; tests require zero.
  bool validation = false;
};

struct DeviceInfo {
  uint32_t index;
  std::string name;
  std::string type;  // "cpu", "discrete-gpu", ...
  std::string api_version;
};

// The exit code of a device that does not finish a submission (experiments/cli/exit_codes.h: kExitDevice).
constexpr int kExitDeviceHang = 3;
// $GLINTLAB_GPU_TIMEOUT_S when it is a number > 0, else 600: the longest one submission may run.
double gpu_timeout_s();

class VkContext {
 public:
  explicit VkContext(const ContextOptions& options = {});
  ~VkContext();
  VkContext(const VkContext&) = delete;
  VkContext& operator=(const VkContext&) = delete;

  static std::vector<DeviceInfo> list_devices();
  // True when GLINTLAB_VALIDATION=1 is set (tests and CI set it).
  static bool validation_requested_by_env();

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  VkCommandPool command_pool() const { return pool_; }
  const DeviceInfo& info() const { return info_; }
  const VkPhysicalDeviceProperties& properties() const { return props_; }
  bool validation_enabled() const { return validation_; }

  // Nanoseconds per timestamp tick, and whether timestamps work on the queue.
  double timestamp_period_ns() const { return props_.limits.timestampPeriod; }
  bool timestamps_supported() const { return timestamp_valid_bits_ > 0; }
  uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }

  // Whether the device blends colour attachments independently (enabled when supported).
  bool independent_blend() const { return independent_blend_; }
  // Whether fragment shaders may use subgroup quad operations (GL_KHR_shader_subgroup_quad).
  bool fragment_quad_operations() const { return fragment_quad_ops_; }

  uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const;
  bool format_supports(VkFormat format, VkFormatFeatureFlags features) const;

  // Records with `record` into a fresh primary command buffer, submits and waits.
  // A submission that has not finished after gpu_timeout_s() (a shader that never terminates: lavapipe
  // has no watchdog) cannot be stopped, and the device cannot be destroyed while it runs: the process
  // prints what happened and exits with kExitDeviceHang at once (glintlab's "device" exit code).
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;

  size_t validation_message_count() const;
  std::vector<std::string> validation_messages() const;

 private:
  void destroy();
  static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT types,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  uint32_t timestamp_valid_bits_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties props_{};
  VkPhysicalDeviceMemoryProperties mem_props_{};
  DeviceInfo info_;
  bool validation_ = false;
  bool independent_blend_ = false;
  bool fragment_quad_ops_ = false;
  mutable std::mutex messages_mutex_;
  std::vector<std::string> messages_;
};

}  // namespace glintlab::core

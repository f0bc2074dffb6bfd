#include "core/vk/vk_context.h"

#include "core/util/strings.h"

#include <memory>
#include <type_traits>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>

namespace glintlab::core {

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    default: return "VkResult " + std::to_string(static_cast<int>(r));
  }
}

std::string type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

bool layer_available(const char* name) {  // (after load_vulkan)
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

VkInstance create_instance(bool validation, const VkDebugUtilsMessengerCreateInfoEXT* messenger_info) {
  vulkan::load_vulkan();  // the first instance of the process loads the Vulkan loader
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "glintlab";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  if (validation) {
    if (!layer_available(kValidationLayer))
      throw VulkanError(std::string("validation was requested but ") + kValidationLayer +
                        " is not installed (Debian package vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    features.pNext = messenger_info;  // messages during vkCreateInstance are counted too
    ci.pNext = &features;
  }
  ci.enabledLayerCount = uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = uint32_t(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw VulkanError("no Vulkan driver found (install mesa-vulkan-drivers for the lavapipe CPU device)");
  vk_check(r, "vkCreateInstance");
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t n = 0;
  vk_check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devs(n);
  if (n) vk_check(vkEnumeratePhysicalDevices(instance, &n, devs.data()), "vkEnumeratePhysicalDevices");
  return devs;
}

DeviceInfo describe(VkPhysicalDevice d, uint32_t index) {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(d, &p);
  return {index, p.deviceName, type_name(p.deviceType),
          std::to_string(VK_API_VERSION_MAJOR(p.apiVersion)) + "." + std::to_string(VK_API_VERSION_MINOR(p.apiVersion)) +
              "." + std::to_string(VK_API_VERSION_PATCH(p.apiVersion))};
}

std::string describe_all(const std::vector<DeviceInfo>& infos) {
  std::string s;
  for (const auto& i : infos) s += "\n  " + std::to_string(i.index) + ": " + i.name + " (" + i.type + ")";
  return s.empty() ? " (none)" : s;
}

}  // namespace

void vk_check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw VulkanError(std::string(what) + " failed: " + result_name(r));
}

bool VkContext::validation_requested_by_env() {
  const char* v = std::getenv("GLINTLAB_VALIDATION");
  return v && std::string(v) != "0" && std::string(v) != "";
}

std::vector<DeviceInfo> VkContext::list_devices() {
  // The instance is destroyed on every path, enumeration failures included.
  std::unique_ptr<std::remove_pointer_t<VkInstance>, void (*)(VkInstance)> instance(
      create_instance(false, nullptr), [](VkInstance i) { vkDestroyInstance(i, nullptr); });
  std::vector<DeviceInfo> out;
  auto devs = physical_devices(instance.get());
  for (uint32_t i = 0; i < devs.size(); ++i) out.push_back(describe(devs[i], i));
  return out;
}

VKAPI_ATTR VkBool32 VKAPI_CALL VkContext::debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                          VkDebugUtilsMessageTypeFlagsEXT,
                                                          const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                          void* user) {
  auto* self = static_cast<VkContext*>(user);
  std::string level = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning";
  std::string msg = "[vulkan validation " + level + "] " + (data && data->pMessage ? data->pMessage : "");
  std::cerr << msg << "\n";
  std::lock_guard<std::mutex> lock(self->messages_mutex_);
  self->messages_.push_back(std::move(msg));
  return VK_FALSE;
}

VkContext::VkContext(const ContextOptions& options) : validation_(options.validation) {
  VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                   VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  mi.pfnUserCallback = &VkContext::debug_callback;
  mi.pUserData = this;
  instance_ = create_instance(validation_, &mi);
  try {
    if (validation_) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw VulkanError("vkCreateDebugUtilsMessengerEXT is not available");
      vk_check(create(instance_, &mi, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
    }

    auto devs = physical_devices(instance_);
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < devs.size(); ++i) infos.push_back(describe(devs[i], i));
    if (devs.empty())
      throw VulkanError("no Vulkan device found; install mesa-vulkan-drivers (lavapipe) or a GPU driver");
    int chosen = -1;
    const std::string& sel = options.device;
    if (sel.empty()) {
      for (const auto& i : infos)
        if (i.type == "cpu" || ascii_lower(i.name).find("llvmpipe") != std::string::npos) { chosen = int(i.index); break; }
      if (chosen < 0) chosen = 0;
    } else if (std::all_of(sel.begin(), sel.end(), [](unsigned char c) { return std::isdigit(c); })) {
      unsigned long idx = std::stoul(sel);
      if (idx >= devs.size())
        throw VulkanError("--device " + sel + ": no device with that index; available:" + describe_all(infos));
      chosen = int(idx);
    } else {
      for (const auto& i : infos)
        if (ascii_lower(i.name).find(ascii_lower(sel)) != std::string::npos) { chosen = int(i.index); break; }
      if (chosen < 0) throw VulkanError("--device " + sel + ": no device name contains it; available:" + describe_all(infos));
    }
    physical_ = devs[chosen];
    info_ = infos[chosen];
    vkGetPhysicalDeviceProperties(physical_, &props_);
    vkGetPhysicalDeviceMemoryProperties(physical_, &mem_props_);
    if (props_.apiVersion >= VK_API_VERSION_1_1) {
      VkPhysicalDeviceSubgroupProperties sub{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
      VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
      p2.pNext = &sub;
      vkGetPhysicalDeviceProperties2(physical_, &p2);
      fragment_quad_ops_ = (sub.supportedStages & VK_SHADER_STAGE_FRAGMENT_BIT) &&
                           (sub.supportedOperations & VK_SUBGROUP_FEATURE_QUAD_BIT);
    }

    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> qf(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nq, qf.data());
    bool found = false;
    for (uint32_t i = 0; i < nq; ++i) {
      if ((qf[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
        queue_family_ = i;
        timestamp_valid_bits_ = qf[i].timestampValidBits;
        found = true;
        break;
      }
    }
    if (!found) throw VulkanError("device " + info_.name + " has no graphics+compute queue");

    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queue_family_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &prio;
    // Independent blend: the surface pass accumulates colour by blending but
    // writes motion vectors unblended in the same draw.
    VkPhysicalDeviceFeatures supported{}, enabled{};
    vkGetPhysicalDeviceFeatures(physical_, &supported);
    enabled.independentBlend = supported.independentBlend;
    independent_blend_ = supported.independentBlend == VK_TRUE;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.pEnabledFeatures = &enabled;
    vk_check(vkCreateDevice(physical_, &dci, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queue_family_;
    vk_check(vkCreateCommandPool(device_, &pci, nullptr, &pool_), "vkCreateCommandPool");
  } catch (...) {
    destroy();
    throw;
  }
}

VkContext::~VkContext() { destroy(); }

void VkContext::destroy() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
    pool_ = VK_NULL_HANDLE;
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

uint32_t VkContext::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const {
  for (uint32_t i = 0; i < mem_props_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (mem_props_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  throw VulkanError("no memory type with the requested properties on " + info_.name);
}

bool VkContext::format_supports(VkFormat format, VkFormatFeatureFlags features) const {
  VkFormatProperties p;
  vkGetPhysicalDeviceFormatProperties(physical_, format, &p);
  return (p.optimalTilingFeatures & features) == features;
}

double gpu_timeout_s() {
  static const double t = [] {
    const char* v = std::getenv("GLINTLAB_GPU_TIMEOUT_S");
    char* end = nullptr;
    const double x = v ? std::strtod(v, &end) : 0.0;
    return v && end != v && *end == '\0' && x > 0 && x < 1e7 ? x : 600.0;
  }();
  return t;
}

void VkContext::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  vk_check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkFence fence = VK_NULL_HANDLE;
  try {
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk_check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    record(cmd);
    vk_check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vk_check(vkCreateFence(device_, &fi, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    vk_check(vkQueueSubmit(queue_, 1, &si, fence), "vkQueueSubmit");
    const VkResult waited = vkWaitForFences(device_, 1, &fence, VK_TRUE, uint64_t(gpu_timeout_s() * 1e9));
    if (waited == VK_TIMEOUT) {
      std::fprintf(stderr,
                   "error: the device (%s) did not finish a submission in %g s: a shader that does not terminate "
                   "(a glint model's loop?). It cannot be stopped, so glintlab exits now (code %d); "
                   "GLINTLAB_GPU_TIMEOUT_S sets the limit.\n",
                   info_.name.c_str(), gpu_timeout_s(), kExitDeviceHang);
      std::fflush(nullptr);
      std::_Exit(kExitDeviceHang);  // destructors would wait for the device forever
    }
    vk_check(waited, "vkWaitForFences");
  } catch (...) {
    if (fence) vkDestroyFence(device_, fence, nullptr);
    vkFreeCommandBuffers(device_, pool_, 1, &cmd);
    throw;
  }
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
}

size_t VkContext::validation_message_count() const {
  std::lock_guard<std::mutex> lock(messages_mutex_);
  return messages_.size();
}

std::vector<std::string> VkContext::validation_messages() const {
  std::lock_guard<std::mutex> lock(messages_mutex_);
  return messages_;
}

}  // namespace glintlab::core

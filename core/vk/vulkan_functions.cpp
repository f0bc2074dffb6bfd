#include "core/vk/vulkan_functions.h"

#include "core/vk/vk_context.h"

#include <dlfcn.h>

#include <mutex>
#include <string>

namespace glintlab::vulkan {

#define GLINTLAB_VULKAN_DEFINE(name) PFN_##name name = nullptr;
GLINTLAB_VULKAN_FUNCTIONS(GLINTLAB_VULKAN_DEFINE)
#undef GLINTLAB_VULKAN_DEFINE

namespace {

void load_once() {
  constexpr const char* kLoader = "libvulkan.so.1";
  void* lib = ::dlopen(kLoader, RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* e = ::dlerror();
    throw core::VulkanError(std::string("cannot load the Vulkan loader ") + kLoader + ": " + (e ? e : "unknown reason") +
                            " (Debian package libvulkan1: apt install libvulkan1)");
  }
  // The loader exports every core function; each is what linking against it would have called.
#define GLINTLAB_VULKAN_LOAD(f)                                                                            \
  f = reinterpret_cast<PFN_##f>(::dlsym(lib, #f));                                                         \
  if (!f)                                                                                                  \
    throw core::VulkanError(std::string(kLoader) + " has no " #f " (a Vulkan 1.2 loader is needed: Debian " \
                            "package libvulkan1)");
  GLINTLAB_VULKAN_FUNCTIONS(GLINTLAB_VULKAN_LOAD)
#undef GLINTLAB_VULKAN_LOAD
}

}  // namespace

void load_vulkan() {
  static std::once_flag once;
  std::call_once(once, load_once);  // a throw leaves it unloaded: the next call tries again
}

}  // namespace glintlab::vulkan

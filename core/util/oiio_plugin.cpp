#include "core/util/oiio_plugin.h"

#include "core/util/io_error.h"

#include <dlfcn.h>

#include <atomic>
#include <mutex>
#include <string>

namespace glintlab::oiio {

namespace {
std::atomic<bool> g_loaded{false};
}

const Api& api() {
  static const Api* table = [] {
    // The RUNPATH of the object that calls dlopen (the program, or the Python module) finds it.
    void* lib = ::dlopen("libglintlab_oiio.so", RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      const char* e = ::dlerror();
      throw IoError(std::string("cannot load libglintlab_oiio.so, glintlab's OpenImageIO image reading and writing: ") +
                    (e ? e : "unknown reason"));
    }
    using Get = const Api* (*)();
    auto get = reinterpret_cast<Get>(::dlsym(lib, "glintlab_oiio_api"));
    const Api* a = get ? get() : nullptr;
    if (!a || a->version != kApiVersion)
      throw IoError("libglintlab_oiio.so is not the one of this glintlab (no glintlab_oiio_api of version " +
                    std::to_string(kApiVersion) + ")");
    g_loaded = true;
    return a;
  }();
  return *table;
}

bool loaded() { return g_loaded; }

}  // namespace glintlab::oiio

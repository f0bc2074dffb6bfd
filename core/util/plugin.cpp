#include "core/util/plugin.h"

#include "core/util/io_error.h"

#include <dlfcn.h>

namespace glintlab {

const void* load_plugin(const char* library, const char* symbol, int version, const std::string& what,
                        const std::string& packages) {
  void* lib = ::dlopen(library, RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* e = ::dlerror();
    throw IoError(std::string("cannot load ") + library + ", glintlab's " + what + ": " + (e ? e : "unknown reason") +
                  " (it needs the Debian packages " + packages + ": apt install " + packages + ")");
  }
  using Get = const void* (*)();
  auto get = reinterpret_cast<Get>(::dlsym(lib, symbol));
  const void* table = get ? get() : nullptr;
  if (!table || *static_cast<const int*>(table) != version)
    throw IoError(std::string(library) + " is not the one of this glintlab (no " + symbol + " of version " +
                  std::to_string(version) + ")");
  return table;
}

const void* LazyPlugin::load() {
  if (loaded_) return table_;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!table_) {
    table_ = load_plugin(library_, symbol_, version_, what_, packages_);
    loaded_ = true;
  }
  return table_;
}

}  // namespace glintlab

#include "core/util/plugin.h"

#include "core/util/data_dir.h"
#include "core/util/io_error.h"

#include <dlfcn.h>

#include <filesystem>

namespace glintlab {

const void* load_plugin(const char* library, const char* symbol, int version, const std::string& what,
                        const std::string& packages) {
  // By its path where glintlab's libraries are (core/util/data_dir.h), else by name (the dynamic loader's
  // search: LD_LIBRARY_PATH, --library-path).
  std::string path = library;
  if (const std::string& dir = data_locations().plugins; !dir.empty()) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(std::filesystem::path(dir) / library, ec)) path = dir + "/" + library;
  }
  void* lib = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
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

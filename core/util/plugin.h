// glintlab's own shared libraries that hold what only some commands need (libglintlab_oiio.so:
// OpenImageIO, core/util/oiio_plugin.h; libglintlab_flow.so: OpenCV's optical flow,
// core/util/flow_plugin.h), loaded with dlopen on first use so that the others never load the
// libraries they link. They are loaded by their path in the folder core/util/data_dir.h names (the build
// folder for a program in it, PREFIX/lib/glintlab when installed), else by name through the dynamic
// loader's search. The program and the Python module carry no RUNPATH: one would be searched first for
// every library they link, at every start (about a hundred failed opens for the program in the build
// folder).
#pragma once

#include <atomic>
#include <mutex>
#include <string>

namespace glintlab {

// dlopen(library), then the table its extern "C" function `const void* symbol()` returns, whose first
// member is an int version that must equal `version`. IoError naming the library, `what` it is for, dlerror()'s
// reason and the Debian `packages` whose libraries it needs (glintlab's package recommends them, so an
// install without its recommendations lacks them) when it cannot be loaded, or when it is not this
// glintlab's (no such function, another version).
const void* load_plugin(const char* library, const char* symbol, int version, const std::string& what,
                        const std::string& packages);

// One such library, loaded by the first call of table() (thread-safe; an IoError from load_plugin is
// thrown again by each later call), and whether it has been (for the tests of the paths that must not).
class LazyPlugin {
 public:
  constexpr LazyPlugin(const char* library, const char* symbol, int version, const char* what, const char* packages)
      : library_(library), symbol_(symbol), version_(version), what_(what), packages_(packages) {}
  template <class Api>
  const Api& table() {
    return *static_cast<const Api*>(load());
  }
  bool loaded() const { return loaded_; }

 private:
  const void* load();
  const char *library_, *symbol_;
  int version_;
  const char *what_, *packages_;
  std::mutex mutex_;
  const void* table_ = nullptr;
  std::atomic<bool> loaded_{false};
};

}  // namespace glintlab

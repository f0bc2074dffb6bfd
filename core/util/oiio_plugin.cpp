#include "core/util/oiio_plugin.h"

#include "core/util/plugin.h"

#include <atomic>

namespace glintlab::oiio {

namespace {
std::atomic<bool> g_loaded{false};
}

const Api& api() {
  static const Api* table = [] {
    auto a = static_cast<const Api*>(load_plugin("libglintlab_oiio.so", "glintlab_oiio_api", kApiVersion,
                                                 "OpenImageIO image reading and writing", "libopenimageio2.4"));
    g_loaded = true;
    return a;
  }();
  return *table;
}

bool loaded() { return g_loaded; }

}  // namespace glintlab::oiio

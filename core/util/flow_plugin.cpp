#include "core/util/flow_plugin.h"

#include "core/util/plugin.h"

#include <atomic>

namespace glintlab::flow {

namespace {
std::atomic<bool> g_loaded{false};
}

const Api& api() {
  static const Api* table = [] {
    auto a = static_cast<const Api*>(
        load_plugin("libglintlab_flow.so", "glintlab_flow_api", kApiVersion, "OpenCV optical flow",
                    "libopencv-core406 libopencv-video406"));
    g_loaded = true;
    return a;
  }();
  return *table;
}

bool loaded() { return g_loaded; }

}  // namespace glintlab::flow

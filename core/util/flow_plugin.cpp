#include "core/util/flow_plugin.h"

#include "core/util/plugin.h"

namespace glintlab::flow {

namespace {
// Constant-initialised (constexpr constructor): ready before any other static initialiser runs.
LazyPlugin g_plugin("libglintlab_flow.so", "glintlab_flow_api", kApiVersion,
                    "OpenCV optical flow", "libopencv-core406 libopencv-video406");
}

const Api& api() { return g_plugin.table<Api>(); }

bool loaded() { return g_plugin.loaded(); }

}  // namespace glintlab::flow

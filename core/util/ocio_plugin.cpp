#include "core/util/ocio_plugin.h"

#include "core/util/plugin.h"

namespace glintlab::ocio {

namespace {
// Constant-initialised (constexpr constructor): ready before any other static initialiser runs.
LazyPlugin g_plugin("libglintlab_ocio.so", "glintlab_ocio_api", kApiVersion,
                    "OpenColorIO colour management", "libopencolorio2.1");
}

const Api& api() { return g_plugin.table<Api>(); }

bool loaded() { return g_plugin.loaded(); }

}  // namespace glintlab::ocio

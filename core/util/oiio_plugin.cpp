#include "core/util/oiio_plugin.h"

#include "core/util/plugin.h"

namespace glintlab::oiio {

namespace {
// Constant-initialised (constexpr constructor): ready before any other static initialiser runs.
LazyPlugin g_plugin("libglintlab_oiio.so", "glintlab_oiio_api", kApiVersion,
                    "OpenImageIO image reading and writing", "libopenimageio2.4");
}

const Api& api() { return g_plugin.table<Api>(); }

bool loaded() { return g_plugin.loaded(); }

}  // namespace glintlab::oiio

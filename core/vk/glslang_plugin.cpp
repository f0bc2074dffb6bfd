#include "core/vk/glslang_plugin.h"

#include "core/util/plugin.h"

namespace glintlab::glsl {

namespace {
// Constant-initialised (constexpr constructor): ready before any other static initialiser runs.
LazyPlugin g_plugin("libglintlab_glslang.so", "glintlab_glslang_api", kApiVersion, "the GLSL shader compiler",
                    "libc6");
}

const Api& api() { return g_plugin.table<Api>(); }

bool loaded() { return g_plugin.loaded(); }

}  // namespace glintlab::glsl

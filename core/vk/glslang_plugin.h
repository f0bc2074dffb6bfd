// glintlab's use of glslang (GLSL -> SPIR-V, with the SPIRV-Tools it links) lives in a shared library of
// its own, libglintlab_glslang.so (experiments/glslang_plugin/), loaded with dlopen by the first shader
// the renderer preprocesses (core::ShaderCompiler, the one user of this interface). glslang's and
// SPIRV-Tools' tables of pointers (grammar, built-ins, opcodes: about 265 KB) are data the dynamic
// loader relocates at the start of any program that links them, page by page; commands that render
// nothing (`compare`, `measure`, `check`, `list`, `--help`) never load them.
//
// The library is found and loaded as core/util/plugin.h says.
#pragma once

#include "core/vk/shader_compiler.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace glintlab::glsl {

// One GLSL source as glslang takes it.
struct Source {
  std::string path;      // names the file in glslang's messages
  std::string text;      // the file's text
  std::string preamble;  // the #extension and #define lines put before it
  core::ShaderStage stage = core::ShaderStage::Compute;
  // Resolves #include "name" met in the file `includer`: its path and text, or false where there is
  // none. May throw (ShaderCompileError: an include that cannot be read).
  std::function<bool(const std::string& name, const std::string& includer, std::string& path, std::string& text)>
      include;
};

constexpr int kApiVersion = 1;

struct Api {
  int version;
  // glslang's preprocessed text of `src` (includes resolved, macros expanded) into `expanded`; on failure,
  // false and glslang's log ("ERROR: <file>:<line>: <message>" lines) in `log`.
  bool (*preprocess)(const Source& src, std::string& expanded, std::string& log);
  // SPIR-V 1.5 for Vulkan 1.2 of `src` into `spirv` (GLSL 450, SPIR-V and Vulkan rules, no optimiser);
  // on failure, false and the log of the step that failed in `log`.
  bool (*compile)(const Source& src, std::vector<std::uint32_t>& spirv, std::string& log);
};

// The library's functions, loaded on first use (thread-safe). Throws IoError when it cannot be loaded.
const Api& api();

// Whether this process has loaded the library (for the tests of the paths that must not).
bool loaded();

}  // namespace glintlab::glsl

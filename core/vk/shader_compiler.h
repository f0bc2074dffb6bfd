// Run-time GLSL -> SPIR-V with glslang (libglintlab_glslang.so, core/vk/glslang_plugin.h, loaded by
// the first shader preprocessed): #include resolved against the shader
// tree (and the including file's folder), defines as "NAME" or "NAME=VALUE",
// errors reported as file:line, and SPIR-V cached on disk by the hash of the
// fully preprocessed source (so an edit in any include invalidates it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace glintlab::core {

enum class ShaderStage { Vertex, Fragment, Compute };

// A `defines` entry "include:NAME=PATH" is no macro but an include alias:
// #include "NAME" reads PATH (absolute, or relative to the shader folder).
inline constexpr std::string_view kIncludeAliasPrefix = "include:";

class ShaderCompileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CompiledShader {
  std::vector<uint32_t> spirv;
  std::string source_hash;  // hash of preprocessed source + stage + defines
  bool from_cache = false;
};

class ShaderCompiler {
 public:
  // shader_dir "" = shaders/ of the data folder (core/util/data_dir.h);
  // cache_dir "" = $XDG_CACHE_HOME/glintlab/spirv (or ~/.cache/...); "-" = no disk cache.
  explicit ShaderCompiler(std::string shader_dir = "", std::string cache_dir = "");

  // `path` is relative to the shader folder (or absolute).
  CompiledShader compile(const std::string& path, ShaderStage stage, const std::vector<std::string>& defines = {});
  // Preprocesses only: the hash that identifies what compile() would produce.
  std::string source_hash(const std::string& path, ShaderStage stage, const std::vector<std::string>& defines = {});
  // The preprocessed text (includes resolved, macros expanded, comments gone). ShaderCompileError on failure.
  std::string preprocess(const std::string& path, ShaderStage stage, const std::vector<std::string>& defines = {});

  const std::string& shader_dir() const { return shader_dir_; }
  const std::string& cache_dir() const { return cache_dir_; }

 private:
  std::string shader_dir_;
  std::string cache_dir_;
};

// The define NAME=w0,w1,... of `bytes` bytes of 32-bit words (hex unsigned
// literals, in order): how a shader takes host data as constants that it
// turns back into floats with uintBitsToFloat, bit-exact.
std::string words_define(const std::string& name, const void* data, std::size_t bytes);

// The process-wide compiler for the project's shader folder.
ShaderCompiler& default_shader_compiler();

}  // namespace glintlab::core

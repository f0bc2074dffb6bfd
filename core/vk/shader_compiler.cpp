#include "core/vk/shader_compiler.h"

#include "core/util/atomic_file.h"

#include "core/util/content_hash.h"
#include "core/util/strings.h"
#include "core/util/data_dir.h"
#include "core/vk/glslang_plugin.h"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;

namespace glintlab::core {

namespace {

constexpr uint32_t kSpirvMagic = 0x07230203u;

const char* stage_name(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex: return "vertex";
    case ShaderStage::Fragment: return "fragment";
    case ShaderStage::Compute: return "compute";
  }
  return "?";
}

std::string read_file(const fs::path& p) {
  if (std::optional<std::string> text = read_text_file(p)) return *text;
  throw ShaderCompileError(p.string() + ": cannot open shader source");
}

// Resolves #include "x" as an include alias (kIncludeAliasPrefix) when one
// is named x, else against the including file's folder, then the shader root.
class Includer {
 public:
  Includer(fs::path root, std::map<std::string, fs::path> aliases)
      : root_(std::move(root)), aliases_(std::move(aliases)) {}

  bool operator()(const std::string& name, const std::string& includer, std::string& path, std::string& text) const {
    if (auto a = aliases_.find(name); a != aliases_.end()) {
      fs::path p = a->second.is_absolute() ? a->second : root_ / a->second;
      return fs::is_regular_file(p) && found(p, path, text);
    }
    fs::path from = fs::path(includer).parent_path();
    for (const fs::path& base : {from, root_}) {
      fs::path p = base / name;
      if (!base.empty() && fs::is_regular_file(p)) return found(p, path, text);
    }
    return false;
  }

 private:
  static bool found(const fs::path& p, std::string& path, std::string& text) {
    text = read_file(p);
    path = p.lexically_normal().string();
    return true;
  }
  fs::path root_;
  std::map<std::string, fs::path> aliases_;
};

bool is_alias(const std::string& d) { return d.rfind(kIncludeAliasPrefix, 0) == 0; }

// "include:NAME=PATH" entries of `defines`: NAME -> PATH.
std::map<std::string, fs::path> include_aliases(const std::vector<std::string>& defines) {
  std::map<std::string, fs::path> out;
  for (const auto& d : defines) {
    if (!is_alias(d)) continue;
    auto eq = d.find('=');
    std::string name = d.substr(kIncludeAliasPrefix.size(), eq == std::string::npos ? std::string::npos
                                                                                   : eq - kIncludeAliasPrefix.size());
    if (eq == std::string::npos || name.empty() || eq + 1 == d.size())
      throw ShaderCompileError("shader include alias \"" + d + "\": expected include:NAME=PATH");
    out[name] = fs::path(d.substr(eq + 1));
  }
  return out;
}

std::string preamble(const std::vector<std::string>& defines) {
  std::string s = "#extension GL_GOOGLE_include_directive : require\n";
  for (const auto& d : defines) {
    if (is_alias(d)) continue;
    auto eq = d.find('=');
    std::string name = d.substr(0, eq);
    if (name.empty() || !std::regex_match(name, std::regex("[A-Za-z_][A-Za-z0-9_]*")))
      throw ShaderCompileError("shader define \"" + d + "\": expected NAME or NAME=VALUE with a C identifier");
    s += "#define " + name + " " + (eq == std::string::npos ? "1" : d.substr(eq + 1)) + "\n";
  }
  return s;
}

// glslang logs "ERROR: <file>:<line>: <message>"; keep that form, drop noise.
std::string format_log(const std::string& log, const std::string& path, const char* stage) {
  std::ostringstream out;
  out << "GLSL " << stage << " shader " << path << " failed to compile:";
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line.find("compilation terminated") != std::string::npos) continue;
    if (line.rfind("ERROR: ", 0) == 0) line = line.substr(7);
    out << "\n  " << line;
  }
  return out.str();
}

std::string default_cache_dir() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  fs::path base = xdg && *xdg ? fs::path(xdg) : fs::path(home && *home ? home : "/tmp") / ".cache";
  return (base / "glintlab" / "spirv").string();
}

// The source glslang takes: the file, the preamble of `defines` and the include resolver of `root`.
glsl::Source load(const std::string& root, const std::string& path, ShaderStage stage,
                         const std::vector<std::string>& defines) {
  fs::path p = fs::path(path).is_absolute() ? fs::path(path) : fs::path(root) / path;
  glsl::Source src;
  src.path = p.lexically_normal().string();
  src.text = read_file(p);
  src.preamble = preamble(defines);
  src.stage = stage;
  src.include = Includer(root, include_aliases(defines));
  return src;
}

}  // namespace

ShaderCompiler::ShaderCompiler(std::string shader_dir, std::string cache_dir)
    : shader_dir_(shader_dir.empty() ? data_path("shaders") : std::move(shader_dir)),
      cache_dir_(cache_dir.empty() ? default_cache_dir() : std::move(cache_dir)) {}

std::string words_define(const std::string& name, const void* data, std::size_t bytes) {
  std::string out = name + "=";
  for (std::size_t i = 0; i + 4 <= bytes; i += 4) {
    std::uint32_t u;
    std::memcpy(&u, static_cast<const unsigned char*>(data) + i, 4);
    char w[16];
    std::snprintf(w, sizeof w, "%s0x%08xu", i ? "," : "", unsigned(u));
    out += w;
  }
  return out;
}

std::string ShaderCompiler::preprocess(const std::string& path, ShaderStage stage,
                                       const std::vector<std::string>& defines) {
  const glsl::Source src = load(shader_dir_, path, stage, defines);
  std::string expanded, log;
  if (!glsl::api().preprocess(src, expanded, log))
    throw ShaderCompileError(format_log(log, src.path, stage_name(stage)));
  return expanded;
}

std::string ShaderCompiler::source_hash(const std::string& path, ShaderStage stage,
                                        const std::vector<std::string>& defines) {
  ContentHash h;
  h.add(std::string_view("glslang-spv1.5-vk1.2"))
      .add(int64_t(stage))
      .add(preamble(defines))
      .add(preprocess(path, stage, defines));
  return h.hex();
}

CompiledShader ShaderCompiler::compile(const std::string& path, ShaderStage stage,
                                       const std::vector<std::string>& defines) {
  CompiledShader out;
  out.source_hash = source_hash(path, stage, defines);
  fs::path cached = cache_dir_ == "-" ? fs::path() : fs::path(cache_dir_) / (out.source_hash + ".spv");
  if (!cached.empty() && fs::is_regular_file(cached)) {
    std::string bytes = read_file(cached);
    if (bytes.size() >= 20 && bytes.size() % 4 == 0) {
      out.spirv.resize(bytes.size() / 4);
      std::memcpy(out.spirv.data(), bytes.data(), bytes.size());
      if (out.spirv[0] == kSpirvMagic) {
        out.from_cache = true;
        return out;
      }
    }
    out.spirv.clear();  // corrupt entry: fall through and rebuild it
  }

  const glsl::Source src = load(shader_dir_, path, stage, defines);
  std::string log;
  if (!glsl::api().compile(src, out.spirv, log)) throw ShaderCompileError(format_log(log, src.path, stage_name(stage)));

  if (!cached.empty()) {
    try {  // a cache that cannot be written only costs time
      std::error_code ec;
      fs::create_directories(cached.parent_path(), ec);
      write_text_atomic(cached, std::string_view(reinterpret_cast<const char*>(out.spirv.data()), out.spirv.size() * 4));
    } catch (const std::exception&) {
    }
  }
  return out;
}

ShaderCompiler& default_shader_compiler() {
  static ShaderCompiler compiler;
  return compiler;
}

}  // namespace glintlab::core

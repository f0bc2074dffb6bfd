#include "core/vk/shader_compiler.h"

#include "core/util/atomic_file.h"

#include "core/util/content_hash.h"
#include "core/util/strings.h"
#include "core/util/data_dir.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

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

void init_glslang() {
  static std::once_flag once;
  std::call_once(once, [] {
    glslang::InitializeProcess();
    std::atexit([] { glslang::FinalizeProcess(); });
  });
}

EShLanguage to_glslang(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex: return EShLangVertex;
    case ShaderStage::Fragment: return EShLangFragment;
    case ShaderStage::Compute: return EShLangCompute;
  }
  return EShLangCompute;
}

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
class Includer : public glslang::TShader::Includer {
 public:
  Includer(fs::path root, std::map<std::string, fs::path> aliases)
      : root_(std::move(root)), aliases_(std::move(aliases)) {}

  IncludeResult* includeLocal(const char* name, const char* includer, size_t /*depth*/) override {
    if (auto a = aliases_.find(name); a != aliases_.end()) {
      fs::path p = a->second.is_absolute() ? a->second : root_ / a->second;
      return fs::is_regular_file(p) ? make(p) : nullptr;
    }
    fs::path from = fs::path(includer).parent_path();
    for (const fs::path& base : {from, root_}) {
      fs::path p = base / name;
      if (!base.empty() && fs::is_regular_file(p)) return make(p);
    }
    return nullptr;
  }
  IncludeResult* includeSystem(const char* name, const char* includer, size_t depth) override {  // same search
    return includeLocal(name, includer, depth);
  }
  void releaseInclude(IncludeResult* r) override {
    if (!r) return;
    delete static_cast<std::string*>(r->userData);
    delete r;
  }

 private:
  IncludeResult* make(const fs::path& p) {
    auto* text = new std::string(read_file(p));
    return new IncludeResult(p.lexically_normal().string(), text->data(), text->size(), text);
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

struct Source {
  std::string path;  // as given to glslang (names the file in errors)
  std::string text;
  std::string preamble;
};

void setup(glslang::TShader& sh, const Source& src, const char** text_ptr, const char** name_ptr, int* len) {
  *text_ptr = src.text.c_str();
  *name_ptr = src.path.c_str();
  *len = int(src.text.size());
  sh.setStringsWithLengthsAndNames(text_ptr, len, name_ptr, 1);
  sh.setPreamble(src.preamble.c_str());
  sh.setEnvInput(glslang::EShSourceGlsl, sh.getStage(), glslang::EShClientVulkan, 100);
  sh.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
  sh.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
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

}  // namespace

ShaderCompiler::ShaderCompiler(std::string shader_dir, std::string cache_dir)
    : shader_dir_(shader_dir.empty() ? data_path("shaders") : std::move(shader_dir)),
      cache_dir_(cache_dir.empty() ? default_cache_dir() : std::move(cache_dir)) {
  init_glslang();
}

static Source load(const std::string& root, const std::string& path, const std::vector<std::string>& defines) {
  fs::path p = fs::path(path).is_absolute() ? fs::path(path) : fs::path(root) / path;
  return Source{p.lexically_normal().string(), read_file(p), preamble(defines)};
}

// A glslang shader with its source, preamble and includer set up, ready to
// preprocess (for the hash) or parse (to compile).
struct Prepared {
  Source src;
  const char* text = nullptr;
  const char* name = nullptr;
  int len = 0;
  glslang::TShader sh;
  Includer includer;
  Prepared(const std::string& root, const std::string& path, ShaderStage stage, const std::vector<std::string>& defines)
      : src(load(root, path, defines)), sh(to_glslang(stage)), includer(root, include_aliases(defines)) {
    setup(sh, src, &text, &name, &len);
  }
};

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

std::string ShaderCompiler::source_hash(const std::string& path, ShaderStage stage,
                                        const std::vector<std::string>& defines) {
  Prepared p(shader_dir_, path, stage, defines);
  std::string expanded;
  if (!p.sh.preprocess(GetDefaultResources(), 450, ENoProfile, false, false, EShMsgDefault, &expanded, p.includer))
    throw ShaderCompileError(format_log(p.sh.getInfoLog(), p.src.path, stage_name(stage)));
  ContentHash h;
  h.add(std::string_view("glslang-spv1.5-vk1.2")).add(int64_t(stage)).add(p.src.preamble).add(expanded);
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

  Prepared p(shader_dir_, path, stage, defines);
  const Source& src = p.src;
  EShMessages msgs = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);
  if (!p.sh.parse(GetDefaultResources(), 450, false, msgs, p.includer))
    throw ShaderCompileError(format_log(p.sh.getInfoLog(), src.path, stage_name(stage)));
  glslang::TProgram program;
  program.addShader(&p.sh);
  if (!program.link(msgs)) throw ShaderCompileError(format_log(program.getInfoLog(), src.path, stage_name(stage)));
  glslang::SpvOptions opt;
  opt.validate = false;
  opt.disableOptimizer = true;
  spv::SpvBuildLogger logger;
  glslang::GlslangToSpv(*program.getIntermediate(to_glslang(stage)), out.spirv, &logger, &opt);
  if (out.spirv.empty()) throw ShaderCompileError(src.path + ": SPIR-V generation failed: " + logger.getAllMessages());

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

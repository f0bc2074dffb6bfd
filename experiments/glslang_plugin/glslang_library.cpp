// libglintlab_glslang.so: every call glintlab makes into glslang (core/vk/glslang_plugin.h), loaded by
// the first shader the renderer preprocesses, so that a process that renders nothing never relocates
// glslang's and SPIRV-Tools' tables. Only glintlab_glslang_api is exported (the rest is hidden).
#include "core/vk/glslang_plugin.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <cstdlib>
#include <memory>
#include <mutex>

namespace glintlab::glsl {
namespace {

void init_glslang() {
  static std::once_flag once;
  std::call_once(once, [] {
    glslang::InitializeProcess();
    std::atexit([] { glslang::FinalizeProcess(); });
  });
}

EShLanguage to_glslang(core::ShaderStage s) {
  switch (s) {
    case core::ShaderStage::Vertex: return EShLangVertex;
    case core::ShaderStage::Fragment: return EShLangFragment;
    case core::ShaderStage::Compute: return EShLangCompute;
  }
  return EShLangCompute;
}

// Includes nest at most this deep: a file that includes itself (or a cycle of files) without a guard
// would otherwise recurse until memory runs out. glintlab's own shaders nest 5 deep.
constexpr size_t kMaxIncludeDepth = 32;

// glslang's #include callbacks, answered by the source's own resolver.
class Includer : public glslang::TShader::Includer {
 public:
  explicit Includer(const Source& src) : src_(src) {}
  IncludeResult* includeLocal(const char* name, const char* includer, size_t depth) override {
    if (depth > kMaxIncludeDepth) {  // an empty header name makes glslang report the text as the error
      auto msg = std::make_unique<Found>();
      msg->text = "includes nest deeper than " + std::to_string(kMaxIncludeDepth) +
                  " files (does a file include itself, or two files each other, without an include guard?)";
      Found* f = msg.release();
      return new IncludeResult("", f->text.data(), f->text.size(), f);
    }
    auto found = std::make_unique<Found>();
    if (!src_.include || !src_.include(name, includer, found->path, found->text)) return nullptr;
    Found* f = found.release();
    return new IncludeResult(f->path, f->text.data(), f->text.size(), f);
  }
  IncludeResult* includeSystem(const char* name, const char* includer, size_t depth) override {  // same search
    return includeLocal(name, includer, depth);
  }
  void releaseInclude(IncludeResult* r) override {
    if (!r) return;
    delete static_cast<Found*>(r->userData);
    delete r;
  }

 private:
  struct Found {
    std::string path, text;
  };
  const Source& src_;
};

// A glslang shader with the source's text, name, preamble and target environment set.
struct Shader {
  const char* text;
  const char* name;
  int len;
  glslang::TShader sh;
  explicit Shader(const Source& src)
      : text(src.text.c_str()), name(src.path.c_str()), len(int(src.text.size())), sh(to_glslang(src.stage)) {
    sh.setStringsWithLengthsAndNames(&text, &len, &name, 1);
    sh.setPreamble(src.preamble.c_str());
    sh.setEnvInput(glslang::EShSourceGlsl, sh.getStage(), glslang::EShClientVulkan, 100);
    sh.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    sh.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
  }
};

bool preprocess(const Source& src, std::string& expanded, std::string& log) {
  init_glslang();
  Shader s(src);
  Includer includer(src);
  if (s.sh.preprocess(GetDefaultResources(), 450, ENoProfile, false, false, EShMsgDefault, &expanded, includer))
    return true;
  log = s.sh.getInfoLog();
  return false;
}

bool compile(const Source& src, std::vector<std::uint32_t>& spirv, std::string& log) {
  init_glslang();
  Shader s(src);
  Includer includer(src);
  const EShMessages msgs = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);
  if (!s.sh.parse(GetDefaultResources(), 450, false, msgs, includer)) {
    log = s.sh.getInfoLog();
    return false;
  }
  glslang::TProgram program;
  program.addShader(&s.sh);
  if (!program.link(msgs)) {
    log = program.getInfoLog();
    return false;
  }
  glslang::SpvOptions opt;
  opt.validate = false;
  opt.disableOptimizer = true;
  spv::SpvBuildLogger logger;
  spirv.clear();
  glslang::GlslangToSpv(*program.getIntermediate(to_glslang(src.stage)), spirv, &logger, &opt);
  if (!spirv.empty()) return true;
  log = "ERROR: SPIR-V generation failed: " + logger.getAllMessages();
  return false;
}

}  // namespace
}  // namespace glintlab::glsl

// The table, untyped: load_plugin (core/util/plugin.h) calls every plugin's function as const void* ().
extern "C" __attribute__((visibility("default"))) const void* glintlab_glslang_api() {
  using namespace glintlab::glsl;
  static const Api api{kApiVersion, &preprocess, &compile};
  return &api;
}

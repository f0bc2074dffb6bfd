// libFuzzer harness: a user's glint model file as glintlab reads it before any GPU work
// (core::glint_model_from_file: the declaration lines, then the preprocessed source's check for what a
// model may not declare).
//
// Input: up to two parts separated by a NUL byte: the model file (m.glsl) and a second file beside it
// (inc.glsl), which the first may #include, or include itself, or each other. Seeds: the built-in
// models (shaders/glint/models/) and tests/data/glint_models/.
//
// Oracle (anything else is a finding, see fuzz_common.h): glint_model_from_file returns or throws
// ConfigError (bad declarations, forbidden words: exit 2) or ShaderCompileError (a preprocessing error,
// an include cycle past 32 levels: exit 3), never anything else, and never recurses without bound. What
// it accepts is checked here, independently of glint_model.cpp: a glint_model line; every parameter
// lower_snake_case, not declared twice, with a default inside its range and both ends finite in a
// float; a table size in 1 ... 2^21; and its preprocessed source contains none of "layout",
// "buffer", "uniform", "shared" and "discard" as a word.

#include "core/material/glint_model.h"
#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"
#include "tests/fuzz/fuzz_common.h"

#include <cmath>
#include <limits>
#include <regex>
#include <set>
#include <string>

using namespace glintlab_fuzz;

namespace {
std::string g_dir;

// What an accepted declaration must not hold; "" when nothing.
std::string accepted_bad_input(const glintlab::core::GlintModelDecl& d, const std::string& path) {
  static const std::regex snake("[a-z][a-z0-9_]*");
  const double fmax = double(std::numeric_limits<float>::max());
  std::set<std::string> names;
  for (const auto& p : d.parameters) {
    if (!std::regex_match(p.name, snake)) return "a parameter name that is not lower_snake_case: " + p.name;
    if (!names.insert(p.name).second) return "a parameter declared twice: " + p.name;
    if (!(p.lo <= p.def && p.def <= p.hi)) return "a default outside its range: " + p.name;
    if (!std::isfinite(p.lo) || !std::isfinite(p.hi) || std::fabs(p.lo) > fmax || std::fabs(p.hi) > fmax)
      return "a range beyond a float: " + p.name;
  }
  if (d.table_size > (1u << 21)) return "a table of " + std::to_string(d.table_size) + " floats";
  // the source as glintlab compiles it (includes resolved, macros expanded, comments gone)
  std::string expanded;
  try {
    expanded = glintlab::core::default_shader_compiler().preprocess(path, glintlab::core::ShaderStage::Compute);
  } catch (const glintlab::core::ShaderCompileError&) {
    return "";
  }
  static const std::regex forbidden("\\b(layout|buffer|uniform|shared|discard)\\b");
  if (std::regex_search(expanded, forbidden)) return "a model whose source uses a forbidden word was accepted";
  return "";
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = make_temp_dir("glint_model");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 64 * 1024) return -1;
  const std::string in(reinterpret_cast<const char*>(data), size);
  const size_t nul = in.find('\0');
  const std::string model = in.substr(0, nul), inc = nul == std::string::npos ? "" : in.substr(nul + 1);
  const std::string path = g_dir + "/m.glsl";
  write_file(path, model);
  write_file(g_dir + "/inc.glsl", inc);
  try {
    const glintlab::core::GlintModelDecl d = glintlab::core::glint_model_from_file(path);
    const std::string why = accepted_bad_input(d, path);
    if (!why.empty()) finding("glint-model-accepted-bad-input", why);
  } catch (const glintlab::ConfigError&) {
  } catch (const glintlab::core::ShaderCompileError&) {
  } catch (...) {
    finding("glint-model-throws", current_exception_text());
  }
  return 0;
}

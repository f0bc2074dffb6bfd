#include "core/vk/user_shader.h"

#include "core/util/json_check.h"
#include "core/util/strings.h"
#include "core/vk/shader_compiler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <sstream>

namespace glintlab::core {

std::vector<std::string> split_list(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  return out;
}

bool parse_finite(const std::string& s, double& v) {
  if (s.empty()) return false;
  std::istringstream in(s);
  in >> v;
  return in && in.peek() == std::char_traits<char>::eof() && std::isfinite(v);
}

bool fits_float(double x) { return std::isfinite(x) && std::fabs(x) <= double(std::numeric_limits<float>::max()); }

std::string parameter_name_problem(const std::string& n, const std::set<std::string>& reserved) {
  static const std::set<std::string> glsl = {
      // GLSL 4.60 keywords (types included) and the words reserved for future use
      "attribute", "const", "uniform", "varying", "buffer", "shared", "coherent", "volatile", "restrict",
      "readonly", "writeonly", "atomic_uint", "layout", "centroid", "flat", "smooth", "noperspective", "patch",
      "sample", "invariant", "precise", "break", "continue", "do", "for", "while", "switch", "case", "default",
      "if", "else", "subroutine", "in", "out", "inout", "int", "void", "bool", "true", "false", "float", "double",
      "discard", "return", "uint", "lowp", "mediump", "highp", "precision", "struct", "common", "partition",
      "active", "asm", "class", "union", "enum", "typedef", "template", "this", "resource", "goto", "inline",
      "noinline", "public", "static", "extern", "external", "interface", "long", "short", "half", "fixed",
      "unsigned", "superp", "input", "output", "filter", "sizeof", "cast", "namespace", "using", "demote"};
  static const std::regex snake("[a-z][a-z0-9_]*");
  static const std::regex type_name("([biud]?vec[234]|d?mat[234](x[234])?|[iu]?(sampler|image|texture)\\w*)");
  if (!std::regex_match(n, snake))
    return "parameter name \"" + n + "\" must be lower_snake_case (a-z, 0-9, _; upper case names are macros)";
  if (n.rfind("gl_", 0) == 0 || glsl.count(n) || std::regex_match(n, type_name))
    return "parameter name \"" + n + "\" is a GLSL keyword, reserved word or type; give the parameter another name";
  if (reserved.count(n))
    return "parameter name \"" + n + "\" is taken (" + join(std::vector<std::string>(reserved.begin(), reserved.end())) +
           " are the struct's own fields or the object's other keys); give the parameter another name";
  return "";
}

DeclaredParameter parse_declared_parameter(const std::vector<std::string>& fields, const std::set<std::string>& reserved,
                                           bool allow_requires, const std::function<void(const std::string&)>& fail) {
  if (fields.empty() || !is_identifier(fields[0])) fail("a parameter needs a GLSL identifier as its name");
  if (const std::string why = parameter_name_problem(fields[0], reserved); !why.empty()) fail(why);
  DeclaredParameter p;
  p.name = fields[0];
  bool has_def = false, has_range = false;
  std::string def_text;
  for (size_t i = 1; i < fields.size(); ++i) {
    const auto& f = fields[i];
    const auto eq = f.find('=');
    const std::string key = f.substr(0, eq), value = eq == std::string::npos ? "" : f.substr(eq + 1);
    if (key == "default") {
      def_text = value;
      has_def = true;
    } else if (key == "type" && value == "bool") {
      p.is_bool = true;
    } else if (key == "requires" && allow_requires && is_identifier(value)) {
      p.requires_bool = value;
    } else if (key == "range") {
      auto lohi = split_list(value, ',');
      if (lohi.size() != 2 || !parse_finite(lohi[0], p.lo) || !parse_finite(lohi[1], p.hi) || p.lo > p.hi ||
          !fits_float(p.lo) || !fits_float(p.hi))
        fail("range of " + p.name + " must be two finite numbers LO,HI with LO <= HI, each within a float's "
             "range (|x| <= 3.4e38: the shader reads a float)");
      has_range = true;
    } else {
      fail("unknown field \"" + f + "\" of parameter " + p.name);
    }
  }
  if (!has_def) fail("parameter " + p.name + " has no default");
  if (!has_range && (def_text == "true" || def_text == "false")) p.is_bool = true;
  if (p.is_bool) {
    if (has_range) fail("a bool parameter (" + p.name + ") has no range");
    if (def_text != "true" && def_text != "false") fail("default of bool " + p.name + " must be true or false");
    p.def = def_text == "true" ? 1.0 : 0.0;
    p.lo = 0.0;
    p.hi = 1.0;
  } else {
    if (!has_range) fail("parameter " + p.name + " has no range");
    if (!parse_finite(def_text, p.def) || p.def < p.lo || p.def > p.hi)
      fail("default of " + p.name + " must be a number in its range");
  }
  return p;
}

namespace {

// Qualifiers and the opaque types by their GLSL names: resources of its own (the driver would read a
// binding the pipeline does not have, or crash on a set it does not know), work-group memory, or
// leaving the pipeline's control flow (discard).
std::string forbidden_token(const std::string& t) {
  static const std::set<std::string> words = {"layout", "uniform", "buffer", "shared", "discard", "barrier",
                                              "atomic_uint", "subpassInput", "subpassInputMS",
                                              "accelerationStructureEXT", "rayQueryEXT", "demote"};
  static const std::regex opaque("[iu]?(sampler|image|texture)(1D|2D|3D|Cube|2DRect|Buffer|2DMS)?(Array)?(Shadow)?");
  if (words.count(t)) return t;
  if (std::regex_match(t, opaque)) return t;
  return "";
}

// The line of `text` where `token` first stands as a word, or 0 (it came from a macro or an include).
int line_of_word(const std::string& text, const std::string& token) {
  const std::regex word("\\b" + token + "\\b");
  std::smatch m;
  if (!std::regex_search(text, m, word)) return 0;
  return int(std::count(text.begin(), text.begin() + m.position(0), '\n')) + 1;
}

}  // namespace

void refuse_what_a_user_shader_may_not_declare(const std::string& path, const std::string& text, const std::string& what,
                                               const std::string& data_hint, const std::vector<std::string>& defines) {
  std::string expanded;
  try {
    expanded = default_shader_compiler().preprocess(path, ShaderStage::Compute, defines);
  } catch (const ShaderCompileError&) {
    return;  // a preprocessing error is the compiler's to report, with its line
  }
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  for (auto it = std::sregex_iterator(expanded.begin(), expanded.end(), identifier); it != std::sregex_iterator(); ++it) {
    const std::string bad = forbidden_token(it->str());
    if (bad.empty()) continue;
    const int line = line_of_word(text, bad);
    throw ConfigError(path + (line ? ":" + std::to_string(line) : std::string()) + ": a " + what + " may not use \"" +
                      bad + "\" (" + (bad == "discard" || bad == "demote" ? "it may not leave the pipeline's control flow"
                                       : bad == "barrier" || bad == "shared" ? "it has no work group"
                                       : "it may not declare resources of its own: " + data_hint) +
                      "); glintlab runs it inside its own shaders");
  }
}

}  // namespace glintlab::core

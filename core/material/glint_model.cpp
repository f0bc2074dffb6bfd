#include "core/material/glint_model.h"

#include "core/util/strings.h"

#include "core/util/content_hash.h"
#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <set>
#include <regex>
#include <sstream>

namespace glintlab::core {

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  if (std::optional<std::string> text = read_text_file(p)) return *text;
  throw ConfigError(p.string() + ": cannot read the glint model file");
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  return out;
}

bool parse_double(const std::string& s, double& v) {
  if (s.empty()) return false;
  std::istringstream in(s);
  in >> v;
  return in && in.peek() == std::char_traits<char>::eof() && std::isfinite(v);
}

// A value the shader's float holds as a finite number.
bool fits_float(double x) { return std::isfinite(x) && std::fabs(x) <= double(std::numeric_limits<float>::max()); }

// "" when `n` may name a parameter, else why not. A parameter is a float field of GlintQuery named
// as declared and a key of the material's "glints": it must be lower_snake_case (upper case names are
// the shaders' macros, which the preprocessor would expand inside the struct), not a GLSL keyword or
// reserved word, not one of GlintQuery's own fields and not one of glintlab's common "glints" keys
// (one JSON value would set both).
std::string parameter_name_problem(const std::string& n) {
  static const std::set<std::string> reserved = {
      // GLSL 4.60 keywords (types included) and the words reserved for future use
      "attribute", "const", "uniform", "varying", "buffer", "shared", "coherent", "volatile", "restrict",
      "readonly", "writeonly", "atomic_uint", "layout", "centroid", "flat", "smooth", "noperspective", "patch",
      "sample", "invariant", "precise", "break", "continue", "do", "for", "while", "switch", "case", "default",
      "if", "else", "subroutine", "in", "out", "inout", "int", "void", "bool", "true", "false", "float", "double",
      "discard", "return", "uint", "lowp", "mediump", "highp", "precision", "struct", "common", "partition",
      "active", "asm", "class", "union", "enum", "typedef", "template", "this", "resource", "goto", "inline",
      "noinline", "public", "static", "extern", "external", "interface", "long", "short", "half", "fixed",
      "unsigned", "superp", "input", "output", "filter", "sizeof", "cast", "namespace", "using", "demote",
      // GlintQuery's own fields (glint/query.glsl)
      "uv", "duv_dx", "duv_dy", "wi", "wo", "h", "dh_dx", "dh_dy", "alpha_g", "alpha_l", "density", "sun_cone",
      "rough",
      // glintlab's common "glints" keys (core/material/sand_material.h)
      "log_density", "relative_roughness", "intensity", "light_cone"};
  static const std::regex snake("[a-z][a-z0-9_]*");
  static const std::regex type_name("([biud]?vec[234]|d?mat[234](x[234])?|[iu]?(sampler|image|texture)\\w*)");
  if (!std::regex_match(n, snake))
    return "parameter name \"" + n + "\" must be lower_snake_case (a-z, 0-9, _; upper case names are macros)";
  if (n.rfind("gl_", 0) == 0 || reserved.count(n) || std::regex_match(n, type_name))
    return "parameter name \"" + n + "\" is a GLSL keyword or reserved word, a GlintQuery field or a common " +
           "\"glints\" key; give the parameter another name";
  return "";
}

const char* kModelSyntax =
    "// glint_model truth=self|grains limit=beckmann|ggx checks=finite,unbiased,limit,deterministic "
    "[fails=CHECK,...]";
const char* kTableSyntax = "// glint_table size=N  (1 <= N <= 2097152 floats)";
const char* kParameterSyntax =
    "// glint_parameter NAME default=VALUE range=LO,HI  or  // glint_parameter NAME default=true|false type=bool";

}  // namespace

std::vector<std::string> glint_check_names() { return {"finite", "unbiased", "limit", "deterministic"}; }

const GlintParameter* GlintModelDecl::parameter(const std::string& n) const {
  for (const auto& p : parameters)
    if (p.name == n) return &p;
  return nullptr;
}

GlintModelDecl parse_glint_model(const std::string& name, const std::string& where, const std::string& text) {
  GlintModelDecl d;
  d.name = name;
  d.content_hash = ContentHash().add(std::string_view(text)).hex();
  bool declared = false;
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;  // a UTF-8 byte-order mark before the first line
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what, const char* syntax) {
    throw ConfigError(where + ":" + std::to_string(line_no) + ": " + what + "; expected " + syntax);
  };
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream words(line);
    std::string slashes, kind;
    words >> slashes >> kind;
    if (slashes != "//" || (kind != "glint_model" && kind != "glint_parameter" && kind != "glint_table")) continue;
    std::vector<std::string> fields;
    for (std::string w; words >> w;) fields.push_back(w);
    if (kind == "glint_model") {
      if (declared) fail("a second glint_model line", kModelSyntax);
      declared = true;
      for (const auto& f : fields) {
        auto eq = f.find('=');
        std::string key = f.substr(0, eq), value = eq == std::string::npos ? "" : f.substr(eq + 1);
        if (key == "truth" && !value.empty()) {
          d.truth = value;
        } else if (key == "limit" && (value == "beckmann" || value == "ggx")) {
          d.limit = value;
        } else if ((key == "checks" || key == "fails") && !value.empty()) {
          std::vector<std::string>& list = key == "checks" ? d.checks : d.fails;
          list = split(value, ',');
          auto all = glint_check_names();
          for (const auto& c : list)
            if (std::find(all.begin(), all.end(), c) == all.end())
              fail("unknown check \"" + c + "\" (allowed: finite, unbiased, limit, deterministic)", kModelSyntax);
        } else {
          fail("unknown or empty field \"" + f + "\" (limit: beckmann or ggx)", kModelSyntax);
        }
      }
    } else if (kind == "glint_table") {
      double n = 0.0;
      if (d.table_size != 0) fail("a second glint_table line", kTableSyntax);
      if (fields.size() != 1 || fields[0].rfind("size=", 0) != 0 || !parse_double(fields[0].substr(5), n) ||
          n < 1.0 || n > double(kMaxGlintTableSize) || n != std::floor(n))
        fail("the table size must be a whole number of floats in range", kTableSyntax);
      d.table_size = uint32_t(n);
    } else {
      if (fields.empty() || !is_identifier(fields[0])) fail("a parameter needs a GLSL identifier as its name", kParameterSyntax);
      if (const std::string why = parameter_name_problem(fields[0]); !why.empty()) fail(why, kParameterSyntax);
      GlintParameter p;
      p.name = fields[0];
      bool has_def = false, has_range = false;
      std::string def_text;
      for (size_t i = 1; i < fields.size(); ++i) {
        const auto& f = fields[i];
        auto eq = f.find('=');
        std::string key = f.substr(0, eq), value = eq == std::string::npos ? "" : f.substr(eq + 1);
        if (key == "default") {
          def_text = value;
          has_def = true;
        } else if (key == "type" && value == "bool") {
          p.is_bool = true;
        } else if (key == "range") {
          auto lohi = split(value, ',');
          if (lohi.size() != 2 || !parse_double(lohi[0], p.lo) || !parse_double(lohi[1], p.hi) || p.lo > p.hi ||
              !fits_float(p.lo) || !fits_float(p.hi))
            fail("range of " + p.name + " must be two finite numbers LO,HI with LO <= HI, each within a float's "
                 "range (|x| <= 3.4e38: the shader reads a float)", kParameterSyntax);
          has_range = true;
        } else {
          fail("unknown field \"" + f + "\" of parameter " + p.name, kParameterSyntax);
        }
      }
      if (!has_def) fail("parameter " + p.name + " has no default", kParameterSyntax);
      if (p.is_bool) {
        if (has_range) fail("a bool parameter (" + p.name + ") has no range", kParameterSyntax);
        if (def_text != "true" && def_text != "false") fail("default of bool " + p.name + " must be true or false", kParameterSyntax);
        p.def = def_text == "true" ? 1.0 : 0.0;
        p.lo = 0.0;
        p.hi = 1.0;
      } else {
        if (!has_range) fail("parameter " + p.name + " has no range", kParameterSyntax);
        if (!parse_double(def_text, p.def) || p.def < p.lo || p.def > p.hi)
          fail("default of " + p.name + " must be a number in its range", kParameterSyntax);
      }
      if (d.parameter(p.name)) fail("parameter " + p.name + " declared twice", kParameterSyntax);
      d.parameters.push_back(p);
      if (d.parameters.size() > kMaxGlintParameters)
        fail("more than " + std::to_string(kMaxGlintParameters) + " parameters", kParameterSyntax);
    }
  }
  if (!declared)
    throw ConfigError(where + ": no glint_model declaration line; expected a comment line " + kModelSyntax);
  for (const auto& c : d.fails)
    if (std::find(d.checks.begin(), d.checks.end(), c) != d.checks.end())
      throw ConfigError(where + ": check \"" + c + "\" is both in checks= and in fails=; expected " + kModelSyntax);
  return d;
}

namespace {

// What a model's code may not declare or do: resources of its own (the driver would read a binding the
// pipeline does not have, or crash on a set it does not know), work-group memory, or leave the
// pipeline's control flow (discard). Qualifiers, and the opaque types by their GLSL names.
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

// A user's model file, preprocessed as glintlab compiles it (its includes resolved, its macros
// expanded: a "#define B buffer" hides nothing), must not declare resources, work-group memory or
// discard. ConfigError naming the file, the line where the word stands (when it does) and why.
void refuse_what_a_model_may_not_declare(const std::string& path, const std::string& text) {
  std::string expanded;
  try {
    expanded = default_shader_compiler().preprocess(path, ShaderStage::Compute);
  } catch (const ShaderCompileError&) {
    return;  // a preprocessing error is the compiler's to report, with its line
  }
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  for (auto it = std::sregex_iterator(expanded.begin(), expanded.end(), identifier); it != std::sregex_iterator(); ++it) {
    const std::string bad = forbidden_token(it->str());
    if (bad.empty()) continue;
    const int line = line_of_word(text, bad);
    throw ConfigError(path + (line ? ":" + std::to_string(line) : std::string()) + ": a glint model may not use \"" +
                      bad + "\" (" + (bad == "discard" || bad == "demote" ? "it may not leave the pipeline's control flow"
                                       : bad == "barrier" || bad == "shared" ? "it has no work group"
                                       : "it may not declare resources of its own: its data comes through "
                                         "\"// glint_table size=N\" and glint_table_entry") +
                      "); glintlab runs it inside its own shaders");
  }
}

}  // namespace

GlintModelDecl glint_model_from_file(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw ConfigError(path + ": glint model file not found (a GLSL file with a glint_model declaration line)");
  const std::string text = read_text(path);
  GlintModelDecl d = parse_glint_model(path, path, text);
  refuse_what_a_model_may_not_declare(fs::absolute(path).lexically_normal().string(), text);
  d.file = fs::absolute(path).lexically_normal().string();
  d.builtin = false;
  if (d.truth != "self") {
    const GlintModelDecl* t = find_builtin_glint_model(d.truth);
    if (!t || t->truth != "self") {
      std::string allowed = "\"self\"";
      for (const auto& m : builtin_glint_models())
        if (m.truth == "self") allowed += ", \"" + m.name + "\"";
      throw ConfigError(path + ": truth=" + d.truth + " is not allowed; allowed " + allowed);
    }
  }
  return d;
}

const std::vector<GlintModelDecl>& builtin_glint_models() {
  static std::vector<GlintModelDecl> models;
  static std::once_flag once;
  std::call_once(once, [] {
    fs::path dir = fs::path(default_shader_compiler().shader_dir()) / "glint" / "models";
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.is_regular_file() && e.path().extension() == ".glsl") files.push_back(e.path());
    if (ec || files.empty()) throw ConfigError(dir.string() + ": no glint model files (*.glsl) found");
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::string name = f.stem().string();
      if (name == kGlintModelKajs || name == kGlintModelNone || !is_identifier(name))
        throw ConfigError(f.string() + ": a built-in glint model needs a GLSL identifier as its file name other than "
                          "\"kajs\" and \"none\"");
      GlintModelDecl d = parse_glint_model(name, f.string(), read_text(f));
      d.file = "glint/models/" + f.filename().string();
      d.builtin = true;
      models.push_back(std::move(d));
    }
    for (const auto& m : models) {
      const GlintModelDecl* t = nullptr;
      for (const auto& o : models)
        if (o.name == m.truth) t = &o;
      if (m.truth != "self" && (!t || t->truth != "self"))
        throw ConfigError(dir.string() + "/" + m.name + ".glsl: truth=" + m.truth +
                          " is neither \"self\" nor a built-in model whose truth is \"self\"");
    }
  });
  return models;
}

const GlintModelDecl* find_builtin_glint_model(const std::string& name) {
  for (const auto& m : builtin_glint_models())
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<std::string> glint_model_names() {
  std::vector<std::string> out{kGlintModelKajs};
  for (const auto& m : builtin_glint_models()) out.push_back(m.name);
  out.push_back(kGlintModelNone);
  return out;
}

uint32_t glint_model_gpu_id(const std::string& name) {
  if (name == kGlintModelNone) return 0u;
  if (name == kGlintModelKajs) return 1u;
  const auto& models = builtin_glint_models();
  for (size_t i = 0; i < models.size(); ++i)
    if (models[i].name == name) return uint32_t(2 + i);
  return uint32_t(2 + models.size());
}

}  // namespace glintlab::core

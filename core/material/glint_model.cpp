#include "core/material/glint_model.h"

#include "core/util/strings.h"

#include "core/util/content_hash.h"
#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/user_shader.h"

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

// GlintQuery's own fields (glint/query.glsl) and glintlab's common "glints" keys
// (core/material/sand_material.h): a parameter may not take these names (one JSON value would set both).
const std::set<std::string>& reserved_parameter_names() {
  static const std::set<std::string> names = {"uv",      "duv_dx",  "duv_dy",  "wi",          "wo",
                                              "h",       "dh_dx",   "dh_dy",   "alpha_g",     "alpha_l",
                                              "density", "sun_cone", "rough",  "log_density", "relative_roughness",
                                              "intensity", "light_cone"};
  return names;
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
          list = split_list(value, ',');
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
      if (fields.size() != 1 || fields[0].rfind("size=", 0) != 0 || !parse_finite(fields[0].substr(5), n) ||
          n < 1.0 || n > double(kMaxGlintTableSize) || n != std::floor(n))
        fail("the table size must be a whole number of floats in range", kTableSyntax);
      d.table_size = uint32_t(n);
    } else {
      const DeclaredParameter dp = parse_declared_parameter(fields, reserved_parameter_names(), false,
                                                            [&](const std::string& why) { fail(why, kParameterSyntax); });
      GlintParameter p;
      p.name = dp.name;
      p.def = dp.def;
      p.lo = dp.lo;
      p.hi = dp.hi;
      p.is_bool = dp.is_bool;
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

GlintModelDecl glint_model_from_file(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw ConfigError(path + ": glint model file not found (a GLSL file with a glint_model declaration line)");
  const std::string text = read_text(path);
  GlintModelDecl d = parse_glint_model(path, path, text);
  refuse_what_a_user_shader_may_not_declare(fs::absolute(path).lexically_normal().string(), text, "glint model",
                                            "its data comes through \"// glint_table size=N\" and glint_table_entry");
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

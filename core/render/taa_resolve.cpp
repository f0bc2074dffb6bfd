#include "core/render/taa_resolve.h"

#include "core/util/content_hash.h"
#include "core/util/json_check.h"
#include "core/util/strings.h"
#include "core/vk/shader_compiler.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace glintlab::core {

namespace fs = std::filesystem;

namespace {

// The interface header beside the built-in resolves is no resolve.
constexpr const char* kInterfaceFile = "interface.glsl";
constexpr const char* kTaaDir = "taa";

// TaaPixel's own fields and the "taa" object's other keys: no parameter or option takes these names.
const std::set<std::string>& reserved_names() {
  static const std::set<std::string> names = {"pixel", "history_valid", "jitter", "jitter_prev", "frame",
                                              "name",  "file",          "parameters"};
  return names;
}

const char* kResolveSyntax =
    "// taa_resolve checks=finite,deterministic,converges,ghosting,cut,pan,flicker [fails=CHECK,...] [extends=BUILT-IN]";
const char* kParameterSyntax =
    "// taa_parameter NAME default=VALUE range=LO,HI [requires=BOOL]  or  // taa_parameter NAME default=true|false";
const char* kOptionSyntax = "// taa_option NAME=a|b|c default=a [requires=BOOL]  (names lower_snake_case)";

std::string read_text(const fs::path& p) {
  if (std::optional<std::string> text = read_text_file(p)) return *text;
  throw ConfigError(p.string() + ": cannot read the TAA resolve file");
}

// requires= names a bool parameter; the macros of two declarations may not coincide (option x choice
// y_z and option x_y choice z both give TAA_x_y_z). ConfigError naming `where`.
void check_declaration(const TaaResolveDecl& d, const std::string& where) {
  std::set<std::string> macros;
  auto macro = [&](const std::string& m, const std::string& what) {
    if (!macros.insert(m).second)
      throw ConfigError(where + ": " + what + " gives the macro " + m + " a second time; rename it");
  };
  auto check_requires = [&](const std::string& who, const std::string& req) {
    if (req.empty()) return;
    const DeclaredParameter* r = d.parameter(req);
    if (!r || !r->is_bool || req == who)
      throw ConfigError(where + ": " + who + " requires=" + req + ", which is no other bool parameter of the file");
  };
  for (const auto& p : d.parameters) {
    check_requires(p.name, p.requires_bool);
    macro("TAA_ON_" + p.name, "parameter " + p.name);
  }
  for (const auto& o : d.options) {
    check_requires(o.name, o.requires_bool);
    macro("TAA_" + o.name, "option " + o.name);
    for (const auto& c : o.choices) macro("TAA_" + o.name + "_" + c, "option " + o.name + " choice " + c);
  }
}

// The parameters and options of `parent` first, then the file's own (a name declared twice is an error).
void inherit(TaaResolveDecl& d, const TaaResolveDecl& parent, const std::string& where) {
  if (!parent.extends.empty())
    throw ConfigError(where + ": extends=" + parent.name + ", which itself extends " + parent.extends +
                      " (one level only)");
  std::vector<DeclaredParameter> params = parent.parameters;
  std::vector<TaaOption> options = parent.options;
  for (const auto& p : d.parameters) {
    if (parent.parameter(p.name) || parent.option(p.name))
      throw ConfigError(where + ": \"" + p.name + "\" is declared by " + parent.name + " already");
    params.push_back(p);
  }
  for (const auto& o : d.options) {
    if (parent.parameter(o.name) || parent.option(o.name))
      throw ConfigError(where + ": \"" + o.name + "\" is declared by " + parent.name + " already");
    options.push_back(o);
  }
  if (params.size() > kMaxTaaParameters)
    throw ConfigError(where + ": more than " + std::to_string(kMaxTaaParameters) + " parameters with " + parent.name + "'s");
  d.parameters = std::move(params);
  d.options = std::move(options);
  check_declaration(d, where);
}

}  // namespace

std::vector<std::string> taa_check_names() {
  return {"finite", "deterministic", "converges", "ghosting", "cut", "pan", "flicker"};
}

const DeclaredParameter* TaaResolveDecl::parameter(const std::string& n) const {
  for (const auto& p : parameters)
    if (p.name == n) return &p;
  return nullptr;
}

const TaaOption* TaaResolveDecl::option(const std::string& n) const {
  for (const auto& o : options)
    if (o.name == n) return &o;
  return nullptr;
}

TaaResolveDecl parse_taa_resolve(const std::string& name, const std::string& where, const std::string& text) {
  TaaResolveDecl d;
  d.name = name;
  d.content_hash = ContentHash().add(std::string_view(text)).hex();
  bool declared = false;
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what, const char* syntax) {
    throw ConfigError(where + ":" + std::to_string(line_no) + ": " + what + "; expected " + syntax);
  };
  auto taken = [&](const std::string& n) { return d.parameter(n) || d.option(n); };
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream words(line);
    std::string slashes, kind;
    words >> slashes >> kind;
    if (slashes != "//" || (kind != "taa_resolve" && kind != "taa_parameter" && kind != "taa_option")) continue;
    std::vector<std::string> fields;
    for (std::string w; words >> w;) fields.push_back(w);
    if (kind == "taa_resolve") {
      if (declared) fail("a second taa_resolve line", kResolveSyntax);
      declared = true;
      for (const auto& f : fields) {
        const auto eq = f.find('=');
        const std::string key = f.substr(0, eq), value = eq == std::string::npos ? "" : f.substr(eq + 1);
        if ((key == "checks" || key == "fails") && !value.empty()) {
          std::vector<std::string>& list = key == "checks" ? d.checks : d.fails;
          list = split_list(value, ',');
          const auto all = taa_check_names();
          for (const auto& c : list)
            if (std::find(all.begin(), all.end(), c) == all.end())
              fail("unknown check \"" + c + "\" (allowed: " + join(all) + ")", kResolveSyntax);
        } else if (key == "extends" && is_identifier(value)) {
          d.extends = value;
        } else {
          fail("unknown or empty field \"" + f + "\"", kResolveSyntax);
        }
      }
    } else if (kind == "taa_parameter") {
      const DeclaredParameter p = parse_declared_parameter(fields, reserved_names(), true,
                                                           [&](const std::string& why) { fail(why, kParameterSyntax); });
      if (taken(p.name)) fail("\"" + p.name + "\" declared twice", kParameterSyntax);
      d.parameters.push_back(p);
      if (d.parameters.size() > kMaxTaaParameters)
        fail("more than " + std::to_string(kMaxTaaParameters) + " parameters", kParameterSyntax);
    } else {
      if (fields.empty()) fail("an option needs NAME=a|b|...", kOptionSyntax);
      const auto eq = fields[0].find('=');
      TaaOption o;
      o.name = fields[0].substr(0, eq);
      if (const std::string why = parameter_name_problem(o.name, reserved_names()); !why.empty())
        fail(why, kOptionSyntax);
      if (eq == std::string::npos) fail("option " + o.name + " lists no choices", kOptionSyntax);
      o.choices = split_list(fields[0].substr(eq + 1), '|');
      static const std::regex snake("[a-z][a-z0-9_]*");
      std::set<std::string> seen;
      for (const auto& c : o.choices)
        if (!std::regex_match(c, snake) || !seen.insert(c).second)
          fail("option " + o.name + ": choice \"" + c + "\" is not lower_snake_case or is listed twice", kOptionSyntax);
      if (o.choices.size() < 2) fail("option " + o.name + " needs at least two choices", kOptionSyntax);
      bool has_def = false;
      for (size_t i = 1; i < fields.size(); ++i) {
        const auto e = fields[i].find('=');
        const std::string key = fields[i].substr(0, e), value = e == std::string::npos ? "" : fields[i].substr(e + 1);
        if (key == "default") {
          const auto it = std::find(o.choices.begin(), o.choices.end(), value);
          if (it == o.choices.end()) fail("default of option " + o.name + " must be one of its choices", kOptionSyntax);
          o.def = size_t(it - o.choices.begin());
          has_def = true;
        } else if (key == "requires" && is_identifier(value)) {
          o.requires_bool = value;
        } else {
          fail("unknown field \"" + fields[i] + "\" of option " + o.name, kOptionSyntax);
        }
      }
      if (!has_def) fail("option " + o.name + " has no default", kOptionSyntax);
      if (taken(o.name)) fail("\"" + o.name + "\" declared twice", kOptionSyntax);
      d.options.push_back(o);
    }
  }
  if (!declared)
    throw ConfigError(where + ": no taa_resolve declaration line; expected a comment line " + kResolveSyntax);
  for (const auto& c : d.fails)
    if (std::find(d.checks.begin(), d.checks.end(), c) != d.checks.end())
      throw ConfigError(where + ": check \"" + c + "\" is both in checks= and in fails=; expected " + kResolveSyntax);
  if (d.extends.empty()) check_declaration(d, where);
  return d;
}

TaaResolveDecl taa_resolve_from_file(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw ConfigError(path + ": TAA resolve file not found (a GLSL file with a taa_resolve declaration line)");
  const std::string text = read_text(path);
  TaaResolveDecl d = parse_taa_resolve(path, path, text);
  if (!d.extends.empty()) {
    const TaaResolveDecl* parent = find_builtin_taa_resolve(d.extends);
    if (!parent)
      throw ConfigError(path + ": extends=" + d.extends + " is no built-in resolve (allowed: " +
                        join(taa_resolve_names()) + ")");
    inherit(d, *parent, path);
  }
  d.file = fs::absolute(path).lexically_normal().string();
  d.builtin = false;
  // Every choice of every option could be compiled: scan the file as each default compiles it (what the
  // options switch is checked again when settings are compiled, TaaSettings::uses).
  refuse_what_a_user_shader_may_not_declare(d.file, text, "TAA resolve",
                                            "its data comes through the taa_* accessors of the interface",
                                            TaaSettings(d).defines());
  return d;
}

const std::vector<TaaResolveDecl>& builtin_taa_resolves() {
  static std::vector<TaaResolveDecl> resolves;
  static std::once_flag once;
  std::call_once(once, [] {
    const fs::path dir = fs::path(default_shader_compiler().shader_dir()) / kTaaDir;
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.is_regular_file() && e.path().extension() == ".glsl" && e.path().filename() != kInterfaceFile)
        files.push_back(e.path());
    if (ec || files.empty()) throw ConfigError(dir.string() + ": no TAA resolve files (*.glsl) found");
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const std::string name = f.stem().string();
      if (!is_identifier(name))
        throw ConfigError(f.string() + ": a built-in TAA resolve needs a GLSL identifier as its file name");
      TaaResolveDecl d = parse_taa_resolve(name, f.string(), read_text(f));
      d.file = std::string(kTaaDir) + "/" + f.filename().string();
      d.builtin = true;
      resolves.push_back(std::move(d));
    }
    for (auto& r : resolves) {
      if (r.extends.empty()) continue;
      const auto parent = std::find_if(resolves.begin(), resolves.end(), [&](const auto& o) { return o.name == r.extends; });
      if (parent == resolves.end())
        throw ConfigError(dir.string() + "/" + r.name + ".glsl: extends=" + r.extends + " is no built-in resolve");
      inherit(r, *parent, dir.string() + "/" + r.name + ".glsl");
    }
  });
  return resolves;
}

const TaaResolveDecl* find_builtin_taa_resolve(const std::string& name) {
  for (const auto& r : builtin_taa_resolves())
    if (r.name == name) return &r;
  return nullptr;
}

std::vector<std::string> taa_resolve_names() {
  std::vector<std::string> out;
  for (const auto& r : builtin_taa_resolves()) out.push_back(r.name);
  return out;
}

// ---- settings

TaaSettings::TaaSettings() {
  const TaaResolveDecl* d = find_builtin_taa_resolve(kTaaDefaultResolve);
  if (!d) throw ConfigError(std::string("shaders/taa/") + kTaaDefaultResolve + ".glsl: the default TAA resolve is missing");
  *this = TaaSettings(*d);
}

TaaSettings::TaaSettings(const TaaResolveDecl& decl) : resolve(std::make_shared<const TaaResolveDecl>(decl)) {
  for (const auto& p : decl.parameters) values.push_back(p.def);
  for (const auto& o : decl.options) choices.push_back(o.def);
}

namespace {
[[noreturn]] void unknown(const TaaResolveDecl& d, const std::string& name) {
  std::vector<std::string> all;
  for (const auto& p : d.parameters) all.push_back(p.name);
  for (const auto& o : d.options) all.push_back(o.name);
  throw std::invalid_argument("TAA resolve " + d.name + " has no parameter or option \"" + name + "\" (it has " +
                              join(all) + ")");
}
}  // namespace

double TaaSettings::value(const std::string& name) const {
  for (size_t i = 0; i < resolve->parameters.size(); ++i)
    if (resolve->parameters[i].name == name) return values[i];
  unknown(*resolve, name);
}

const std::string& TaaSettings::option(const std::string& name) const {
  for (size_t i = 0; i < resolve->options.size(); ++i)
    if (resolve->options[i].name == name) return resolve->options[i].choices[choices[i]];
  unknown(*resolve, name);
}

TaaSettings& TaaSettings::set(const std::string& name, double v) {
  for (size_t i = 0; i < resolve->parameters.size(); ++i) {
    const DeclaredParameter& p = resolve->parameters[i];
    if (p.name != name) continue;
    if (!(v >= p.lo && v <= p.hi) || (p.is_bool && v != 0.0 && v != 1.0))
      throw std::invalid_argument("TAA resolve " + resolve->name + ": " + name + " = " + std::to_string(v) +
                                  " is out of range [" + std::to_string(p.lo) + ", " + std::to_string(p.hi) + "]");
    values[i] = v;
    return *this;
  }
  unknown(*resolve, name);
}

TaaSettings& TaaSettings::set(const std::string& name, const std::string& choice) {
  for (size_t i = 0; i < resolve->options.size(); ++i) {
    const TaaOption& o = resolve->options[i];
    if (o.name != name) continue;
    const auto it = std::find(o.choices.begin(), o.choices.end(), choice);
    if (it == o.choices.end())
      throw std::invalid_argument("TAA resolve " + resolve->name + ": " + name + " = \"" + choice + "\" (allowed: " +
                                  join(o.choices) + ")");
    choices[i] = size_t(it - o.choices.begin());
    return *this;
  }
  unknown(*resolve, name);
}

std::vector<std::string> TaaSettings::defines() const {
  const TaaResolveDecl& d = *resolve;
  std::vector<std::string> out = {std::string(kIncludeAliasPrefix) + "TAA_RESOLVE_FILE=" + d.file};
  std::string fields, assign;
  for (size_t i = 0; i < d.parameters.size(); ++i) {
    const DeclaredParameter& p = d.parameters[i];
    out.push_back("TAA_ON_" + p.name + "=" + (values[i] != 0.0 ? "1" : "0"));
    const std::string v = "taa_parameter_value(" + std::to_string(i) + ")";
    fields += (p.is_bool ? "bool " : "float ") + p.name + "; ";
    assign += "p." + p.name + " = " + (p.is_bool ? v + " != 0.0" : v) + "; ";
  }
  out.push_back("TAA_PARAMETER_FIELDS=" + fields);
  out.push_back("TAA_PARAMETER_VALUES=" + assign);
  for (size_t i = 0; i < d.options.size(); ++i) {
    const TaaOption& o = d.options[i];
    out.push_back("TAA_" + o.name + "=" + std::to_string(choices[i]));
    for (size_t c = 0; c < o.choices.size(); ++c) out.push_back("TAA_" + o.name + "_" + o.choices[c] + "=" + std::to_string(c));
  }
  return out;
}

TaaUses TaaSettings::uses() const {
  // The file alone, as these settings compile it, at and below the output resolution (the host's
  // TAA_RENDER_SCALED): an accessor named in code the options compile out is not used.
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  std::set<std::string> words;
  for (const char* scaled : {"TAA_RENDER_SCALED=0", "TAA_RENDER_SCALED=1"}) {
    std::vector<std::string> d = defines();
    d.push_back(scaled);
    const std::string text = default_shader_compiler().preprocess(resolve->file, ShaderStage::Fragment, d);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), identifier); it != std::sregex_iterator(); ++it)
      words.insert(it->str());
  }
  TaaUses u;
  u.motion = words.count("taa_motion") || words.count("taa_distance") || words.count("taa_distance_prev") ||
             words.count("taa_render_motion") || words.count("taa_render_distance") ||
             words.count("taa_render_distance_prev");
  u.glint = words.count("taa_glint") || words.count("taa_render_glint");
  u.state = words.count("taa_state");
  u.state2 = words.count("taa_state2");
  u.history2 = words.count("taa_history2");
  return u;
}

nlohmann::json TaaSettings::to_json() const {
  const TaaResolveDecl& d = *resolve;
  nlohmann::json j = {{"jitter", enum_name(kJitterNames, jitter)}};
  if (d.builtin) {
    j["name"] = d.name;
  } else {
    j["file"] = d.file;
    j["hash"] = d.content_hash;
  }
  for (size_t i = 0; i < d.parameters.size(); ++i) {
    if (d.parameters[i].is_bool)
      j[d.parameters[i].name] = values[i] != 0.0;
    else
      j[d.parameters[i].name] = values[i];
  }
  for (size_t i = 0; i < d.options.size(); ++i) j[d.options[i].name] = d.options[i].choices[choices[i]];
  return j;
}

}  // namespace glintlab::core

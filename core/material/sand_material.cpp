#include "core/material/sand_material.h"

#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"

#include <algorithm>
#include <filesystem>

#include <cmath>
#include <sstream>

namespace glintlab::core {

namespace {

const std::vector<std::string> kColourSpaces = {"lin_rec709", "ACEScg", "ACES2065-1", "sRGB"};
const std::vector<std::string> kFresnelHalfVectors = {"macro_normal", "light_view"};
const double kPi = 3.14159265358979323846;

struct Range {
  const char* name;
  double lo, hi;
};
// One table for validate() and from_json() so the two cannot disagree.
const Range kSSS{"SSS", 0, 1}, kRs{"R_s", 0, 1}, kT{"T", 0, 1}, kRt{"R_t", 0, 1},
    kSigmaG{"glint_sigma", 1e-6, 1}, kP{"P", 0, 1}, kNoise{"noise_scale", 1, 1e6},
    kScatter{"scattering", 0, 1}, kAbsorb{"absorption", 0, 1}, kSigmaON{"oren_nayar_sigma", 0, kPi / 2},
    kSigA{"sigmoid_a", 1e-6, 1e4}, kSigB{"sigmoid_b", 0, 1e7}, kIor{"ior", 1, 3}, kColour{"palette", 0, 1e3},
    kGlintGain{"I_glints", 0, 1e6};
// "glints" (Zirr & Kaplanyan 2016 sec. 4.5); names as the JSON keys inside "glints"
// log_density from -3 (one microdetail per 1000 uv units: sparser than any mesh) to 14
const Range kLogDensity{"log_density", -3, 14}, kAlphaG{"alpha_g", 1e-3, 1},
    kRelRough{"relative_roughness", 1e-3, 1}, kIntensity{"intensity", 0, 1e6}, kLightCone{"light_cone", 0, 0.5};

// "specular_aa" (sand/specular_aa.glsl): sigma^2 up to 4 (a pixel filter 2 px wide), kappa up to 1
const Range kSpecSigma2{"specular_aa.sigma2", 1e-6, 4}, kSpecKappa{"specular_aa.kappa", 1e-6, 1};

}  // namespace

const std::vector<std::string>& SandSpecularAA::names() {
  static const std::vector<std::string> n{"none", "kaplanyan2016", "tokuyoshi2019", "tokuyoshi2021"};
  return n;
}

SandSpecularAA SandSpecularAA::published(const std::string& method) {
  SandSpecularAA a;
  a.method = method;
  // Kaplanyan et al. 2016: the bounding rectangle's half extent r = b / 2 (b = |dp/dx| + |dp/dy|),
  // at most 0.3, adds 2 r^2 = 2 (1/4) b^2 to alpha^2: sigma^2 = 1/4, kappa = 2 (0.3)^2.
  // Tokuyoshi & Kaplanyan 2019: sigma^2 = 0.25 (the screen-space variance), kappa = 0.18.
  // Tokuyoshi & Kaplanyan 2021: sigma^2 = 1 / (2 pi) (a Gaussian pixel filter of unit peak), kappa = 0.18.
  if (method == "kaplanyan2016" || method == "tokuyoshi2019") {
    a.sigma2 = 0.25;
    a.kappa = 0.18;
  } else if (method == "tokuyoshi2021") {
    a.sigma2 = 1.0 / (2.0 * kPi);
    a.kappa = 0.18;
  }
  return a;
}

int SandSpecularAA::define() const {
  const auto& n = names();
  return int(std::find(n.begin(), n.end(), method) - n.begin());
}

std::vector<std::string> SandParams::glint_vector_keys() { return {kAlphaG.name, kRelRough.name}; }

namespace {

std::string num(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

void check(const Range& r, double v, const std::string& suffix = "") {
  if (!std::isfinite(v) || v < r.lo || v > r.hi)
    throw ConfigError("sand: " + std::string(r.name) + suffix + " = " + num(v) + " is out of range; allowed [" +
                      num(r.lo) + ", " + num(r.hi) + "]");
}

void check_glint(const Range& r, double v, const std::string& suffix = "") {
  if (!std::isfinite(v) || v < r.lo || v > r.hi)
    throw ConfigError("sand: glints." + std::string(r.name) + suffix + " = " + num(v) + " is out of range; allowed [" +
                      num(r.lo) + ", " + num(r.hi) + "]");
}

void check_enum(const char* name, const std::string& v, const std::vector<std::string>& allowed) {
  for (const auto& a : allowed)
    if (a == v) return;
  std::string list;
  for (size_t i = 0; i < allowed.size(); ++i) list += (i ? ", \"" : "\"") + allowed[i] + "\"";
  throw ConfigError("sand: " + std::string(name) + " = \"" + v + "\" is not allowed; allowed " + list);
}

double get(JsonReader& r, const Range& range, double def) { return r.get_number(range.name, def, range.lo, range.hi); }

std::string parameter_list(const GlintModelDecl& d) {
  std::string out;
  for (const auto& p : d.parameters)
    out += (out.empty() ? "" : ", ") + p.name +
           (p.is_bool ? " (true or false)" : " [" + num(p.lo) + ", " + num(p.hi) + "]");
  return out;
}

}  // namespace

std::vector<std::string> SandParams::preset_names() { return {"thesis-default", "thesis-hdri-match", "thesis-appendix-a"}; }

SandParams SandParams::preset(const std::string& name) {
  SandParams p;  // Appendix A property defaults
  if (name == "thesis-default") return p;
  if (name == "thesis-hdri-match") {
    // Kajs 2022 sec. 6.2: Fig. 6.8 copies the Blender BSDF of Fig. 6.5 --
    // Roughness 0.300, IOR 1.458, Transmission 0.250, TransmissionRoughness
    // 0.300, BaseColor (0.895, 0.713, 0.602) for all grains, no subsurface
    // scattering. P and the noise scale are only shown in the Fig. 6.8 image:
    // Appendix A defaults are kept.
    for (auto& c : p.palette) c = {0.895, 0.713, 0.602};
    p.palette_space = "lin_rec709";  // Blender's scene-linear RGB fields
    p.SSS = 0.0;
    p.R_s = 0.3;
    p.T = 0.25;
    p.R_t = 0.3;
    p.ior = 1.458;
    return p;
  }
  if (name == "thesis-appendix-a") {
    p.appendix_compat = kSandCompatAll;
    return p;
  }
  check_enum("preset", name, preset_names());
  return p;  // unreachable
}

std::vector<std::string> SandParams::compat_names() {
  return {"rand_normalized", "intensity_xi1", "gate_xi1", "glint_sky", "fresnel_abs", "oren_nayar_world"};
}

std::vector<std::string> SandParams::debug_output_names() {
  return {"final", "diffuse",  "specular", "glints", "fresnel",
          "transmission", "far", "sigmoid",  "grain_id", "close", "glint_cells"};
}

int SandParams::debug_output_define(const std::string& name) {
  auto names = debug_output_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);  // = SAND_DEBUG_* in sand.glsl
  check_enum("debug_output", name, names);
  return 0;
}

void SandParams::validate() const {
  for (size_t i = 0; i < palette.size(); ++i)
    for (size_t c = 0; c < 3; ++c) check(kColour, palette[i][c], "[" + std::to_string(i) + "][" + std::to_string(c) + "]");
  for (size_t c = 0; c < 3; ++c) check(kGlintGain, I_glints[c], "[" + std::to_string(c) + "]");
  check(kSSS, SSS);
  check(kRs, R_s);
  check(kT, T);
  check(kRt, R_t);
  check(kSigmaG, glint_sigma);
  check(kP, P);
  check(kNoise, noise_scale);
  check(kScatter, scattering);
  check(kAbsorb, absorption);
  check(kSigmaON, oren_nayar_sigma);
  check(kSigA, sigmoid_a);
  check(kSigB, sigmoid_b);
  check(kIor, ior);
  check_enum("palette_space", palette_space, kColourSpaces);
  check_enum("fresnel_half_vector", fresnel_half_vector, kFresnelHalfVectors);
  check_glint(kLogDensity, glints.log_density);
  for (size_t a = 0; a < 2; ++a) {
    check_glint(kAlphaG, glints.alpha_g[a], "[" + std::to_string(a) + "]");
    check_glint(kRelRough, glints.relative_roughness[a], "[" + std::to_string(a) + "]");
  }
  check_glint(kIntensity, glints.intensity);
  if (glints.light_cone) check_glint(kLightCone, *glints.light_cone);
  auto names = glint_model_names();
  if (!glint_file && std::find(names.begin(), names.end(), glint_model) == names.end())
    check_enum("glint_model", glint_model, names);
  const GlintModelDecl* decl = glint_decl();
  for (const auto& [name, value] : glints.model) {
    const GlintParameter* gp = decl ? decl->parameter(name) : nullptr;
    if (!gp)
      throw ConfigError("sand: glints." + name + " is not a parameter of glint model " + glint_model +
                        (decl && !decl->parameters.empty() ? "; its parameters: " + parameter_list(*decl)
                                                           : "; it has none"));
    if (gp->is_bool && !(value == 0.0 || value == 1.0))
      throw ConfigError("sand: glints." + name + " = " + num(value) + " is not allowed; allowed true or false");
    check_glint(Range{gp->name.c_str(), gp->lo, gp->hi}, value);
  }
  check_enum("specular_aa", specular_aa.method, SandSpecularAA::names());
  if (specular_aa.on()) {
    check(kSpecSigma2, specular_aa.sigma2);
    check(kSpecKappa, specular_aa.kappa);
    if (!decl)
      throw ConfigError("sand: specular_aa = " + specular_aa.method + " needs a glint model with a roughness to widen; glint model " +
                        glint_model + " has none (allowed: a model other than kajs and none, or specular_aa none)");
  }
  if (appendix_compat & ~uint32_t(kSandCompatAll))
    throw ConfigError("sand: appendix_compat = " + std::to_string(appendix_compat) + " has unknown bits; allowed 0.." +
                      std::to_string(unsigned(kSandCompatAll)));
}

SandParams SandParams::from_json(JsonReader& r) {
  SandParams p = preset(r.get_enum("preset", "thesis-default", preset_names()));
  if (r.has("palette")) {
    const auto& j = r.raw("palette");
    if (!j.is_array() || j.size() != 8) r.fail("palette", "expected an array of 8 [r, g, b] colours");
    for (size_t i = 0; i < 8; ++i) {
      const auto& c = j[i];
      if (!c.is_array() || c.size() != 3)
        r.fail("palette", "element " + std::to_string(i) + ": expected [r, g, b] with values in [0, 1000]");
      for (size_t k = 0; k < 3; ++k) {
        if (!c[k].is_number() || !std::isfinite(c[k].get<double>()) || c[k].get<double>() < kColour.lo ||
            c[k].get<double>() > kColour.hi)
          r.fail("palette", "element " + std::to_string(i) + "[" + std::to_string(k) +
                                "]: expected a number in [0, 1000]");
        p.palette[i][k] = c[k].get<double>();
      }
    }
  }
  p.palette_space = r.get_enum("palette_space", p.palette_space, kColourSpaces);
  p.SSS = get(r, kSSS, p.SSS);
  p.R_s = get(r, kRs, p.R_s);
  p.T = get(r, kT, p.T);
  p.R_t = get(r, kRt, p.R_t);
  p.glint_sigma = get(r, kSigmaG, p.glint_sigma);
  p.P = get(r, kP, p.P);
  p.noise_scale = get(r, kNoise, p.noise_scale);
  auto ig = r.get_numbers(kGlintGain.name, std::vector<double>(p.I_glints.begin(), p.I_glints.end()), kGlintGain.lo,
                          kGlintGain.hi);
  p.I_glints = {ig[0], ig[1], ig[2]};
  p.scattering = get(r, kScatter, p.scattering);
  p.absorption = get(r, kAbsorb, p.absorption);
  p.oren_nayar_sigma = get(r, kSigmaON, p.oren_nayar_sigma);
  p.sigmoid_a = get(r, kSigA, p.sigmoid_a);
  p.sigmoid_b = get(r, kSigB, p.sigmoid_b);
  p.ior = get(r, kIor, p.ior);
  if (r.has("glint_model") && r.raw("glint_model").is_object() && r.raw("glint_model").contains("name")) {
    // a built-in model measured against another truth: {"name": model, "truth": a model whose truth is "self"}
    JsonReader g = r.child("glint_model");
    std::vector<std::string> names;
    for (const auto& m : builtin_glint_models()) names.push_back(m.name);
    GlintModelDecl decl = *find_builtin_glint_model(g.get_enum("name", names));
    std::vector<std::string> truths{"self"};
    for (const auto& m : builtin_glint_models())
      if (m.truth == "self") truths.push_back(m.name);
    decl.truth = g.get_enum("truth", decl.truth, truths);
    g.finish();
    p.glint_model = decl.name;
    p.glint_file = std::make_shared<const GlintModelDecl>(std::move(decl));
  } else if (r.has("glint_model") && r.raw("glint_model").is_object()) {
    // a user's model file: {"file": path relative to the experiment file, "truth", "parameters"}
    JsonReader g = r.child("glint_model");
    const std::string file = g.get_string("file");
    const std::filesystem::path path =
        std::filesystem::path(file).is_absolute() ? std::filesystem::path(file)
                                                  : std::filesystem::path(r.file()).parent_path() / file;
    GlintModelDecl decl;
    try {
      decl = glint_model_from_file(path.string());
    } catch (const ConfigError& e) {
      g.fail("file", e.what());
    }
    decl.name = file;
    if (g.has("truth")) {
      std::vector<std::string> truths{"self"};
      for (const auto& m : builtin_glint_models())
        if (m.truth == "self") truths.push_back(m.name);
      decl.truth = g.get_enum("truth", truths);
    }
    if (auto pj = g.optional_child("parameters")) {
      for (const auto& gp : decl.parameters) {
        if (!pj->has(gp.name)) continue;
        p.glints.model[gp.name] = gp.is_bool ? (pj->get_bool(gp.name) ? 1.0 : 0.0) : pj->get_number(gp.name, gp.lo, gp.hi);
      }
      pj->finish();
    }
    g.finish();
    p.glint_model = file;
    p.glint_file = std::make_shared<const GlintModelDecl>(std::move(decl));
  } else {
    p.glint_model = r.get_enum("glint_model", p.glint_model, glint_model_names());
  }
  p.fresnel_half_vector = r.get_enum("fresnel_half_vector", p.fresnel_half_vector, kFresnelHalfVectors);
  if (r.has("appendix_compat")) {
    const auto& j = r.raw("appendix_compat");
    auto names = compat_names();
    std::string allowed = "\"none\", \"all\" or an array of";
    for (const auto& n : names) allowed += " \"" + n + "\"";
    if (j.is_string() && j.get<std::string>() == "none") {
      p.appendix_compat = 0;
    } else if (j.is_string() && j.get<std::string>() == "all") {
      p.appendix_compat = kSandCompatAll;
    } else if (j.is_array()) {
      p.appendix_compat = 0;
      for (const auto& e : j) {
        bool found = false;
        for (size_t i = 0; i < names.size(); ++i)
          if (e.is_string() && e.get<std::string>() == names[i]) {
            p.appendix_compat |= 1u << i;
            found = true;
          }
        if (!found) r.fail("appendix_compat", "unknown entry " + e.dump() + "; allowed " + allowed);
      }
    } else {
      r.fail("appendix_compat", "expected " + allowed);
    }
  }
  p.energy_consistent = r.get_bool("energy_consistent", p.energy_consistent);
  if (r.has("specular_aa")) {
    if (r.raw("specular_aa").is_object()) {
      JsonReader a = r.child("specular_aa");
      p.specular_aa = SandSpecularAA::published(a.get_enum("method", SandSpecularAA::names()));
      if (p.specular_aa.on()) {
        p.specular_aa.sigma2 = a.get_number("sigma2", p.specular_aa.sigma2, kSpecSigma2.lo, kSpecSigma2.hi);
        p.specular_aa.kappa = a.get_number("kappa", p.specular_aa.kappa, kSpecKappa.lo, kSpecKappa.hi);
      }
      a.finish();
    } else {
      p.specular_aa = SandSpecularAA::published(r.get_enum("specular_aa", SandSpecularAA::names()));
    }
  }
  if (auto g = r.optional_child("glints")) {
    auto& G = p.glints;
    auto getg = [&](const Range& range, double def) { return g->get_number(range.name, def, range.lo, range.hi); };
    auto get2 = [&](const Range& range, std::array<double, 2> def) {
      auto v = g->get_numbers(range.name, std::vector<double>(def.begin(), def.end()), range.lo, range.hi);
      return std::array<double, 2>{v[0], v[1]};
    };
    G.log_density = getg(kLogDensity, G.log_density);
    G.alpha_g = get2(kAlphaG, G.alpha_g);
    G.relative_roughness = get2(kRelRough, G.relative_roughness);
    G.intensity = getg(kIntensity, G.intensity);
    if (g->has(kLightCone.name)) {
      const auto& j = g->raw(kLightCone.name);
      if (j.is_string() && j.get<std::string>() == "sun") {
        G.light_cone.reset();
      } else if (j.is_number() && std::isfinite(j.get<double>()) && j.get<double>() >= kLightCone.lo &&
                 j.get<double>() <= kLightCone.hi) {
        G.light_cone = j.get<double>();
      } else {
        g->fail(kLightCone.name, "expected \"sun\" or a number in [0, 0.5] (radians)");
      }
    }
    // the model's own parameters (its declaration); any other key is unknown
    if (const GlintModelDecl* decl = p.glint_decl())
      for (const auto& gp : decl->parameters) {
        if (!g->has(gp.name)) continue;
        G.model[gp.name] = gp.is_bool ? (g->get_bool(gp.name) ? 1.0 : 0.0) : g->get_number(gp.name, gp.lo, gp.hi);
      }
    // a key another glint model declares: say which, rather than only that it is unknown here
    const GlintModelDecl* own = p.glint_decl();
    for (auto it = g->json().begin(); it != g->json().end(); ++it) {
      if (own && own->parameter(it.key())) continue;
      std::string owners;
      for (const auto& m : builtin_glint_models())
        if (m.parameter(it.key())) owners += (owners.empty() ? "" : ", ") + m.name;
      if (!owners.empty())
        g->fail(it.key(), "unknown key for this material's glint model " + p.glint_model +
                              (own && !own->parameters.empty() ? " (its parameters: " + parameter_list(*own) + ")"
                                                               : std::string(" (it has no parameters of its own)")) +
                              "; it is a parameter of the glint model " + owners +
                              ": set \"glint_model\" beside it, or set it where that model is chosen");
    }
    g->finish();
  }
  r.finish();
  p.validate();
  return p;
}

const GlintModelDecl* SandParams::glint_decl() const {
  if (glint_file) return glint_file.get();
  return find_builtin_glint_model(glint_model);
}

double SandParams::glint_parameter(const std::string& name) const {
  const GlintModelDecl* d = glint_decl();
  const GlintParameter* gp = d ? d->parameter(name) : nullptr;
  if (!gp) throw ConfigError("sand: glint model " + glint_model + " has no parameter " + name);
  auto it = glints.model.find(name);
  return it != glints.model.end() ? it->second : gp->def;
}

SandParams SandParams::reference() const {
  SandParams p = *this;
  if (const GlintModelDecl* d = glint_decl(); d && d->truth != "self") {
    const GlintModelDecl* truth = find_builtin_glint_model(d->truth);
    if (!truth) throw ConfigError("sand: glint model " + glint_model + ": truth " + d->truth + " is no built-in model");
    // the truth keeps the values of the parameters it declares too
    std::map<std::string, double> kept;
    for (const auto& [name, value] : glints.model)
      if (truth->parameter(name)) kept[name] = value;
    p.glint_model = truth->name;
    p.glint_file.reset();
    p.glints.model = kept;
  }
  // The truth has no far field and no transition (SAND_FAR=0): the sigmoid's
  // parameters do not change it, so variants that differ only there share it.
  const SandParams defaults;
  p.specular_aa = defaults.specular_aa;  // the footprint integral itself: nothing to approximate
  p.sigmoid_a = defaults.sigmoid_a;
  p.sigmoid_b = defaults.sigmoid_b;
  return p;
}

SandParamsGPU SandParams::pack() const {
  validate();
  SandParamsGPU g{};
  for (size_t i = 0; i < 8; ++i) {
    for (size_t c = 0; c < 3; ++c) g.palette[i][c] = float(palette[i][c]);
    g.palette[i][3] = 1.0f;
  }
  for (size_t c = 0; c < 3; ++c) g.I_glints[c] = float(I_glints[c]);
  g.SSS = float(SSS);
  g.R_s = float(R_s);
  g.T = float(T);
  g.R_t = float(R_t);
  g.sigma_g = float(glint_sigma);
  g.P = float(P);
  g.noise_scale = float(noise_scale);
  g.ior = float(ior);
  g.scattering = float(scattering);
  g.absorption = float(absorption);
  g.sigma_on = float(oren_nayar_sigma);
  g.sig_a = float(sigmoid_a);
  g.sig_b = float(sigmoid_b);
  g.appendix_compat = appendix_compat;
  g.fresnel_half_vector = fresnel_half_vector == "light_view" ? 1u : 0u;  // SAND_FRESNEL_*
  g.glint_model = glint_file && !glint_file->builtin ? glint_model_gpu_id("") : glint_model_gpu_id(glint_model);  // SAND_GLINT_*
  g.energy_consistent = energy_consistent ? 1u : 0u;
  g.glint_intensity = float(glints.intensity);
  g.glint_light_cone = glints.light_cone ? float(*glints.light_cone) : -1.0f;  // < 0: the sun's
  for (size_t a = 0; a < 2; ++a) {
    g.glint_alpha[a] = float(glints.alpha_g[a]);
    g.glint_alpha[2 + a] = float(glints.relative_roughness[a]);
  }
  g.glint_log_density = float(glints.log_density);
  g.specular_aa_sigma2 = float(specular_aa.sigma2);
  g.specular_aa_kappa = float(specular_aa.kappa);
  if (const GlintModelDecl* d = glint_decl())
    for (size_t i = 0; i < d->parameters.size(); ++i) g.glint_parameters[i] = float(glint_parameter(d->parameters[i].name));
  return g;
}

double sand_sigmoid(double x, double a, double b) {
  double z = a * (x - b);
  if (std::isnan(z)) return 0.5;
  double e = std::exp(-std::fabs(z));
  return z >= 0 ? 1.0 / (1.0 + e) : e / (1.0 + e);
}

std::vector<std::string> shader_defines(const SandParams& p, const SandFeatures& needs) {
  p.validate();
  int debug = SandParams::debug_output_define(needs.debug_output);
  if (!(needs.min_distance >= 0) || !(needs.max_distance >= needs.min_distance))
    throw ConfigError("sand: features: need 0 <= min_distance <= max_distance, got [" + num(needs.min_distance) +
                      ", " + num(needs.max_distance) + "]");
  bool transmission = p.T > 0.0;
  const bool kajs = p.glint_model == kGlintModelKajs;
  bool glints = p.glint_model != kGlintModelNone &&
                (kajs ? (p.I_glints[0] > 0 || p.I_glints[1] > 0 || p.I_glints[2] > 0) : p.glints.intensity > 0);
  bool far = true, close = true;
  if (debug == 0) {
    // eq. 4.38: the far weight is sig(dist), increasing in dist (a > 0)
    far = sand_sigmoid(needs.max_distance, p.sigmoid_a, p.sigmoid_b) >= kSandPruneWeight;
    close = 1.0 - sand_sigmoid(needs.min_distance, p.sigmoid_a, p.sigmoid_b) >= kSandPruneWeight;
    if (!far && !close) close = true;  // degenerate range: keep the nearer field
  }
  // kajs glints live in L_close only; the other models also add their
  // smooth limit to L_far (shaders/sand/sand.glsl)
  if (!close && kajs) glints = false;
  std::vector<std::string> out = {
      "SAND_TRANSMISSION=" + std::to_string(int(transmission)), "SAND_GLINTS=" + std::to_string(int(glints)),
      "SAND_GLINT_MODEL=" + std::to_string(p.pack().glint_model), "SAND_CLOSE=" + std::to_string(int(close)),
      "SAND_FAR=" + std::to_string(int(far)), "SAND_DEBUG=" + std::to_string(debug)};
  if (const GlintModelDecl* d = p.glint_decl(); d && glints) {
    for (auto& def : glint_model_defines(*d)) out.push_back(std::move(def));
    if (p.specular_aa.on()) out.push_back("SAND_SPECULAR_AA=" + std::to_string(p.specular_aa.define()));
  }
  return out;
}

std::vector<std::string> glint_model_defines(const GlintModelDecl& d) {
  std::string fields, values;
  for (size_t i = 0; i < d.parameters.size(); ++i) {
    const std::string& n = d.parameters[i].name;
    fields += "float " + n + ";";
    values += "q." + n + "=p.glint_parameters[" + std::to_string(i / 4) + "][" + std::to_string(i % 4) + "];";
  }
  std::vector<std::string> out = {"GLINT_MODEL_INCLUDE", std::string(kIncludeAliasPrefix) + "GLINT_MODEL_FILE=" + d.file};
  out.push_back("GLINT_MODEL_HASH=h" + d.content_hash);  // the file's bytes (an identifier: h + hex) in every key
  if (d.limit == "ggx") out.push_back("GLINT_LIMIT_GGX");
  if (d.table_size) out.push_back("GLINT_TABLE_SIZE=" + std::to_string(d.table_size) + "u");
  if (!fields.empty()) {
    out.push_back("GLINT_MODEL_PARAMETERS=" + fields);
    out.push_back("GLINT_MODEL_PARAMETER_VALUES=" + values);
  }
  return out;
}

}  // namespace glintlab::core

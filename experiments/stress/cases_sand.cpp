// Stress cases of the sand material's terms: shaders/sand/sand.glsl through
// shaders/tests/sand_terms.comp (the compute harness) against the fp64 twin
// (core/testkit/sand_fp64.h) on extreme inputs, for every glint model
// where the case applies.
//
// Compared: L_final (and sand_shade(), which must equal it) per colour channel,
// err = |gpu - fp64| / max(|fp64|, 1e-4 S), S the item's radiance scale
// (max over channels of L_i + L_sky, times the largest palette or I_glints
// gain, times pi when energy consistent): below 1e-4 S an error counts
// against the scale, not the value. The grains/zirr/beckmann glint terms enter
// with the GPU's own values (the glint.* cases check them stage by stage);
// items whose discrete decisions fp32 cannot make reliably are not compared:
// a Kajs cube face within 1e-4 of a tie, a normalised grain random number
// within 1e-5 of 1/2. Grain random numbers (exact multiples of 2^-24) must
// agree exactly. Every output term must be finite and every non-negative term
// >= 0 on every item (compared or not).
#include "core/material/sand_material.h"
#include "core/testkit/glint_fp64.h"
#include "core/testkit/harness_io.h"
#include "core/testkit/sand_fp64.h"
#include "core/vk/compute_harness.h"
#include "experiments/stress/stress_internal.h"

#include <glm/geometric.hpp>

namespace glintlab::stress {

namespace {

namespace ref = glintlab::reference::sand;
using ref::vec3;

using Item = reference::harness::SandTermsInput;
constexpr size_t kIn = reference::harness::kSandTermsIn, kOut = reference::harness::kSandTermsOut;

using reference::harness::d3;
using reference::harness::f3;

// What a case changes: the parameters before packing, then the geometry and light.
struct Draw {
  std::mt19937_64& rng;
  core::SandParams sp;
  vec3 n, wo, wi;
  vec3 x_obj;
  double dist;
  vec3 L_i, L_sky;
  double U() { return std::uniform_real_distribution<double>()(rng); }
  double N() { return std::normal_distribution<double>()(rng); }
  vec3 unit() { return glm::normalize(vec3(N(), N(), N())); }
  // a unit vector at angle `theta` (rad) from n, random azimuth
  vec3 at_angle(const vec3& axis, double theta) {
    vec3 t1, t2;
    ref::frisvad_basis(axis, t1, t2);
    double phi = 2 * kPi * U();
    return glm::normalize(std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * t1 + std::sin(phi) * t2));
  }
  vec3 upper(const vec3& axis) {  // uniform on the hemisphere around axis
    vec3 v = unit();
    return glm::dot(v, axis) < 0 ? v - 2.0 * axis * glm::dot(v, axis) : v;
  }
};

using Modifier = std::function<void(Draw&)>;

Item make_item(std::mt19937_64& rng, const std::string& model, const Modifier& mod) {
  Draw d{rng, core::SandParams{}, vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1), vec3(0), 1.0, vec3(1), vec3(1)};
  core::SandParams& sp = d.sp;
  for (auto& c : sp.palette) c = {d.U(), d.U(), d.U()};
  sp.I_glints = {log_uniform(rng, 0.1, 100), log_uniform(rng, 0.1, 100), log_uniform(rng, 0.1, 100)};
  sp.SSS = d.U();
  sp.R_s = d.U();
  sp.T = d.U();
  sp.R_t = d.U();
  sp.glint_sigma = log_uniform(rng, 1e-4, 1.0);
  sp.P = d.U();
  sp.noise_scale = log_uniform(rng, 1, 1e4);
  sp.ior = 1 + 2 * d.U();
  sp.scattering = d.U();
  sp.absorption = d.U();
  sp.oren_nayar_sigma = d.U() * 1.5;
  sp.sigmoid_a = log_uniform(rng, 1e-2, 10);
  sp.sigmoid_b = 20 * d.U();
  sp.appendix_compat = d.U() < 0.5 ? 0u : uint32_t(rng() % 64);
  sp.fresnel_half_vector = d.U() < 0.5 ? "macro_normal" : "light_view";
  sp.glint_model = model;
  sp.energy_consistent = d.U() < 0.5;
  sp.glints.alpha_g = {log_uniform(rng, 0.05, 1), log_uniform(rng, 0.05, 1)};
  sp.glints.relative_roughness = {log_uniform(rng, 0.05, 1), log_uniform(rng, 0.05, 1)};
  sp.glints.log_density = 3 + 9 * d.U();
  // a model's own parameters where it declares them (the draws are made for every model)
  auto own = [&sp](const char* name, double v) {
    if (const core::GlintModelDecl* decl = sp.glint_decl(); decl && decl->parameter(name)) sp.glints.model[name] = v;
  };
  own("size_variation", d.U() < 0.5 ? 0.0 : 2 * d.U());
  sp.glints.intensity = log_uniform(rng, 0.1, 10);
  if (d.U() < 0.5) sp.glints.light_cone = 0.5 * d.U();
  own("color_saturation", d.U() < 0.5 ? 0.0 : d.U());
  d.n = d.unit();
  d.wo = d.upper(d.n);
  d.wi = d.U() < 0.7 ? d.upper(d.n) : d.unit();
  if (d.U() < 0.3) {  // near the mirror configuration, where glints are
    vec3 h = glm::normalize(d.n + 0.3 * d.unit());
    d.wi = glm::normalize(2.0 * glm::dot(d.wo, h) * h - d.wo);
  }
  d.x_obj = vec3(d.N(), d.N(), d.N()) * 10.0;
  d.dist = log_uniform(rng, 1e-2, 1e3);
  d.L_i = vec3(d.U(), d.U(), d.U()) * 10.0;
  d.L_sky = vec3(d.U(), d.U(), d.U()) * 2.0;
  mod(d);
  Item c;
  c.p = d.sp.pack();  // validates: every case stays inside the documented parameter ranges
  c.n = f3(d.n);
  c.wo = f3(d.wo);
  c.wi = f3(d.wi);
  c.x_obj = f3(d.x_obj);
  c.dist = f32(d.dist);
  c.L_i = f3(d.L_i);
  c.L_sky = f3(d.L_sky);
  vec3 t = glm::normalize(glm::cross(d.n, glm::normalize(vec3(d.N(), d.N(), d.N()))));
  c.t = f3(t);
  c.b = f3(glm::cross(d.n, t) * (d.U() < 0.5 ? 1.0 : -1.0));
  c.cone = f32(0.01 * d.U());
  c.uv = {f32(10 * d.U()), f32(10 * d.U())};
  double fs = log_uniform(rng, 1e-8, 0.1);
  c.duv_dx = {f32(d.N() * fs), f32(d.N() * fs)};
  c.duv_dy = {f32(d.N() * fs), f32(d.N() * fs)};
  return c;
}

ref::Terms ref_terms(const Item& c) { return reference::harness::sand_terms_of(c); }

struct SandCaseSpec {
  std::string name;
  bool fast;
  std::vector<std::string> models;  // items cycle through them
  Modifier mod;
  double bound;        // on max_rel_error
  bool check_basis = false;  // also the Frisvad basis of n (orthonormal, = fp64 within 1e-6)
  std::string what;    // what the case stresses (detail)
};

StressCaseResult run_sand_case(Env& env, const SandCaseSpec& spec) {
  const size_t n_items = env.fast ? 512 : 131072;
  std::mt19937_64 rng(std::hash<std::string>()(spec.name));
  std::vector<Item> items;
  items.reserve(n_items);
  for (size_t i = 0; i < n_items; ++i) items.push_back(make_item(rng, spec.models[i % spec.models.size()], spec.mod));
  std::vector<float> in(n_items * kIn, 0.0f);
  for (size_t i = 0; i < n_items; ++i) reference::harness::write_sand_terms_input(items[i], &in[i * kIn]);
  std::vector<float> out =
      core::run_compute(env.ctx, "tests/sand_terms.comp", reference::harness::twin_defines(), in, n_items * kOut, uint32_t(n_items));

  ValueScan scan;
  ErrorStat err;
  size_t skipped = 0, xi_mismatch = 0, shade_mismatch = 0, basis_bad = 0;
  double basis_err = 0;
  for (size_t i = 0; i < n_items; ++i) {
    const Item& c = items[i];
    const float* o = &out[i * kOut];
    for (size_t k = 0; k < 71; ++k) {
      bool signed_out = (k >= 3 && k <= 5) || (k >= 7 && k <= 9) || k >= 61;  // xi_pm, m, basis
      bool in_scan = k != 44;  // L_oren alone may exceed any scale at grazing (only its product is used)
      if (in_scan) scan.add(o[k], !signed_out);
    }
    ref::Terms r = ref_terms(c);
    const bool normalised = c.p.appendix_compat & ref::kCompatRandNormalized;
    if (!normalised)
      for (int k = 0; k < 3; ++k) xi_mismatch += o[k] != r.xi[k];
    for (int k = 0; k < 3; ++k) shade_mismatch += o[58 + k] != o[55 + k];
    if (spec.check_basis) {
      vec3 b1, b2;
      ref::frisvad_basis(d3(c.n), b1, b2);
      vec3 g1(o[61], o[62], o[63]), g2(o[64], o[65], o[66]);
      double e = std::max({glm::length(g1 - b1), glm::length(g2 - b2), std::fabs(glm::dot(g1, g2)),
                           std::fabs(glm::dot(g1, d3(c.n))), std::fabs(glm::length(g1) - 1), std::fabs(glm::length(g2) - 1)});
      basis_err = std::max(basis_err, e);
      basis_bad += !(e <= 1e-6);
    }
    const uint32_t model = c.p.glint_model;
    bool decidable = !(normalised && r.palette_margin <= 1e-5) && !(model == ref::kGlintKajs && r.face_margin <= 1e-4);
    if (!decidable) {
      ++skipped;
      continue;
    }
    // the radiance scale of the item
    double S = 0, gain = 1;
    for (int k = 0; k < 3; ++k) S = std::max(S, double(c.L_i[k]) + c.L_sky[k]);
    for (int k = 0; k < 3; ++k) gain = std::max(gain, double(c.p.I_glints[k]));
    for (auto& col : c.p.palette) gain = std::max({gain, double(col[0]), double(col[1]), double(col[2])});
    S *= gain;
    if (c.p.energy_consistent) S *= kPi;
    // the new glint models' terms as the GPU computed them
    vec3 L_g = r.L_g, L_far = r.L_far;
    if (model != ref::kGlintKajs && model != ref::kGlintNone) {
      L_g = vec3(o[33], o[34], o[35]);
      L_far = ref::L_far(r.L_brdf, r.L_f + vec3(o[68], o[69], o[70]), r.L_t, r.rho_n_intensity);
      S = std::max({S, L_g.x, L_g.y, L_g.z});
    }
    vec3 L_close = ref::L_close(r.L_d, r.L_f + L_g, r.L_t, r.rho_m_intensity);
    vec3 L_final = ref::L_final(L_close, L_far, r.sig);
    for (int k = 0; k < 3; ++k) err.add(o[55 + k], L_final[k], 1e-4 * std::max(S, 1e-30), "item " + std::to_string(i));
  }
  bool ok = xi_mismatch == 0 && shade_mismatch == 0 && basis_bad == 0 && err.compared > 0;
  std::string detail = spec.what + "; L_final of " + std::to_string(err.compared / 3) + " of " +
                       std::to_string(n_items) + " items vs fp64 (" + std::to_string(skipped) +
                       " at an fp32-undecidable face/palette tie); worst: " + err.worst;
  if (xi_mismatch) detail += "; grain random numbers differ: " + std::to_string(xi_mismatch);
  if (shade_mismatch) detail += "; sand_shade != L_final: " + std::to_string(shade_mismatch);
  if (spec.check_basis) detail += "; Frisvad basis max deviation " + fmt(basis_err) + " (bound 1e-6)";
  StressCaseResult res = make_result(spec.name, "sand", scan, &err, spec.bound, ok, detail);
  res.items = scan.items;
  if (spec.check_basis) res.extra["basis_error"] = basis_err;
  return res;
}

// kajs, every glint_D model with an fp64 twin, none.
std::vector<std::string> all_models() {
  std::vector<std::string> out;
  for (const auto& n : core::glint_model_names())
    if (!core::find_builtin_glint_model(n) || reference::glint::twin_of_gpu(core::glint_model_gpu_id(n)) != 0u)
      out.push_back(n);
  return out;
}
// The footprint-filtering model, whose walk is stressed at grazing angles, and its smooth limit.
const std::string kZirr = "zirr";
std::string zirr_limit() { return core::find_builtin_glint_model(kZirr)->limit; }

}  // namespace

void add_sand_cases(std::vector<Case>& cases) {
  const double deg = kPi / 180;
  std::vector<SandCaseSpec> specs;
  auto model_name = [](const std::string& m) { return m; };
  const std::vector<std::string> kAllModels = all_models();
  // grazing views 80-89.99 deg, one case per glint model
  for (const std::string& m : kAllModels) {
    if (m == core::kGlintModelNone) continue;
    specs.push_back({"sand.grazing-view." + model_name(m), m == core::kGlintModelKajs || m == kZirr,
                     {m},
                     [deg](Draw& d) {
                       d.wo = d.at_angle(d.n, (80 + 9.99 * d.U()) * deg);
                       if (d.U() < 0.3) d.wi = d.at_angle(d.n, (80 + 9.99 * d.U()) * deg);
                       if (d.U() < 0.2) d.wo = d.at_angle(d.n, 89.99 * deg);
                     },
                     1e-3, false, "view 80-89.99 deg from the normal"});
  }
  specs.push_back({"sand.backlit", true, kAllModels,
                   [](Draw& d) {
                     d.wi = -d.wo;  // light exactly opposite the view (exact in fp32)
                     d.sp.T = d.U() < 0.5 ? 1.0 : d.sp.T;
                   },
                   1e-3, false, "w_i = -w_o exactly (transmission's peak), every model"});
  specs.push_back({"sand.view-behind-surface", false, kAllModels,
                   [](Draw& d) {
                     d.wo = -d.upper(d.n);  // below the macro surface
                     if (d.U() < 0.3) d.wi = -d.upper(d.n);
                   },
                   1e-3, false, "w_o (and some w_i) below the surface: the camera behind it"});
  specs.push_back({"sand.normal-minus-z", true, kAllModels,
                   [](Draw& d) {
                     double u = d.U();
                     d.n = u < 0.4 ? vec3(0, 0, -1) : (u < 0.7 ? glm::normalize(vec3(1e-4 * d.N(), 1e-4 * d.N(), -1))
                                                              : glm::normalize(vec3(1e-8, -1e-8, -1)));
                     d.wo = d.upper(d.n);
                     d.wi = d.upper(d.n);
                   },
                   1e-3, true, "n = -z and within 1e-4 of it (the Frisvad singularity of the 2012 form)"});
  specs.push_back({"sand.normal-plus-z", false, kAllModels,
                   [](Draw& d) {
                     d.n = d.U() < 0.5 ? vec3(0, 0, 1) : glm::normalize(vec3(1e-4 * d.N(), 1e-4 * d.N(), 1));
                     d.wo = d.upper(d.n);
                     d.wi = d.U() < 0.3 ? d.n : d.upper(d.n);
                   },
                   1e-3, true, "n = +z and near it, w_i = n in 30 %"});
  specs.push_back({"sand.object-coords-1e6", true, {core::kGlintModelKajs, core::kGlintModelNone},
                   [](Draw& d) {
                     d.x_obj = vec3(d.N(), d.N(), d.N()) * log_uniform(d.rng, 1e3, 1e6);
                     d.sp.noise_scale = log_uniform(d.rng, 1, 1e6);
                     if (d.U() < 0.2) d.sp.noise_scale = 1e6;
                   },
                   1e-3, false, "object coordinates up to 1e6, noise_scale up to 1e6 (products up to 1e12)"});
  specs.push_back({"sand.noise-scale-1e6", false, {core::kGlintModelKajs},
                   [](Draw& d) {
                     d.sp.noise_scale = 1e6;
                     d.x_obj = vec3(d.N(), d.N(), d.N()) * log_uniform(d.rng, 1e-6, 1e6);
                   },
                   1e-3, false, "noise_scale = 1e6 (grain cells 1e-6 wide) at coordinates 1e-6 .. 1e6"});
  specs.push_back({"sand.roughness-0-and-1", true, kAllModels,
                   [](Draw& d) {
                     d.sp.R_s = d.U() < 0.5 ? 0.0 : 1.0;
                     d.sp.R_t = d.U() < 0.5 ? 0.0 : 1.0;
                     d.sp.oren_nayar_sigma = d.U() < 0.5 ? 0.0 : kPi / 2;
                     double a = d.U() < 0.5 ? 1e-3 : 1.0;  // the glint models' alpha_g at both ends
                     d.sp.glints.alpha_g = {a, d.U() < 0.5 ? a : 1e-3};
                     d.sp.glints.relative_roughness = {d.U() < 0.5 ? 1e-3 : 1.0, d.U() < 0.5 ? 1e-3 : 1.0};
                   },
                   1e-3, false, "R_s, R_t in {0, 1}, Oren-Nayar sigma in {0, pi/2}, glint alpha_g and relative roughness at 1e-3 and 1"});
  specs.push_back({"sand.glint-sigma-1e-6-to-1", true, {core::kGlintModelKajs},
                   [](Draw& d) {
                     const double s[] = {1e-6, 1e-5, 1e-4, 1e-2, 1.0};
                     d.sp.glint_sigma = s[d.rng() % 5];
                     d.sp.R_s = 0.1 * d.U();  // G(R_s) ~ 1: the glint term is on
                   },
                   1e-3, false, "Kajs glint sigma in {1e-6, 1e-5, 1e-4, 1e-2, 1}"});
  specs.push_back({"sand.transmission-T1-Rt-0-1", true, kAllModels,
                   [](Draw& d) {
                     d.sp.T = 1.0;
                     d.sp.R_t = d.U() < 0.5 ? 0.0 : 1.0;
                     if (d.U() < 0.5) d.wi = -d.wo;
                     else d.wi = d.at_angle(-d.wo, 0.3 * d.U());
                   },
                   1e-3, false, "T = 1, R_t in {0, 1}, light behind the grains"});
  specs.push_back({"sand.porosity-0-1", true, kAllModels,
                   [](Draw& d) {
                     d.sp.P = d.U() < 0.5 ? 0.0 : 1.0;
                     const double ds[] = {0.0, 1e-30, 1e-6, 1.0, 1e6, 3e38};
                     d.dist = ds[d.rng() % 6];
                   },
                   1e-3, false, "P in {0, 1} at distances 0, 1e-30, 1e-6, 1, 1e6, 3e38 (exp(-P/d))"});
  specs.push_back({"sand.sigmoid-a1e3-dist1e6", true, {core::kGlintModelKajs, zirr_limit()},
                   [](Draw& d) {
                     const double a[] = {1e2, 1e3, 1e4};
                     d.sp.sigmoid_a = a[d.rng() % 3];
                     d.sp.sigmoid_b = log_uniform(d.rng, 1, 1e6);
                     double u = d.U();
                     d.dist = u < 0.3 ? 1e6 : (u < 0.6 ? d.sp.sigmoid_b * (1 + 1e-3 * d.N()) : log_uniform(d.rng, 1e-3, 1e6));
                   },
                   1e-3, false, "sigmoid a up to 1e4, b up to 1e6, distances up to 1e6 and near b"});
  specs.push_back({"sand.sun-1e6", true, kAllModels,
                   [](Draw& d) {
                     d.L_i = vec3(1e6, 1e6 * d.U(), 1e6);
                     if (d.U() < 0.3) d.sp.I_glints = {1e6, 1e6, 1e6};
                   },
                   1e-3, false, "sun radiance 1e6 (and I_glints 1e6 in 30 %)"});
  specs.push_back({"sand.palette-black", true, kAllModels,
                   [](Draw& d) {
                     for (auto& c : d.sp.palette) c = {0, 0, 0};
                     if (d.U() < 0.5) d.L_sky = vec3(0);
                   },
                   1e-3, false, "every grain colour 0 (and no sky in half)"});
  specs.push_back({"sand.palette-white", true, kAllModels,
                   [](Draw& d) {
                     double v = d.U() < 0.7 ? 1.0 : 1e3;
                     for (auto& c : d.sp.palette) c = {v, v, v};
                   },
                   1e-3, false, "every grain colour 1 (and the range's 1e3 in 30 %)"});
  specs.push_back({"sand.oren-nayar-0-and-90deg", true, {core::kGlintModelNone, zirr_limit()},
                   [deg](Draw& d) {
                     double u = d.U();
                     if (u < 0.25) d.wo = d.wi = d.n;
                     else if (u < 0.5) d.wo = d.n, d.wi = d.at_angle(d.n, 1e-4 * d.U());
                     else if (u < 0.75) d.wo = d.at_angle(d.n, (89.9 + 0.0999 * d.U()) * deg), d.wi = d.at_angle(d.n, (89.9 + 0.0999 * d.U()) * deg);
                     else d.wo = d.at_angle(d.n, 89.999 * deg), d.wi = d.n;
                     d.sp.oren_nayar_sigma = d.U() < 0.2 ? kPi / 2 : d.U();
                     d.sp.sigmoid_a = 1e3, d.sp.sigmoid_b = 0.0;  // the far field (Oren-Nayar) everywhere
                   },
                   1e-3, false, "Oren-Nayar at theta_i, theta_o = 0 and 89.9-90 deg, sigma up to pi/2, far field"});
  for (auto& s : specs)
    cases.push_back({s.name, "sand", s.fast, [s](Env& env) { return run_sand_case(env, s); }});
}

}  // namespace glintlab::stress

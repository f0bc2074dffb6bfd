// Stress cases of the microdetail glint models (Zirr & Kaplanyan 2016;
// shaders/sand/glint_*.glsl, glint/models/*.glsl, common/binomial.glsl) through
// shaders/tests/glint_terms.comp and glint_math.comp against the fp64 twin
// (core/testkit/glint_fp64.h), stage by stage as
// tests/core/material/glint_models.cpp does: each stage is fed the GPU's fp32
// results of the stages before it (frame, roughness, per-pixel values), so an
// error is that stage's own.
//
// err = |gpu - fp64| / max(|fp64|, 1e-3 scale), scale = the item's largest
// fp64 value of the quantity and its beckmann D(h), at least 1e-20 (kDFloor); zirr's error first loses
// what fp32 cell coordinates put into the coverage weights (Zirr::abs_err).
// Items are compared where their discrete decisions (levels, walk, cells,
// quantised half vector, binomial steps) are decidable in fp32 (fp64 slack
// > 0) and the quantity is conditioned within the case's bound (grains at a
// tiny alpha_l: the sampled slope's fp32 error over alpha_l); the others are
// counted, and must still be finite and non-negative.
#include "core/testkit/glint_fp64.h"
#include "core/testkit/harness_io.h"
#include "core/testkit/sand_fp64.h"
#include "core/vk/compute_harness.h"
#include "experiments/stress/stress_internal.h"

#include <glm/geometric.hpp>

namespace glintlab::stress {

namespace {

namespace gr = glintlab::reference::glint;
using gr::vec2;
using gr::vec3;

using Item = reference::harness::GlintTermsInput;
using reference::harness::kGlintTermsOut;
using reference::harness::round_to_f32;
// NDF values below this (1/sr) are compared against it: D exp(-q) / (pi a_u a_v h.z^4) underflows in
// fp32 where the exponential alone falls below 1.2e-38 although D would not (a narrow lobe's large
// prefactor); such a D times any sun (1e6) and gain (1e6) stays below 1e-8.
constexpr double kDFloor = 1e-20;
constexpr size_t kMathIn = 12, kMathOut = 12;    // shaders/tests/glint_math.comp

std::vector<float> run_terms(Env& env, const std::vector<Item>& items) {
  return reference::harness::run_glint_terms(env.ctx, items);
}

vec2 o2(const float* o) { return vec2(o[0], o[1]); }
vec3 o3(const float* o) { return vec3(o[0], o[1], o[2]); }

struct Rng {
  std::mt19937_64 g;
  explicit Rng(const std::string& seed) : g(std::hash<std::string>()(seed)) {}
  double U() { return std::uniform_real_distribution<double>()(g); }
  double N() { return std::normal_distribution<double>()(g); }
  double logu(double lo, double hi) { return log_uniform(g, lo, hi); }
  vec3 unit() { return glm::normalize(vec3(N(), N(), N())); }
};

// A random shading point near the specular configuration (where the models
// are non-zero), moderate parameters; `mod` makes it extreme.
Item base_item(Rng& r, uint32_t model) {
  Item c;
  c.model = model;
  c.n = r.unit();
  c.t = glm::normalize(glm::cross(c.n, r.unit()));
  c.b = glm::cross(c.n, c.t) * (r.U() < 0.5 ? 1.0 : -1.0);
  c.wo = r.unit();
  if (glm::dot(c.wo, c.n) < 0) c.wo -= 2.0 * c.n * glm::dot(c.wo, c.n);
  vec3 h = glm::normalize(c.n + 0.3 * r.unit());
  if (glm::dot(h, c.n) < 0.2) h = c.n;
  c.wi = glm::normalize(2.0 * glm::dot(c.wo, h) * h - c.wo);
  if (glm::dot(c.wi, c.n) <= 0) c.wi = glm::normalize(c.wi - 2.0 * c.n * glm::dot(c.wi, c.n));
  c.uv = vec2(r.U(), r.U()) * 10.0;
  c.p.alpha_g = vec2(r.logu(0.05, 0.8), r.logu(0.05, 0.8));
  c.p.relative = vec2(r.logu(0.05, 1), r.logu(0.05, 1));
  c.p.log_density = 3 + 9 * r.U();
  c.p.size_variation = 0;
  c.p.intensity = r.logu(0.1, 10);
  c.p.light_cone = r.U() < 0.5 ? -1.0 : 0.2 * r.U();
  c.p.color_saturation = r.U() < 0.5 ? 0.0 : r.U();
  c.p.ior = 1 + 2 * r.U();
  c.sun_cone = 0.01 * r.U();
  c.L_i = vec3(r.U(), r.U(), r.U()) * 10.0;
  double s = r.logu(0.1, 100) * std::pow(10.0, -0.5 * c.p.log_density);  // 0.1 .. 100 reference cells
  double ang = 2 * kPi * r.U(), an = r.logu(1, 8);
  c.dx = vec2(std::cos(ang), std::sin(ang)) * s;
  c.dy = vec2(-std::sin(ang), std::cos(ang)) * s / an;
  return c;
}

using Modifier = std::function<void(Rng&, Item&)>;

struct Checks {
  bool zirr = false, grains = false, beckmann = false, radiance = true;
  bool pointwise_energy = false;  // D <= 2 m0 (1 + saturation) / h.z^4 (zirr without size variation, grains)
};

struct GlintCaseSpec {
  std::string name;
  bool fast;
  std::vector<uint32_t> models;
  Modifier mod;
  Checks checks;
  double bound;
  std::string what;
  size_t items_full = 131072;
};

StressCaseResult run_glint_case(Env& env, const GlintCaseSpec& spec) {
  Rng r(spec.name);
  const size_t n = env.fast ? spec.items_full / 256 : spec.items_full;
  std::vector<Item> items;
  for (size_t i = 0; i < n; ++i) {
    Item c = base_item(r, spec.models[i % spec.models.size()]);
    c.p.half_vector_blend = (i / spec.models.size()) % 2 == 1;  // zirr: half the items blend half-vector bins
    spec.mod(r, c);
    round_to_f32(c);
    items.push_back(c);
  }
  std::vector<float> out = run_terms(env, items);
  ValueScan scan;
  ErrorStat err;
  size_t undecidable = 0, ill_conditioned = 0, cells_mismatch = 0, energy_violations = 0, glinting = 0, delta_lobes = 0;
  double energy_ratio_max = 0;
  for (size_t i = 0; i < n; ++i) {
    const Item& c = items[i];
    const float* o = &out[i * kGlintTermsOut];
    // m0 = D_l(0) = 1 / (pi alpha_l,u alpha_l,v) is +inf for a perfectly smooth microdetail (alpha_g = 0
    // and no light cone, below the validated range): a delta lobe, never multiplied (its pmf is 0)
    const bool delta_lobe = o[14] == 0 || o[15] == 0;
    for (size_t k = 0; k < 70; ++k) {
      bool signed_out = k < 9 || (k >= 32 && k <= 33) || k == 35 || (k >= 40 && k <= 55);
      if (k == 31 && delta_lobe) {
        delta_lobes += !(o[k] > 0);  // must be +inf or a positive number, never NaN
        continue;
      }
      scan.add(o[k], !signed_out);
    }
    const std::string where = "item " + std::to_string(i);
    gr::Frame fg{o3(o), o3(o + 3), o3(o + 6), o[9] != 0};
    const gr::Roughness rg = reference::harness::gpu_roughness(o, c);  // the GPU's, for the later stages
    const vec3 h = fg.h;
    const double beck = gr::beckmann_D(h, vec2(0), rg.alpha_g);
    bool any_glint = false;
    for (int k = 0; k < 3; ++k) any_glint = any_glint || o[63 + k] > 0;
    glinting += any_glint;
    double q_g = h.z > 0 ? std::pow(h.x / h.z / rg.alpha_g.x, 2) + std::pow(h.y / h.z / rg.alpha_g.y, 2) : 0;
    if (spec.checks.beckmann && h.z > 0 && std::fabs(q_g - 88) > 0.1) {
      if (2e-6 * (1 + q_g) > spec.bound / 2) ++ill_conditioned;
      else err.add(o[24], beck, std::max(1e-3 * beck, kDFloor), where + " beckmann D");
    }
    gr::ZirrPixel pxg{o[30], o[31], o2(o + 32)};
    // pointwise energy: no cell holds more reflecting microdetails than it has
    if (spec.checks.pointwise_energy && h.z > 0) {
      double cap = 2 * pxg.m0 * (1 + c.p.color_saturation) / std::pow(h.z, 4) * (1 + 1e-4);
      const float* D = c.model == gr::kGlintZirr ? o + 56 : o + 60;
      for (int k = 0; k < 3; ++k) {
        energy_violations += !(D[k] <= cap);
        energy_ratio_max = std::max(energy_ratio_max, D[k] / cap * 2);
      }
    }
    if (spec.checks.zirr && h.z > 0 && c.model == gr::kGlintZirr) {
      gr::Slack zs;
      gr::Zirr z = gr::zirr(c.uv, c.dx, c.dy, h, rg, pxg, c.p.size_variation, c.p.color_saturation, &zs);
      bool huge = std::fabs(c.uv.x) > 1e3 || std::fabs(c.uv.y) > 1e3 || !std::isfinite(c.uv.x) || !std::isfinite(c.uv.y);
      if (zs.min > 0 && !huge) {
        cells_mismatch += o[59] != z.cells;
        double scale = std::max({z.D.x, z.D.y, z.D.z, beck, kDFloor});
        if (2e-4 + z.rel_err > spec.bound / 2) {
          ++ill_conditioned;
        } else {
          for (int k = 0; k < 3; ++k) err.add(o[56 + k], z.D[k], 1e-3 * scale, where + " zirr D", z.abs_err);
        }
      } else {
        ++undecidable;
      }
    }
    if (spec.checks.grains && h.z > 0 && c.model == gr::kGlintGrains) {
      gr::Slack gs;
      double q = 0;
      vec2 x_i(0);
      vec3 G = gr::grains_D(c.uv, h, rg, c.p.color_saturation, &gs, &q, &x_i);
      bool huge = std::fabs(c.uv.x) > 1e3 || std::fabs(c.uv.y) > 1e3;
      if (gs.min > 0 && q < 87.5 && !huge) {
        double amin = std::min(rg.alpha_l.x, rg.alpha_l.y);
        double rel = 4e-6 * (1 + q) + 2 * std::sqrt(q) * 4e-6 * (1 + std::max(std::fabs(x_i.x), std::fabs(x_i.y))) / amin;
        if (rel > spec.bound / 2) {
          ++ill_conditioned;
        } else {
          double scale = std::max({G.x, G.y, G.z, beck, kDFloor});
          for (int k = 0; k < 3; ++k) err.add(o[60 + k], G[k], 1e-3 * scale, where + " grains D");
        }
      } else {
        ++undecidable;
      }
    }
    if (spec.checks.radiance) {
      const reference::harness::GlintRadiance R = reference::harness::glint_radiance_of(o, c, fg, rg);
      // Schlick's F error: its share of the floor
      double floor = std::max({1e-3 * R.L_max, R.fresnel_allowance / (spec.bound / 2), 1e-30});
      for (int k = 0; k < 3; ++k) err.add(o[63 + k], R.L[k], floor, where + " radiance");
    }
  }
  bool ok = cells_mismatch == 0 && energy_violations == 0 && delta_lobes == 0;
  std::string detail = spec.what + "; " + std::to_string(err.compared) + " values of " + std::to_string(n) +
                       " items vs fp64 (" + std::to_string(undecidable) + " items fp32-undecidable, " +
                       std::to_string(ill_conditioned) + " conditioned beyond the bound); " +
                       std::to_string(glinting) + " items with glint radiance > 0";
  if (cells_mismatch) detail += "; zirr cells differ: " + std::to_string(cells_mismatch);
  if (spec.checks.pointwise_energy)
    detail += "; D / (m0 (1 + s) / h.z^4) max " + fmt(energy_ratio_max) + " (bound 2: a cell of Cn >= 1 "
              "microdetails rounded up holds at most 2 Cn)" + (energy_violations ? " VIOLATED " + std::to_string(energy_violations) : "");
  detail += "; worst: " + err.worst;
  StressCaseResult res = make_result(spec.name, "glint", scan, &err, spec.bound, ok, detail);
  if (spec.checks.pointwise_energy) res.extra["energy_ratio"] = energy_ratio_max, res.extra["energy_bound"] = 2.0;
  return res;
}

// ---- energy over a region: mean glint radiance of zirr vs beckmann
StressCaseResult energy_case(Env& env, bool fast) {
  Rng r("glint.energy-zirr-vs-beckmann");
  const double densities[] = {-3, 0, 3, 6, 9, 12};
  const size_t per = fast ? 2048 : 8192;
  std::vector<Item> items;
  for (double ld : densities)
    for (size_t i = 0; i < per; ++i) {
      for (uint32_t model : {gr::kGlintZirr, gr::kGlintBeckmann}) {
        Item c;
        c.model = model;
        c.n = vec3(0, 0, 1);
        c.t = vec3(1, 0, 0);
        c.b = vec3(0, 1, 0);
        c.wo = glm::normalize(vec3(0.3, 0.1, 1.0));
        c.wi = glm::normalize(vec3(-0.25, -0.05, 1.0));
        c.p.alpha_g = vec2(0.3, 0.3);
        c.p.relative = vec2(0.5, 0.5);  // pmf at the peak (alpha_l / alpha_g)^2 = 1/4: many reflecting microdetails
        c.p.log_density = ld;
        c.p.light_cone = 0;
        c.L_i = vec3(1);
        items.push_back(c);
      }
    }
  // the region: random pixels over 256 x 256 reference cells, footprints 0.5 .. 64 cells
  for (size_t i = 0; i < items.size(); i += 2) {
    double s_ref = std::pow(10.0, -0.5 * items[i].p.log_density);
    vec2 uv = vec2(r.U(), r.U()) * 256.0 * s_ref;
    double s = r.logu(0.5, 64) * s_ref, ang = 2 * kPi * r.U();
    for (size_t k = i; k < i + 2; ++k) {
      items[k].uv = uv;
      items[k].dx = vec2(std::cos(ang), std::sin(ang)) * s;
      items[k].dy = vec2(-std::sin(ang), std::cos(ang)) * s;
      round_to_f32(items[k]);
    }
  }
  std::vector<float> out = run_terms(env, items);
  ValueScan scan;
  double worst = 0, lowest = 1e300;
  std::string per_density;
  for (size_t d = 0; d < std::size(densities); ++d) {
    double sz = 0, sb = 0;
    for (size_t i = 0; i < per; ++i) {
      size_t base = (d * per + i) * 2;
      for (int m = 0; m < 2; ++m) {
        const float* o = &out[(base + m) * kGlintTermsOut];
        for (int k = 0; k < 3; ++k) scan.add(o[63 + k]);
      }
      sz += out[base * kGlintTermsOut + 63 + 1];
      sb += out[(base + 1) * kGlintTermsOut + 63 + 1];
    }
    double ratio = sb > 0 ? sz / sb : kInf;
    worst = std::max(worst, ratio);
    lowest = std::min(lowest, ratio);
    per_density += (per_density.empty() ? "" : ", ") + std::string("1e") + std::to_string(int(densities[d])) + ": " + fmt(ratio);
  }
  const double factor = 1.25;
  StressCaseResult res = make_result(
      "glint.energy-zirr-vs-beckmann", "glint", scan, nullptr, std::nullopt, worst <= factor,
      "mean zirr glint radiance over " + std::to_string(per) + " pixels (footprints 0.5 .. 64 reference cells, "
      "random over 256 x 256 cells) / beckmann's, per density 1e-3 .. 1e12 per uv unit: " + per_density +
      "; bound: <= " + fmt(factor) + " (E = 1; the counts' spread over the region is ~3 %)");
  res.extra["energy_ratio"] = worst;
  res.extra["energy_ratio_min"] = lowest;
  res.extra["energy_bound"] = factor;
  res.items = scan.items;
  return res;
}

// ---- binomial draws (common/binomial.glsl) for n up to 1e12 and p in {0, 1e-12, 0.5, 1}
StressCaseResult binomial_case(Env& env, bool random_p, const std::string& name) {
  Rng r(name);
  struct Draw {
    double n, p, u, u_round;
  };
  std::vector<Draw> draws;
  const double ns[] = {0, 0.5, 1, 2, 10, 24, 25, 1e3, 1e6, 16777216, 16777217, 1e9, 1e12};
  const double ps[] = {0, 1e-12, 0.5, 1};
  const size_t reps = random_p ? 0 : (env.fast ? 64 : 512);
  for (double n : ns)
    for (double p : ps)
      for (size_t k = 0; k < reps; ++k) {
        double u = (double(r.g() >> 40) + 0.5) * std::ldexp(1.0, -24);
        if (k == 0) u = std::ldexp(0.5, -24);
        if (k == 1) u = 1 - std::ldexp(0.5, -24);
        draws.push_back({n, p, u, double(r.g() >> 40) * std::ldexp(1.0, -24)});
      }
  if (random_p)
    for (size_t k = 0; k < (env.fast ? 4096u : 32768u); ++k) {
      double n = r.U() < 0.5 ? std::floor(r.logu(1, 1e12)) : r.logu(1e-3, 1e12);
      double p = r.U() < 0.2 ? 1 - r.logu(1e-12, 0.5) : r.logu(1e-14, 1);
      draws.push_back({n, p, (double(r.g() >> 40) + 0.5) * std::ldexp(1.0, -24),
                       double(r.g() >> 40) * std::ldexp(1.0, -24)});
    }
  std::vector<float> in(draws.size() * kMathIn, 0.0f);
  for (size_t i = 0; i < draws.size(); ++i) {
    float* rec = &in[i * kMathIn];
    rec[2] = f32(draws[i].n), rec[3] = f32(draws[i].p), rec[4] = f32(draws[i].u), rec[5] = f32(draws[i].u_round);
  }
  auto out = core::run_compute(env.ctx, "tests/glint_math.comp", {}, in, draws.size() * kMathOut, uint32_t(draws.size()));
  ValueScan scan;
  ErrorStat err;
  size_t undecidable = 0, out_of_range = 0, ends_wrong = 0;
  for (size_t i = 0; i < draws.size(); ++i) {
    double k = out[i * kMathOut + 4];
    scan.add(k);
    double n = f32(draws[i].n), p = f32(draws[i].p), u = f32(draws[i].u), ur = f32(draws[i].u_round);
    double n_max = std::ceil(n);
    out_of_range += !(k >= 0 && k <= n_max && k == std::floor(k));
    if (p == 0 && k != 0) ++ends_wrong;
    if (p == 1 && !(k == std::floor(n) || k == std::ceil(n))) ++ends_wrong;
    gr::Slack s;
    double want = gr::binomial_draw(n, p, u, ur, &s);
    if (!(s.min > 0)) {
      ++undecidable;
      continue;
    }
    // beyond 2^23 (counts) and 2^24 (n) the GPU's count is the fp32 value nearest its draw, whose
    // final rounding the slack does not cover: |err| <= 1 + 2^-22 k
    double allow = n >= 16777216.0 || want >= 8388608.0 ? 1 + std::ldexp(want, -22) : 0.0;
    err.add(k, want, 1.0, "n " + fmt(n) + " p " + fmt(p) + " u " + fmt(u), allow);
  }
  std::string what = random_p ? "random n 1e-3 .. 1e12 (real and integer), p 1e-14 .. 1 and 1 - (1e-12 .. 0.5)"
                              : "n in {0, 0.5, 1, 2, 10, 24, 25, 1e3, 1e6, 2^24, 2^24 + 1, 1e9, 1e12} x p in {0, "
                                "1e-12, 0.5, 1}, u at the ends of (0, 1)";
  return make_result(name, "glint", scan, &err, 0.0, out_of_range == 0 && ends_wrong == 0,
                     what + "; counts integer in [0, ceil n] (" + std::to_string(out_of_range) + " not), p = 0 -> 0 "
                     "and p = 1 -> n (" + std::to_string(ends_wrong) + " not); equal to fp64 where every decision "
                     "is decidable (" + std::to_string(undecidable) + " not), beyond 2^23 within 1 + 2^-22 k "
                     "(error beyond that allowance, relative to max(k, 1), bound 0); worst: " + err.worst);
}

// ---- wrapped cell coordinates and coherent seeds (exact)
StressCaseResult wrapped_case(Env& env) {
  Rng r("glint.wrapped-cells");
  const size_t n = env.fast ? 4096 : 32768;
  std::vector<float> in(n * kMathIn, 0.0f);
  std::vector<double> xs(n);
  std::vector<std::array<uint32_t, 2>> cells(n);
  std::vector<int> levels(n);
  for (size_t i = 0; i < n; ++i) {
    double x = (r.U() < 0.5 ? -1 : 1) * r.logu(1e-3, 3e38);
    if (i < 4) x = std::vector<double>{kInf, -kInf, std::numeric_limits<double>::quiet_NaN(), -0.0}[i];
    xs[i] = f32(x);
    cells[i] = {uint32_t(r.g()), uint32_t(r.g())};
    levels[i] = int(r.g() % 29);
    float* rec = &in[i * kMathIn];
    rec[0] = f32(x);
    rec[1] = 0.5f;
    rec[6] = float(cells[i][0] >> 16), rec[7] = float(cells[i][0] & 0xFFFF);
    rec[8] = float(cells[i][1] >> 16), rec[9] = float(cells[i][1] & 0xFFFF);
    rec[10] = float(levels[i]);
  }
  auto out = core::run_compute(env.ctx, "tests/glint_math.comp", {}, in, n * kMathOut, uint32_t(n));
  ValueScan scan;
  size_t mismatch = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* o = &out[i * kMathOut];
    scan.add(o[0]), scan.add(o[1]);
    uint32_t w = (uint32_t(o[0]) << 16) | uint32_t(o[1]);
    mismatch += w != gr::wrapped_floor(xs[i]);
    auto seed = gr::coherent_seed({cells[i][0], cells[i][1]}, levels[i]);
    uint32_t su = (uint32_t(o[5]) << 16) | uint32_t(o[6]), sv = (uint32_t(o[7]) << 16) | uint32_t(o[8]);
    mismatch += su != seed[0] || sv != seed[1];
  }
  return make_result("glint.wrapped-cells-and-seeds", "glint", scan, nullptr, std::nullopt, mismatch == 0,
                     "wrapped_floor(x) mod 2^32 for |x| 1e-3 .. 3e38, +-inf, NaN, -0 and the coherent seeds of "
                     "random cells at levels 0 .. 28: exact vs fp64 (" + std::to_string(mismatch) + " mismatches)");
}

}  // namespace

void add_glint_cases(std::vector<Case>& cases) {
  const double deg = kPi / 180;
  const uint32_t Z = gr::kGlintZirr, G = gr::kGlintGrains, B = gr::kGlintBeckmann;
  Checks all{true, true, true, true, false};
  std::vector<GlintCaseSpec> specs;
  specs.push_back({"glint.footprint-1e-9-to-1e3-cells", true, {Z},
                   [](Rng& r, Item& c) {
                     double s_ref = std::pow(10.0, -0.5 * c.p.log_density);
                     double s = r.logu(1e-9, 1e3) * s_ref, ang = 2 * kPi * r.U(), an = r.logu(1, 16);
                     c.dx = vec2(std::cos(ang), std::sin(ang)) * s;
                     c.dy = vec2(-std::sin(ang), std::cos(ang)) * s / an;
                     if (r.U() < 0.5) std::swap(c.dx, c.dy);
                   },
                   {true, false, true, true, true}, 2e-3,
                   "zirr, pixel footprints 1e-9 .. 1e3 reference cells, anisotropy 1 .. 16, any orientation"});
  specs.push_back({"glint.footprint-degenerate", true, {Z},
                   [](Rng& r, Item& c) {
                     double s_ref = std::pow(10.0, -0.5 * c.p.log_density);
                     double s = r.logu(1e-3, 1e3) * s_ref, ang = 2 * kPi * r.U();
                     vec2 d = vec2(std::cos(ang), std::sin(ang)) * s;
                     const double nan = std::numeric_limits<double>::quiet_NaN();
                     switch (r.g() % 7) {
                       case 0: c.dx = c.dy = vec2(0); break;                        // zero footprint
                       case 1: c.dx = d, c.dy = vec2(0); break;                     // a segment: zero area
                       case 2: c.dx = d, c.dy = d * r.logu(0.01, 100); break;       // parallel: zero area
                       case 3: c.dx = d * 1e6, c.dy = vec2(-d.y, d.x) * 1e-6; break;  // anisotropy 1e12
                       case 4: c.dx = vec2(1e30, -3e29), c.dy = d; break;           // huge
                       case 5: c.dx = vec2(kInf, 1), c.dy = d; break;               // infinite
                       default: c.dx = d, c.dy = vec2(nan, 1e-3); break;            // NaN
                     }
                   },
                   {true, false, true, true, true}, 2e-3,
                   "zirr, footprints of zero area (zero, segment, parallel edges), anisotropy 1e12, 1e30, inf and NaN "
                   "derivatives"});
  specs.push_back({"glint.zirr-density-1e-3-to-1e12", true, {Z},
                   [](Rng& r, Item& c) {
                     c.p.log_density = -3 + 15 * r.U();
                     double s_ref = std::pow(10.0, -0.5 * c.p.log_density);
                     double s = r.logu(0.01, 100) * s_ref, ang = 2 * kPi * r.U();
                     c.dx = vec2(std::cos(ang), std::sin(ang)) * s;
                     c.dy = vec2(-std::sin(ang), std::cos(ang)) * s * r.logu(0.1, 1);
                     c.uv = vec2(r.U(), r.U()) * std::min(10.0, 1000 * s_ref);
                     if (r.U() < 0.5) c.p.size_variation = 0.5 * r.U();
                   },
                   {true, false, true, true, false}, 2e-3, "zirr at 1e-3 .. 1e12 microdetails per uv unit, size variation 0 .. 0.5"});
  specs.push_back({"glint.grains-density-1e-3-to-1e12", false, {G},
                   [](Rng& r, Item& c) {
                     c.p.log_density = -3 + 15 * r.U();
                     c.uv = vec2(r.U(), r.U()) * 10.0;
                   },
                   {false, true, true, true, true}, 2e-3, "grains at 1e-3 .. 1e12 microdetails per uv unit"});
  for (uint32_t m : {G, Z, B}) {
    std::string mn = gr::twin_name(m);
    specs.push_back({"glint.grazing-view." + mn, m == Z, {m},
                     [deg](Rng& r, Item& c) {
                       vec3 t1 = c.t, t2 = c.b * (glm::dot(glm::cross(c.t, c.b), c.n) > 0 ? 1.0 : -1.0);
                       auto at = [&](double th) {
                         double ph = 2 * kPi * r.U();
                         return glm::normalize(std::cos(th) * c.n + std::sin(th) * (std::cos(ph) * t1 + std::sin(ph) * t2));
                       };
                       c.wo = at((80 + 9.99 * r.U()) * deg);
                       if (r.U() < 0.2) c.wo = at(89.99 * deg);
                       // light in the mirror direction of a random slope, or grazing too
                       vec3 h = glm::normalize(c.n + 0.3 * r.unit());
                       c.wi = glm::normalize(2.0 * glm::dot(c.wo, h) * h - c.wo);
                       if (glm::dot(c.wi, c.n) <= 0 || r.U() < 0.3) c.wi = at((80 + 9.99 * r.U()) * deg);
                     },
                     all, 2e-3, mn + ", view 80 .. 89.99 deg from the normal"});
    specs.push_back({"glint.backlit." + mn, false, {m},
                     [](Rng& r, Item& c) {
                       if (r.U() < 0.7) c.wi = -c.wo;  // exactly opposite: h undefined, no lobe
                       else c.wi = c.wo;               // retro-reflection: h = w_o
                     },
                     all, 2e-3, mn + ", w_i = -w_o (70 %) and w_i = w_o"});
  }
  specs.push_back({"glint.roughness-0-and-1", true, {G, Z, B},
                   [](Rng& r, Item& c) {
                     const double a[] = {0.0, 1e-3, 1.0};
                     c.p.alpha_g = vec2(a[r.g() % 3], a[r.g() % 3]);
                     c.p.relative = vec2(r.U() < 0.5 ? 1e-3 : 1.0, r.U() < 0.5 ? 1e-3 : 1.0);
                     if (r.U() < 0.5) c.p.light_cone = 0;  // no widening: alpha_g = 0 stays 0
                   },
                   all, 2e-3,
                   "alpha_g in {0 (below the validated 1e-3: the raw GPU struct), 1e-3, 1}, relative roughness in "
                   "{1e-3, 1} (alpha_m = 0: the stretch clamp), light cone 0 in half"});
  specs.push_back({"glint.huge-uv", false, {G, Z, B},
                   [](Rng& r, Item& c) {
                     const double nan = std::numeric_limits<double>::quiet_NaN();
                     double u = r.U();
                     c.uv = vec2(r.N(), r.N()) * (u < 0.6 ? r.logu(1e3, 1e6) : r.logu(1e6, 3e38));
                     if (u > 0.95) c.uv = vec2(nan, kInf);
                   },
                   {false, false, true, true, true}, 2e-3,
                   "uv up to 1e6 (object coordinates) and beyond to 3e38, inf, NaN: wrapped cells; finite, energy "
                   "bounded"});
  for (auto& s : specs)
    cases.push_back({s.name, "glint", s.fast, [s](Env& env) { return run_glint_case(env, s); }});
  cases.push_back({"glint.energy-zirr-vs-beckmann", "glint", true, [](Env& env) { return energy_case(env, env.fast); }});
  cases.push_back({"glint.binomial-n1e12-p-0-1e-12-half-1", "glint", true,
                   [](Env& env) { return binomial_case(env, false, "glint.binomial-n1e12-p-0-1e-12-half-1"); }});
  cases.push_back({"glint.binomial-random", "glint", false,
                   [](Env& env) { return binomial_case(env, true, "glint.binomial-random"); }});
  cases.push_back({"glint.wrapped-cells-and-seeds", "glint", false, wrapped_case});
}

}  // namespace glintlab::stress

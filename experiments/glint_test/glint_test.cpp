#include "experiments/glint_test/glint_test.h"

#include "core/material/glint_table.h"

#include "core/material/sand_material.h"
#include "core/util/json_check.h"
#include "core/vk/compute_harness.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>

namespace glintlab {

namespace {

using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
constexpr double kPi = 3.14159265358979323846;
constexpr size_t kIn = 28, kOut = 8;  // shaders/glint/conformance.comp

// One evaluation of the model (an input record of conformance.comp).
struct Query {
  vec2 uv{0.5}, dx{0.0}, dy{0.0};
  vec3 wi{0, 0, 1}, wo{0, 0, 1};
  vec2 alpha{0.3}, relative{0.1};
  double log_density = 7, light_cone = 0;
};

struct Value {
  vec3 D;
  double limit = 0;
  bool valid = false;
  double mean() const { return (D.x + D.y + D.z) / 3.0; }
};

class Evaluator {
 public:
  Evaluator(core::VkContext& ctx, const core::GlintModelDecl& d, const std::vector<float>& params)
      : ctx_(ctx), defines_(core::glint_model_defines(d)), params_(params), table_(core::glint_table(ctx, d)) {}
  std::vector<Value> operator()(const std::vector<Query>& qs, std::vector<float>* raw = nullptr) const {
    std::vector<float> in(qs.size() * kIn, 0.0f);
    for (size_t i = 0; i < qs.size(); ++i) {
      float* r = &in[i * kIn];
      const Query& q = qs[i];
      auto p2 = [&](size_t o, vec2 v) { r[o] = float(v.x), r[o + 1] = float(v.y); };
      auto p3 = [&](size_t o, vec3 v) { r[o] = float(v.x), r[o + 1] = float(v.y), r[o + 2] = float(v.z); };
      p2(0, q.uv), p2(2, q.dx), p2(4, q.dy), p3(6, q.wi), p3(9, q.wo), p2(12, q.alpha), p2(14, q.relative);
      r[16] = float(q.log_density);
      r[17] = float(q.light_cone);
      for (size_t k = 0; k < params_.size(); ++k) r[20 + k] = params_[k];
    }
    std::vector<float> out;
    const size_t chunk = size_t(1) << 20;
    for (size_t b = 0; b < qs.size(); b += chunk) {
      const size_t n = std::min(chunk, qs.size() - b);
      std::vector<float> part(in.begin() + long(b * kIn), in.begin() + long((b + n) * kIn));
      auto o = core::run_compute(ctx_, "glint/conformance.comp", defines_, part, n * kOut, uint32_t(n),
                                 table_->empty() ? nullptr : table_.get());
      out.insert(out.end(), o.begin(), o.end());
    }
    std::vector<Value> v(qs.size());
    for (size_t i = 0; i < qs.size(); ++i) {
      const float* o = &out[i * kOut];
      v[i] = {vec3(o[0], o[1], o[2]), o[3], o[4] > 0.5f};
    }
    if (raw) *raw = std::move(out);
    return v;
  }

 private:
  core::VkContext& ctx_;
  std::vector<std::string> defines_;
  std::vector<float> params_;
  std::shared_ptr<const std::vector<float>> table_;  // the model's data table (empty: none)
};

vec3 direction(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

// w_i that makes h the half vector of (w_i, w_o): the mirror of w_o about h.
vec3 mirror(vec3 wo, vec3 h) { return 2.0 * glm::dot(wo, h) * h - wo; }

// Half vector at slope offset (s alpha_u, s alpha_v / 2) from the normal.
vec3 half_vector(vec2 alpha, double s) { return glm::normalize(vec3(s * alpha.x, 0.5 * s * alpha.y, 1.0)); }

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= n, mb /= n;
  double saa = 0, sbb = 0, sab = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
    sab += (a[i] - ma) * (b[i] - mb);
  }
  // a model constant over positions gives equal values everywhere: coherent by definition
  const double scale = std::max(ma * ma, mb * mb) * n;
  if (!(saa > 1e-18 * scale) && !(sbb > 1e-18 * scale)) return 1.0;
  if (!(saa > 0) || !(sbb > 0)) return 0.0;
  return sab / std::sqrt(saa * sbb);
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream o;
  o << std::setprecision(prec) << v;
  return o.str();
}

// The grid (stated in the README and the report): alpha_g u in {0.05, 0.15, 0.5}, isotropic and
// 4:1 (alpha_v = alpha_u / 4), relative roughness 0.1, no light cone.
std::vector<vec2> alpha_grid() {
  std::vector<vec2> out;
  for (double a : {0.05, 0.15, 0.5})
    for (double aniso : {1.0, 4.0}) out.push_back(vec2(a, a / aniso));
  return out;
}

// A check whose figure is a count of defects, bound 0.
GlintCheckResult count_check(const std::string& name, size_t defects, const std::string& unit, const std::string& detail) {
  GlintCheckResult r;
  r.name = name;
  r.figure = double(defects);
  r.bound = 0;
  r.unit = unit;
  r.pass = defects == 0;
  r.detail = detail;
  return r;
}

GlintCheckResult check_finite(const Evaluator& eval) {
  // the stress inputs: every combination of the extremes, drawn at random
  std::mt19937_64 rng(0x6c696e6974ull);
  auto pick = [&](const std::vector<double>& v) { return v[rng() % v.size()]; };
  std::vector<Query> qs;
  const size_t n = 20000;
  for (size_t i = 0; i < n; ++i) {
    Query q;
    q.alpha = vec2(pick({1e-3, 0.05, 0.3, 1.0}), pick({1e-3, 0.05, 0.3, 1.0}));
    q.relative = vec2(pick({1e-3, 0.1, 1.0}), pick({1e-3, 0.1, 1.0}));
    q.log_density = pick({-3.0, 1.0, 7.0, 14.0});
    q.light_cone = pick({0.0, 0.0046, 0.5});
    const double u = pick({0.0, 0.37, 1e7, -1e7});
    q.uv = vec2(u + pick({0.0, 0.25}), pick({0.0, 1e7, -3.5}));
    const double w = pick({0.0, 1e-12, 1e-6, 1e-3, 1.0, 1e3});
    q.dx = vec2(w, pick({0.0, w * 0.5}));
    q.dy = vec2(pick({0.0, -w * 0.3}), w * pick({1.0, 1e-6, 1e6}));
    const double th_o = pick({0.0, 45.0, 80.0, 89.0, 89.9, 89.99});
    const double th_i = pick({0.0, 45.0, 80.0, 89.0, 89.9, 89.99});
    q.wo = direction(th_o, pick({0.0, 90.0, 200.0}));
    q.wi = rng() % 2 ? mirror(q.wo, vec3(0, 0, 1)) : direction(th_i, pick({0.0, 180.0, 30.0}));
    qs.push_back(q);
  }
  auto v = eval(qs);
  size_t bad = 0, nan = 0, inf = 0, neg = 0;
  for (const auto& x : v)
    for (double c : {x.D.x, x.D.y, x.D.z}) {
      nan += std::isnan(c);
      inf += std::isinf(c);
      neg += c < 0;
      bad += !(std::isfinite(c) && c >= 0);
    }
  return count_check("finite", bad, "NaN/Inf/negative values",
                     std::to_string(n) + " queries x 3 channels: grazing (to 89.99 deg), zero to 1e3 footprints "
                     "(1e6:1), uv to 1e7, alpha_g and relative roughness 1e-3 and 1, log_density -3 to 14, light cone "
                     "0 to 0.5; NaN " + std::to_string(nan) + ", Inf " + std::to_string(inf) + ", negative " +
                     std::to_string(neg));
}

struct BiasCase {
  std::string what;
  std::vector<Query> qs;
};

// Many random uv positions at one footprint, half vector, roughness and density.
std::vector<BiasCase> bias_cases(size_t positions) {
  std::vector<BiasCase> out;
  std::mt19937_64 rng(0x756e626961ull);
  std::uniform_real_distribution<double> U(0.0, 1000.0);
  for (vec2 a : alpha_grid())
    for (double ld : {1.0, 4.0, 8.0})
      for (double th : {0.0, 60.0, 85.0})
        for (double s : {0.0, 0.7})
          for (double cells : {1.0, 16.0}) {
            BiasCase c;
            const double s_ref = std::pow(10.0, -0.5 * ld), w = cells * s_ref;
            vec3 h = half_vector(a, s), wo = direction(th, 20.0), wi = mirror(wo, h);
            if (!(wi.z > 1e-3)) continue;
            c.what = "alpha " + fmt(a.x) + "/" + fmt(a.y) + " log_density " + fmt(ld) + " view " + fmt(th) +
                     " deg slope " + fmt(s) + " alpha footprint " + fmt(cells) + " cells";
            for (size_t i = 0; i < positions; ++i) {
              Query q;
              q.alpha = a;
              q.log_density = ld;
              q.uv = vec2(U(rng), U(rng));
              q.dx = vec2(w, 0);
              q.dy = vec2(0, w);
              q.wo = wo;
              q.wi = wi;
              c.qs.push_back(q);
            }
            out.push_back(std::move(c));
          }
  return out;
}

constexpr size_t kBiasPositions = 16384;
constexpr double kBiasSigmas = 5.0;

// unbiased, and deterministic (the same queries dispatched twice).
std::pair<GlintCheckResult, GlintCheckResult> check_unbiased(const Evaluator& eval) {
  auto cases = bias_cases(kBiasPositions);
  std::vector<Query> all;
  for (const auto& c : cases) all.insert(all.end(), c.qs.begin(), c.qs.end());
  std::vector<float> raw1, raw2;
  auto v = eval(all, &raw1);
  eval(all, &raw2);
  size_t differ = 0;
  for (size_t i = 0; i < raw1.size(); ++i) differ += std::memcmp(&raw1[i], &raw2[i], sizeof(float)) != 0;
  GlintCheckResult det = count_check("deterministic", differ, "output values that differ between two dispatches",
                                     std::to_string(all.size()) +
                                         " queries (the unbiased check's), dispatched twice, compared bit for bit");

  GlintCheckResult r;
  r.name = "unbiased";
  r.bound = kBiasSigmas;
  r.unit = "standard errors";
  double worst = 0;
  std::string worst_what;
  size_t at = 0, used = 0;
  for (const auto& c : cases) {
    double sum = 0, sum2 = 0, limit = 0;
    for (size_t i = 0; i < c.qs.size(); ++i) {
      const Value& x = v[at + i];
      const double d = x.mean();
      sum += d;
      sum2 += d * d;
      limit = x.limit;
    }
    at += c.qs.size();
    const double n = double(c.qs.size()), mean = sum / n;
    const double var = std::max(0.0, sum2 / n - mean * mean) * n / (n - 1);
    // fp32: 1e-4 of D_g absorbs the rounding of a deterministic model (var = 0)
    const double se = std::sqrt(var / n) + 1e-4 * limit / kBiasSigmas;
    const double z = std::isfinite(mean) ? std::fabs(mean - limit) / se : INFINITY;
    ++used;
    if (worst_what.empty() || !(z <= worst)) {
      worst = z;
      worst_what = c.what + ": mean " + fmt(mean, 5) + " vs D_g " + fmt(limit, 5) + " (+-" + fmt(se, 3) + ")";
    }
  }
  r.figure = worst;
  r.pass = worst <= kBiasSigmas;
  r.detail = "largest |mean - D_g| / standard error over " + std::to_string(used) + " configurations of " +
             std::to_string(kBiasPositions) + " uniform uv positions in [0, 1000)^2 each (the standard error from the "
             "sample variance, CLT: P(|z| > 5) = 5.7e-7 per configuration); worst: " + worst_what;
  return {r, det};
}

GlintCheckResult check_limit(const Evaluator& eval) {
  std::vector<Query> qs;
  std::mt19937_64 rng(0x6c696d6974ull);
  std::uniform_real_distribution<double> U(0.0, 1000.0);
  const size_t per = 16;
  for (vec2 a : alpha_grid())
    for (double th : {0.0, 30.0, 60.0, 85.0})
      for (double s : {0.0, 0.7}) {
        vec3 h = half_vector(a, s), wo = direction(th, 20.0), wi = mirror(wo, h);
        if (!(wi.z > 1e-3)) continue;
        for (size_t i = 0; i < per; ++i) {
          Query q;
          q.alpha = a;
          q.log_density = 14;
          q.uv = vec2(U(rng), U(rng));
          q.dx = vec2(1e-3, 0);
          q.dy = vec2(0, 1e-3);
          q.wo = wo;
          q.wi = wi;
          qs.push_back(q);
        }
      }
  auto v = eval(qs);
  double worst = 0;
  for (const auto& x : v) {
    const double e = x.limit > 0 ? std::fabs(x.mean() - x.limit) / x.limit : (x.mean() == 0 ? 0.0 : INFINITY);
    if (!(e <= worst)) worst = e;
  }
  GlintCheckResult r;
  r.name = "limit";
  r.figure = 100 * worst;
  r.bound = 3;
  r.unit = "% largest relative error";
  r.pass = worst <= 0.03;
  r.detail = std::to_string(qs.size()) + " single evaluations, 10^14 microdetails per uv area over a 1e-3 x 1e-3 "
             "footprint (1e8 microdetails), the roughness grid, views 0-85 deg, half vectors at slope 0 and 0.7 alpha";
  return r;
}

// LOD and shift coherence: correlations over random positions between the model over a footprint
// and the mean over its four half-size sub-footprints, and over the footprint moved by 1/4 width.
std::pair<GlintCheckResult, GlintCheckResult> check_coherence(const Evaluator& eval) {
  const size_t n = 4096;
  std::mt19937_64 rng(0x636f6865ull);
  std::uniform_real_distribution<double> U(0.0, 1000.0);
  const double ld = 6, w = 4 * std::pow(10.0, -0.5 * ld);  // a footprint 4 microdetail cells wide
  const vec2 a(0.3, 0.3);
  const vec3 wo = direction(30, 20), wi = mirror(wo, half_vector(a, 0.3));
  std::vector<Query> qs;
  for (size_t i = 0; i < n; ++i) {
    Query q;
    q.alpha = a;
    q.log_density = ld;
    q.wo = wo;
    q.wi = wi;
    q.uv = vec2(U(rng), U(rng));
    q.dx = vec2(w, 0);
    q.dy = vec2(0, w);
    qs.push_back(q);  // the footprint
    for (int k = 0; k < 4; ++k) {  // its four half-size sub-footprints
      Query s = q;
      s.uv = q.uv + ((k & 1) ? 0.25 : -0.25) * q.dx + ((k & 2) ? 0.25 : -0.25) * q.dy;
      s.dx = 0.5 * q.dx;
      s.dy = 0.5 * q.dy;
      qs.push_back(s);
    }
    Query m = q;  // moved by a quarter of its width
    m.uv = q.uv + 0.25 * q.dx;
    qs.push_back(m);
  }
  auto v = eval(qs);
  std::vector<double> whole, subs, moved;
  for (size_t i = 0; i < n; ++i) {
    const Value* x = &v[i * 6];
    whole.push_back(x[0].mean());
    subs.push_back(0.25 * (x[1].mean() + x[2].mean() + x[3].mean() + x[4].mean()));
    moved.push_back(x[5].mean());
  }
  const std::string where = std::to_string(n) + " random positions, footprint 4 microdetail cells wide (log_density 6), "
                            "alpha_g 0.3, view 30 deg, half vector at slope 0.3 alpha";
  GlintCheckResult lod, shift;
  lod.name = "LOD coherence";
  lod.figure_only = true;
  lod.figure = correlation(whole, subs);
  lod.unit = "correlation (1: the exact box filter of a point model)";
  lod.detail = "the model over a footprint vs the mean over its four half-size sub-footprints; " + where;
  shift.name = "shift coherence";
  shift.figure_only = true;
  shift.figure = correlation(whole, moved);
  shift.unit = "correlation";
  shift.detail = "the model over a footprint vs over the footprint moved by 1/4 of its width; " + where;
  return {lod, shift};
}

}  // namespace

core::GlintModelDecl resolve_glint_model(const std::string& m) {
  if (const core::GlintModelDecl* d = core::find_builtin_glint_model(m)) return *d;
  if (m.find('/') == std::string::npos && m.find(".glsl") == std::string::npos) {
    std::string list;
    for (const auto& b : core::builtin_glint_models()) list += (list.empty() ? "" : ", ") + b.name;
    throw ConfigError("glint-test: \"" + m + "\" is neither a built-in glint_D model (" + list +
                      ") nor a .glsl file");
  }
  return core::glint_model_from_file(m);
}

std::vector<float> glint_test_parameters(const core::GlintModelDecl& d, const std::vector<std::string>& overrides) {
  std::vector<float> out;
  for (const auto& p : d.parameters) out.push_back(float(p.def));
  for (const auto& kv : overrides) {
    const size_t eq = kv.find('=');
    const std::string k = kv.substr(0, eq), v = eq == std::string::npos ? "" : kv.substr(eq + 1);
    size_t i = 0;
    while (i < d.parameters.size() && d.parameters[i].name != k) ++i;
    std::string names;
    for (const auto& p : d.parameters) names += (names.empty() ? "" : ", ") + p.name;
    if (i == d.parameters.size())
      throw ConfigError("glint-test --parameters " + kv + ": " + d.name + " has no parameter \"" + k + "\"" +
                        (names.empty() ? "; it has none" : "; its parameters: " + names));
    const core::GlintParameter& p = d.parameters[i];
    double x = 0;
    if (p.is_bool) {
      if (v != "true" && v != "false" && v != "1" && v != "0")
        throw ConfigError("glint-test --parameters " + kv + ": " + k + " is a bool; allowed true or false");
      x = (v == "true" || v == "1") ? 1.0 : 0.0;
    } else {
      std::istringstream in(v);
      if (!(in >> x) || in.peek() != std::char_traits<char>::eof() || !std::isfinite(x) || x < p.lo || x > p.hi)
        throw ConfigError("glint-test --parameters " + kv + ": " + k + " must be a number in [" + fmt(p.lo, 6) +
                          ", " + fmt(p.hi, 6) + "]");
    }
    out[i] = float(x);
  }
  return out;
}

GlintTestReport run_glint_test(core::VkContext& ctx, const core::GlintModelDecl& d, const std::vector<float>& params) {
  GlintTestReport r;
  r.suite = "glint-test";
  r.subject_key = "model";
  r.subject = d.name;
  r.file = d.file;
  r.device = ctx.info().name;
  for (size_t i = 0; i < d.parameters.size(); ++i) r.parameters[d.parameters[i].name] = params[i];
  Evaluator eval(ctx, d, params);
  GlintCheckResult finite = check_finite(eval);
  auto [unbiased, deterministic] = check_unbiased(eval);
  GlintCheckResult limit = check_limit(eval);
  auto [lod, shift] = check_coherence(eval);
  for (GlintCheckResult* c : {&finite, &unbiased, &limit, &deterministic}) apply_declaration(*c, d.checks, d.fails);
  r.checks = {finite, unbiased, limit, deterministic, lod, shift};
  return r;
}

void add_glint_test_command(CLI::App& app, int& exit_code) {
  add_conformance_command(
      app, exit_code, "glint-test",
      "the conformance suite of a glint model (built-in name or .glsl file): finite, unbiased, limit, "
      "deterministic, LOD and shift coherence on the GPU (exit 1 if a declared check fails)",
      "model", "a built-in glint_D model (see `list`) or a model file", [](const ConformanceCommandOptions& o) {
        const core::GlintModelDecl d = resolve_glint_model(o.subject);
        const std::vector<float> params = glint_test_parameters(d, o.parameters);
        return ConformanceSuite([d, params](core::VkContext& ctx) { return run_glint_test(ctx, d, params); });
      });
}

}  // namespace glintlab

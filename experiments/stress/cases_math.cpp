// Stress cases of the shared shader helpers and the sand's scalar terms:
// shaders/tests/stress_math.comp against the fp64 twins (core/material/fp64)
// and core::sand_sigmoid (the stable sigmoid in double) on extreme arguments.
// err = |gpu - fp64| / max(|fp64|, floor) with the floor each case states.
#include "core/material/fp64/glint_fp64.h"
#include "core/material/fp64/sand_fp64.h"
#include "core/material/sand_material.h"
#include "core/vk/compute_harness.h"
#include "experiments/stress/stress_internal.h"

#include <glm/geometric.hpp>

#include <array>

namespace glintlab::stress {

namespace {

namespace ref = glintlab::reference::sand;
using ref::vec3;

constexpr size_t kIn = 16, kOut = 16;  // strides of shaders/tests/stress_math.comp

using Record = std::array<float, kIn>;

std::vector<float> run_math(Env& env, const std::vector<Record>& recs) {
  std::vector<float> in(recs.size() * kIn);
  for (size_t i = 0; i < recs.size(); ++i) std::copy(recs[i].begin(), recs[i].end(), in.begin() + i * kIn);
  return core::run_compute(env.ctx, "tests/stress_math.comp", {}, in, recs.size() * kOut, uint32_t(recs.size()));
}

void put3(Record& r, size_t o, const vec3& v) {
  r[o] = f32(v.x), r[o + 1] = f32(v.y), r[o + 2] = f32(v.z);
}
vec3 get3(const Record& r, size_t o) { return vec3(r[o], r[o + 1], r[o + 2]); }
vec3 out3(const float* o) { return vec3(o[0], o[1], o[2]); }

size_t count(bool fast, size_t full) { return fast ? full / 4 : full * 8; }

vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> N;
  return glm::normalize(vec3(N(rng), N(rng), N(rng)));
}
vec3 at_angle(std::mt19937_64& rng, const vec3& axis, double theta) {
  vec3 t1, t2;
  ref::frisvad_basis(axis, t1, t2);
  double phi = 2 * kPi * std::uniform_real_distribution<double>()(rng);
  return glm::normalize(std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * t1 + std::sin(phi) * t2));
}

// ---- sigmoid of eq. 4.37 (shaders/sand/transition.glsl) and stable_logistic
StressCaseResult sigmoid_case(Env& env) {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  const double xs[] = {-3e38, -1e6, -1.0, 0.0, 1.3, 1e3, 1e6, 3e38};
  const double as[] = {1e-6, 1e-2, 2.0, 1e2, 1e3, 1e4};
  const double bs[] = {0.0, 1.3, 1e3, 1e6, 1e7};
  for (double x : xs)
    for (double a : as)
      for (double b : bs) recs.push_back({0, f32(x), f32(a), f32(b), f32(a * (x - b))});
  for (size_t i = 0; i < count(env.fast, 8192); ++i) {
    // near the midpoint, where the exponent is moderate: b in [0, 1e6], x = b (1 + small)
    double a = log_uniform(rng, 1e-3, 1e4), b = U(rng) < 0.2 ? 1e6 : log_uniform(rng, 1e-3, 1e6);
    double x = b + (U(rng) - 0.5) * 200.0 / a;
    if (U(rng) < 0.3) x = log_uniform(rng, 1e-3, 1e6);
    recs.push_back({0, f32(x), f32(a), f32(b), f32(std::ldexp(U(rng) - 0.5, int(rng() % 256) - 128))});
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  size_t out_of_range = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    scan.add(o[0]);
    scan.add(o[1]);
    out_of_range += !(o[0] <= 1 && o[1] <= 1);
    // fp64 of the same fp32 arguments, with the GLSL's fp32 roundings of x - b and a (x - b): the
    // sigmoid's own error is measured, not the conditioning of exp at |z| up to 88
    float d = f32(double(recs[i][1]) - double(recs[i][3]));
    float z = f32(double(recs[i][2]) * double(d));
    double want = core::sand_sigmoid(double(z), 1.0, 0.0);
    err.add(o[0], want, 1e-30, "sig(" + fmt(recs[i][1]) + ", " + fmt(recs[i][2]) + ", " + fmt(recs[i][3]) + ")");
    err.add(o[1], core::sand_sigmoid(double(recs[i][4]), 1.0, 0.0), 1e-30, "logistic(" + fmt(recs[i][4]) + ")");
  }
  auto r = make_result("math.sigmoid-stable", "math", scan, &err, 2e-5, out_of_range == 0,
                       "sig(x, a, b) for x to +-3e38, a to 1e4, b to 1e7, and near the midpoint; fp64 stable "
                       "logistic of the fp32-rounded exponent, floor 1e-30 (exp in fp32 carries 1.2e-7 |z| relative, "
                       "<= 1.1e-5 where the value is a normal fp32 number); worst: " + err.worst);
  return r;
}

// ---- Frisvad / Duff et al. basis (common/frisvad.glsl) at n = +-z
StressCaseResult frisvad_case(Env& env) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  std::vector<vec3> ns = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
  for (size_t i = 0; i < count(env.fast, 8192); ++i) {
    double e = log_uniform(rng, 1e-12, 1e-2), s = U(rng) < 0.5 ? -1.0 : 1.0;
    double phi = 2 * kPi * U(rng);
    vec3 n = U(rng) < 0.8 ? glm::normalize(vec3(e * std::cos(phi), e * std::sin(phi), s)) : random_unit(rng);
    ns.push_back(n);
  }
  for (const vec3& n : ns) {
    Record r{1};
    put3(r, 1, n);  // the fp64 reference reads the same fp32 components
    recs.push_back(r);
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  double ortho = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    for (int k = 0; k < 6; ++k) scan.add(o[k], false);
    vec3 n = get3(recs[i], 1);
    vec3 b1, b2;
    ref::frisvad_basis(n, b1, b2);
    vec3 g1 = out3(o), g2 = out3(o + 3);
    for (int k = 0; k < 3; ++k) {
      err.add(g1[k], b1[k], 1.0, "n = (" + fmt(n.x) + ", " + fmt(n.y) + ", " + fmt(n.z) + ") b1");
      err.add(g2[k], b2[k], 1.0, "n = (" + fmt(n.x) + ", " + fmt(n.y) + ", " + fmt(n.z) + ") b2");
    }
    vec3 nu = glm::normalize(n);
    ortho = std::max({ortho, std::fabs(glm::dot(g1, g2)), std::fabs(glm::dot(g1, nu)), std::fabs(glm::dot(g2, nu)),
                      std::fabs(glm::length(g1) - 1), std::fabs(glm::length(g2) - 1),
                      glm::length(glm::cross(g1, g2) - nu)});
  }
  auto r = make_result("math.frisvad-basis-pm-z", "math", scan, &err, 1e-6, ortho <= 1e-6,
                       "n = +z, -z and within 1e-12 .. 1e-2 of them; basis components vs fp64 (floor 1: absolute), "
                       "orthonormality and handedness within 1e-6 (max " + fmt(ortho) + "); worst: " + err.worst);
  r.extra["orthonormality_error"] = ortho;
  return r;
}

// ---- safe_normalize (common/math.glsl) of tiny, huge and non-finite vectors
StressCaseResult normalize_case(Env& env) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<vec3> special = {{0, 0, 0}, {1e-45, 0, 0}, {1e-38, -1e-38, 0}, {3e38, 3e38, 3e38}, {-3e38, 1, 0},
                               {kInf, 0, 0}, {nan, 1, 0}, {1e-30, 1e-30, 1e-30}, {2e-30, 0, 0}};
  for (size_t i = 0; i < count(env.fast, 8192); ++i) {
    double s = std::ldexp(1.0, int(rng() % 250) - 100);  // 2^-100 .. 2^149 (fp32 overflows at 2^128)
    vec3 v = random_unit(rng) * s;
    if (U(rng) < 0.2) v.y *= 1e-30;
    special.push_back(v);
  }
  for (const vec3& v : special) {
    Record r{2};
    put3(r, 1, v);
    recs.push_back(r);
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  size_t not_unit = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    for (int k = 0; k < 3; ++k) scan.add(o[k], false);
    vec3 v = get3(recs[i], 1), g = out3(o);
    not_unit += !(std::fabs(glm::length(g) - 1) <= 1e-6);
    double m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    bool fallback = !(m > double(f32(1e-30))) || !std::isfinite(m);
    vec3 want = fallback ? vec3(0, 0, 1) : v / glm::length(v / m) / m;
    for (int k = 0; k < 3; ++k) err.add(g[k], want[k], 1.0, "v = (" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + ")");
  }
  return make_result("math.safe-normalize", "math", scan, &err, 1e-6, not_unit == 0,
                     "vectors 2^-100 .. 3e38, zero, denormal, infinite, NaN (-> the fallback z); components vs fp64 "
                     "(floor 1), |result| = 1 within 1e-6 (" + std::to_string(not_unit) + " not); worst: " + err.worst);
}

// ---- Oren-Nayar (sand/oren_nayar.glsl) near 0 and 90 degrees
StressCaseResult oren_nayar_case(Env& env) {
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> U;
  const double deg = kPi / 180;
  std::vector<Record> recs;
  for (size_t i = 0; i < count(env.fast, 16384); ++i) {
    vec3 n = U(rng) < 0.3 ? vec3(0, 0, U(rng) < 0.5 ? 1 : -1) : random_unit(rng);
    auto angle = [&] {
      double u = U(rng);
      if (u < 0.25) return 0.0;
      if (u < 0.5) return log_uniform(rng, 1e-7, 1e-2);
      if (u < 0.75) return 90 * deg - log_uniform(rng, 1e-7, 1e-2);
      return u < 0.85 ? 90 * deg : U(rng) * 90 * deg;
    };
    vec3 wi = at_angle(rng, n, angle()), wo = at_angle(rng, n, angle());
    if (U(rng) < 0.1) wo = wi;
    if (U(rng) < 0.1) wo = at_angle(rng, n, 90 * deg + log_uniform(rng, 1e-7, 0.1));  // just below the horizon
    double sigma = U(rng) < 0.3 ? kPi / 2 : (U(rng) < 0.2 ? 0.0 : U(rng) * kPi / 2);
    Record r{3};
    put3(r, 1, n);
    put3(r, 4, wi);
    put3(r, 7, wo);
    r[10] = f32(sigma);
    r[11] = U(rng) < 0.2 ? 32.0f : 0.0f;
    recs.push_back(r);
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  double raw_max = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    scan.add(o[0]);
    scan.add(o[1]);
    raw_max = std::max(raw_max, double(o[0]));
    vec3 n = get3(recs[i], 1), wi = get3(recs[i], 4), wo = get3(recs[i], 7);
    double L = ref::L_oren(n, wi, wo, recs[i][10], uint32_t(recs[i][11]));
    double cos_ni = std::max(0.0, glm::dot(n, wi));
    err.add(o[1], L * cos_ni, 1.0, "theta_i " + fmt(std::acos(std::min(1.0, glm::dot(n, wi))) / deg) + " theta_o " +
                                        fmt(std::acos(std::max(-1.0, std::min(1.0, glm::dot(n, wo)))) / deg));
  }
  auto r = make_result("math.oren-nayar-0-90deg", "math", scan, &err, 1e-3, true,
                       "theta_i, theta_o at 0, 1e-7 .. 1e-2 rad from 0 and from 90 deg, 90 deg, just below the "
                       "horizon, sigma 0 .. pi/2, chapter 4 and world frames; L_oren max(0, n.w_i) (the product "
                       "L_brdf uses, A + B <= 1.5) vs fp64, floor 1 (the product's scale: rho/pi L_i times it is the radiance); L_oren alone peaks at " + fmt(raw_max) +
                           " (tan beta, finite); worst: " + err.worst);
  r.extra["L_oren_max"] = raw_max;
  return r;
}

// ---- grain cells: wrapped keys and pcg3d at huge coordinates (exact)
StressCaseResult grain_key_case(Env& env) {
  std::mt19937_64 rng(53);
  std::uniform_real_distribution<double> U;
  std::normal_distribution<double> N;
  std::vector<Record> recs;
  for (size_t i = 0; i < count(env.fast, 16384); ++i) {
    double scale = U(rng) < 0.3 ? 1e6 : log_uniform(rng, 1, 1e6);
    double mag = U(rng) < 0.1 ? log_uniform(rng, 1e6, 3e38) : log_uniform(rng, 1e-6, 1e6);
    vec3 x = vec3(N(rng), N(rng), N(rng)) * mag;
    if (U(rng) < 0.05) x.x = U(rng) < 0.5 ? kInf : -0.0;
    Record r{4};
    put3(r, 1, x);
    r[4] = f32(scale);
    r[5] = U(rng) < 0.3 ? 1.0f : 0.0f;
    recs.push_back(r);
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  size_t key_mismatch = 0, xi_mismatch = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    for (int k = 6; k < 9; ++k) scan.add(o[k]);
    std::array<float, 3> x{recs[i][1], recs[i][2], recs[i][3]};
    auto key = ref::grain_cell_key(x, recs[i][4]);
    auto gr = ref::grain_random(key, uint32_t(recs[i][5]));
    for (int k = 0; k < 3; ++k) {
      uint32_t g = (uint32_t(o[2 * k]) << 16) | uint32_t(o[2 * k + 1]);
      key_mismatch += g != key[k];
      if (recs[i][5] == 0) xi_mismatch += o[6 + k] != gr.xi[k];
      else err.add(o[6 + k], gr.xi[k], 1.0, "normalised xi");
    }
  }
  auto r = make_result("math.grain-cell-keys", "math", scan, &err, 1e-6, key_mismatch == 0 && xi_mismatch == 0,
                       "grain_cell_key and pcg3d for |x| up to 3e38 and inf, noise_scale up to 1e6: keys and "
                       "uniform xi exact (" + std::to_string(key_mismatch) + " key, " + std::to_string(xi_mismatch) +
                           " xi mismatches), normalised xi within 1e-6 (floor 1)");
  return r;
}

// ---- porosity exp(-P / d) (sand/porosity.glsl)
StressCaseResult porosity_case(Env& env) {
  std::vector<Record> recs;
  std::mt19937_64 rng(59);
  const double Ps[] = {0.0, 1e-6, 0.1, 1.0};
  const double ds[] = {0.0, 1e-45, 1e-38, 1e-30, 1e-6, 1e-2, 1.0, 1e6, 3e38, kInf};
  for (double P : Ps)
    for (double d : ds) recs.push_back({5, f32(P), f32(d)});
  for (size_t i = 0; i < count(env.fast, 4096); ++i)
    recs.push_back({5, f32(std::uniform_real_distribution<double>()(rng)), f32(log_uniform(rng, 1e-3, 1e6))});
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  size_t out_of_range = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    scan.add(o[0]);
    scan.add(o[1]);
    out_of_range += !(o[0] <= 1 && o[1] >= 0.5 && o[1] <= 1);
    double P = recs[i][1], d = recs[i][2];
    // fp32 quotient P / d (rounded once), the GLSL's guard max(d, 1e-30)
    double q = d > 0 ? double(f32(P / std::max(d, 1e-30))) : (P > 0 ? kInf : 0.0);
    double want = std::exp(-q);
    err.add(o[0], want, 1e-30, "P " + fmt(P) + " d " + fmt(d));
    err.add(o[1], ref::rho_n_intensity(want), 1e-30, "rho_n^intensity P " + fmt(P) + " d " + fmt(d));
  }
  return make_result("math.porosity-extremes", "math", scan, &err, 2e-5, out_of_range == 0,
                     "I_min = exp(-P/d) for P in {0, 1e-6, 0.1, 1} and d from 0 (and denormal) to inf; vs exp of "
                     "the fp32 quotient in double, floor 1e-30 (fp32 exp: 1.2e-7 |P/d| relative); I_min in [0, 1], rho_n^intensity in [1/2, 1]; worst: " +
                         err.worst);
}

// ---- transmission t (sand/transmission.glsl), T = 1, R_t in {0, 1}
StressCaseResult transmission_case(Env& env) {
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  const double deg = kPi / 180;
  for (size_t i = 0; i < count(env.fast, 8192); ++i) {
    vec3 n = random_unit(rng);
    double th = U(rng) < 0.3 ? 90 * deg - log_uniform(rng, 1e-7, 0.1) : (U(rng) < 0.2 ? 0.0 : U(rng) * 90 * deg);
    vec3 wo = at_angle(rng, n, th);
    vec3 wi = U(rng) < 0.4 ? -wo : at_angle(rng, -wo, U(rng) < 0.5 ? 0.0 : log_uniform(rng, 1e-7, 1.5));
    Record r{6};
    r[1] = U(rng) < 0.6 ? 1.0f : f32(U(rng));
    r[2] = U(rng) < 0.4 ? 0.0f : (U(rng) < 0.6 ? 1.0f : f32(U(rng)));
    put3(r, 3, n);
    put3(r, 6, wo);
    put3(r, 9, wi);
    recs.push_back(r);
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    scan.add(o[0]);
    double t = ref::transmission_t(recs[i][1], recs[i][2], get3(recs[i], 3), get3(recs[i], 6), get3(recs[i], 9));
    err.add(o[0], t, 1e-4, "T " + fmt(recs[i][1]) + " R_t " + fmt(recs[i][2]));
  }
  return make_result("math.transmission-T1-Rt01", "math", scan, &err, 1e-3, true,
                     "t of eq. 4.31 with T = 1 (60 %), R_t in {0, 1}, w_i = -w_o and grazing views; vs fp64, floor "
                     "1e-4 (pow(1 - cos, 5) near cos = 1 carries the fp32 dot's 6e-8 absolute); worst: " + err.worst);
}

// ---- the Gaussian gate of eq. 4.17 (sand/glints.glsl), sigma 1e-6 .. 1
StressCaseResult gdf_case(Env& env) {
  std::mt19937_64 rng(67);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  for (size_t i = 0; i < count(env.fast, 8192); ++i) {
    double sigma = U(rng) < 0.3 ? (U(rng) < 0.5 ? 1e-6 : 1.0) : log_uniform(rng, 1e-6, 1.0);
    // the gate reads xi_pm = 2 xi - 1, multiples of 2^-23; near 0 where the gate is open
    double x = std::ldexp(double(int64_t(rng() % (1u << 24)) - (1 << 23)), -23);
    if (U(rng) < 0.5) x = std::ldexp(std::round(sigma * 13 * (U(rng) - 0.5) * std::ldexp(1.0, 23)), -23);
    recs.push_back({7, f32(x), f32(sigma)});
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    scan.add(o[0]);
    double x = recs[i][1], s = recs[i][2];
    err.add(o[0], ref::GDF(x, s), 1e-30, "x " + fmt(x) + " sigma " + fmt(s));
  }
  return make_result("math.glint-gate-sigma-1e-6-to-1", "math", scan, &err, 2e-5, true,
                     "GDF(x, sigma), sigma 1e-6 .. 1, x on the 2^-23 grid of the grain numbers; vs fp64 exp, floor "
                     "1e-30 (the fp32 exponent r^2/2 carries 1.2e-7 r^2 relative, <= 1.1e-5 where the gate > 1e-38); "
                     "worst: " + err.worst);
}

// ---- safe_log1p and safe_pow (common/math.glsl)
StressCaseResult log_pow_case(Env& env) {
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  const double special[] = {-1.0, -1.0 + 6e-8, -0.5, -1e-12, 0.0, 1e-30, 1e-12, 0.5, 1.0, 1e30, 3e38, kInf};
  for (double x : special) recs.push_back({8, f32(x), 2.5f});
  for (size_t i = 0; i < count(env.fast, 4096); ++i) {
    double x = U(rng) < 0.5 ? (U(rng) - 0.5) * std::ldexp(1.0, -int(rng() % 60)) : log_uniform(rng, 1e-30, 3e38);
    double y = log_uniform(rng, 0.2, 5.0);
    recs.push_back({8, f32(x), f32(y)});
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    double x = recs[i][1], y = recs[i][2];
    double p = x > 0 ? std::pow(x, y) : 0.0;
    scan.add(o[0], false);
    if (p < 3.4e38) scan.add(o[1]);  // beyond, fp32 overflows as it must
    double l = reference::glint::safe_log1p(x);
    if (x > -1 + 1e-6) err.add(o[0], l, 1e-30, "log1p(" + fmt(x) + ")");
    if (p < 3e38 && p > 1e-37) err.add(o[1], p, 1e-30, "pow(" + fmt(x) + ", " + fmt(y) + ")");
  }
  return make_result("math.log1p-pow", "math", scan, &err, 2e-5, true,
                     "safe_log1p from -1 to inf, safe_pow(x, 0.2 .. 5) for x up to 3e38; vs fp64 where the result "
                     "is a normal fp32 number (pow's exp2(y log2 x) carries 1.2e-7 |y log2 x| relative); worst: " +
                         err.worst);
}

// ---- Kajs micro normals (sand/micro_normals.glsl) for axis-aligned and random views
StressCaseResult micro_normal_case(Env& env) {
  std::mt19937_64 rng(73);
  std::uniform_real_distribution<double> U;
  std::vector<Record> recs;
  for (size_t i = 0; i < count(env.fast, 8192); ++i) {
    double xi1 = std::ldexp(double(rng() >> 40), -24), xi2 = std::ldexp(double(rng() >> 40), -24);
    if (U(rng) < 0.1) xi2 = U(rng) < 0.5 ? 0.0 : 1.0 - std::ldexp(1.0, -24);  // q = +-z: the basis' poles
    vec3 wo = random_unit(rng);
    if (U(rng) < 0.2) wo = vec3(0, 0, U(rng) < 0.5 ? 1 : -1);
    Record r{9, f32(xi1), f32(xi2)};
    put3(r, 3, wo);
    recs.push_back(r);
  }
  auto out = run_math(env, recs);
  ValueScan scan;
  ErrorStat err;
  size_t face_mismatch = 0, skipped = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const float* o = &out[i * kOut];
    for (int k = 0; k < 3; ++k) scan.add(o[k], false);
    int face;
    double margin;
    vec3 m = ref::micro_normal(recs[i][1], recs[i][2], get3(recs[i], 3), face, margin);
    if (margin <= 1e-4) {
      ++skipped;
      continue;
    }
    face_mismatch += o[3] != face;
    for (int k = 0; k < 3; ++k) err.add(o[k], m[k], 1.0, "xi (" + fmt(recs[i][1]) + ", " + fmt(recs[i][2]) + ")");
  }
  return make_result("math.micro-normals", "math", scan, &err, 2e-5, face_mismatch == 0,
                     "cube micro normals for xi on the 2^-24 grid incl. the sphere's poles, w_o = +-z; face exact where "
                     "the fp64 margin > 1e-4 (" + std::to_string(skipped) + " skipped, " +
                         std::to_string(face_mismatch) + " mismatches), m within 2e-5 (cos/sin of 2 pi xi in fp32)");
}

}  // namespace

void add_math_cases(std::vector<Case>& cases) {
  cases.push_back({"math.sigmoid-stable", "math", true, sigmoid_case});
  cases.push_back({"math.frisvad-basis-pm-z", "math", true, frisvad_case});
  cases.push_back({"math.safe-normalize", "math", true, normalize_case});
  cases.push_back({"math.oren-nayar-0-90deg", "math", true, oren_nayar_case});
  cases.push_back({"math.grain-cell-keys", "math", true, grain_key_case});
  cases.push_back({"math.porosity-extremes", "math", true, porosity_case});
  cases.push_back({"math.transmission-T1-Rt01", "math", false, transmission_case});
  cases.push_back({"math.glint-gate-sigma-1e-6-to-1", "math", false, gdf_case});
  cases.push_back({"math.log1p-pow", "math", false, log_pow_case});
  cases.push_back({"math.micro-normals", "math", false, micro_normal_case});
}

}  // namespace glintlab::stress

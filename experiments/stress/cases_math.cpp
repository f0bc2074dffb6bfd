// Stress cases of the shared shader helpers and the sand's scalar terms:
// shaders/tests/stress_math.comp against the fp64 twins (core/testkit)
// and core::sand_sigmoid (the stable sigmoid in double) on extreme arguments.
// err = |gpu - fp64| / max(|fp64|, floor) with the floor each case states.
//
// A case is a row (MathRow): its fixed and seeded random records, the check
// of one record's outputs against the fp64 twin, the counters that must stay
// 0 and the bound; run_math_case makes the records, runs the shader once and
// checks them all.
#include "core/material/sand_material.h"
#include "core/testkit/glint_fp64.h"
#include "core/testkit/sand_fp64.h"
#include "core/vk/compute_harness.h"
#include "experiments/stress/stress_internal.h"

#include <glm/geometric.hpp>

#include <array>
#include <map>
#include <stdexcept>

namespace glintlab::stress {

namespace {

namespace ref = glintlab::reference::sand;
using ref::vec3;

constexpr size_t kIn = 16, kOut = 16;  // strides of shaders/tests/stress_math.comp
constexpr double kDeg = kPi / 180;

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
std::string str3(const vec3& v) { return "(" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + ")"; }

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

// The random draws of one case's inputs.
struct Draw {
  std::mt19937_64& rng;
  std::normal_distribution<double> normal{};  // one per case: its cached second value carries over between records
  double U() { return std::uniform_real_distribution<double>()(rng); }
  double N() { return normal(rng); }
};

// What the checks of one case accumulate over its records.
struct Tally {
  ValueScan scan;  // outputs that must be finite (and >= 0)
  ErrorStat err;   // the comparisons with the fp64 twin
  std::map<std::string, size_t> counts;  // named counters (mismatches, values out of range, ...)
  std::map<std::string, double> maxima;  // named largest values (extra keys)
  // Only the names the row declares exist (run_math_case fills them in first).
  size_t& count(const std::string& name) { return known(counts, name); }
  double& maximum(const std::string& key) { return known(maxima, key); }

 private:
  template <class T>
  static T& known(std::map<std::string, T>& m, const std::string& name) {
    auto it = m.find(name);
    if (it == m.end()) throw std::logic_error("stress: undeclared math counter '" + name + "'");
    return it->second;
  }
};

// A largest value a case reports in `extra` under `key`; the case fails above `bound`.
struct Maximum {
  std::string key;
  double bound = kInf;
};

// A case: `fixed` records, then count(fast, drawn) records from `draw` on the generator seeded `seed`;
// `check` compares each record's outputs with the fp64 twin.
struct MathRow {
  std::string name;
  bool fast;      // part of the --fast subset
  uint64_t seed;  // of the mt19937_64 the records are drawn from
  double bound;   // on max_rel_error
  std::string what;                     // what is stressed, against what, the floor and why (detail)
  std::vector<std::string> invariants;  // counters that must end at 0 for the case to pass
  std::vector<Maximum> maxima;          // largest values (extra), each within its bound
  std::vector<Record> fixed;            // the special records, first
  size_t drawn;                         // then count(fast, drawn) records from `draw`
  std::function<Record(Draw& d)> draw;
  // One record and its kOut outputs: scan them, compare them with the fp64 twin, count.
  std::function<void(const Record& rec, const float* o, Tally& t)> check;
  std::vector<std::string> counted;  // counters only reported
};

StressCaseResult run_math_case(Env& env, const MathRow& row) {
  std::mt19937_64 rng(row.seed);
  Draw d{rng};
  std::vector<Record> recs = row.fixed;
  for (size_t i = 0; i < count(env.fast, row.drawn); ++i) recs.push_back(row.draw(d));
  const std::vector<float> out = run_math(env, recs);
  Tally t;
  for (const auto& n : row.invariants) t.counts[n] = 0;
  for (const auto& n : row.counted) t.counts[n] = 0;
  for (const auto& m : row.maxima) t.maxima[m.key] = 0;
  for (size_t i = 0; i < recs.size(); ++i) row.check(recs[i], &out[i * kOut], t);
  bool ok = true;
  std::string detail = row.what;
  for (const auto& n : row.invariants) ok = ok && t.counts[n] == 0;
  for (const auto& [n, c] : t.counts) detail += "; " + n + ": " + std::to_string(c);
  for (const auto& m : row.maxima) {
    ok = ok && t.maxima[m.key] <= m.bound;
    detail += "; " + m.key + " " + fmt(t.maxima[m.key]);
  }
  if (t.err.compared) detail += "; worst: " + t.err.worst;
  StressCaseResult r = make_result(row.name, "math", t.scan, &t.err, row.bound, ok, detail);
  for (const auto& m : row.maxima) r.extra[m.key] = t.maxima[m.key];
  return r;
}

// Records of operation `op` with the vector v at 1 .. 3 (the fp64 reference reads the same fp32 components).
Record vec_record(float op, const vec3& v) {
  Record r{op};
  put3(r, 1, v);
  return r;
}
std::vector<Record> vec_records(float op, const std::vector<vec3>& vs) {
  std::vector<Record> recs;
  for (const vec3& v : vs) recs.push_back(vec_record(op, v));
  return recs;
}

std::vector<Record> sigmoid_grid() {
  std::vector<Record> recs;
  const double xs[] = {-3e38, -1e6, -1.0, 0.0, 1.3, 1e3, 1e6, 3e38};
  const double as[] = {1e-6, 1e-2, 2.0, 1e2, 1e3, 1e4};
  const double bs[] = {0.0, 1.3, 1e3, 1e6, 1e7};
  for (double x : xs)
    for (double a : as)
      for (double b : bs) recs.push_back({0, f32(x), f32(a), f32(b), f32(a * (x - b))});
  return recs;
}

std::vector<Record> porosity_grid() {
  std::vector<Record> recs;
  const double Ps[] = {0.0, 1e-6, 0.1, 1.0};
  const double ds[] = {0.0, 1e-45, 1e-38, 1e-30, 1e-6, 1e-2, 1.0, 1e6, 3e38, kInf};
  for (double P : Ps)
    for (double d : ds) recs.push_back({5, f32(P), f32(d)});
  return recs;
}

std::vector<Record> log_pow_specials() {
  std::vector<Record> recs;
  const double special[] = {-1.0, -1.0 + 6e-8, -0.5, -1e-12, 0.0, 1e-30, 1e-12, 0.5, 1.0, 1e30, 3e38, kInf};
  for (double x : special) recs.push_back({8, f32(x), 2.5f});
  return recs;
}

// In the fast subset: the sand's sigmoid and the vector helpers of shaders/common/.
std::vector<MathRow> fast_helper_rows() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<MathRow> rows;
  // ---- sigmoid of eq. 4.37 (shaders/sand/transition.glsl) and stable_logistic
  rows.push_back(
      {"math.sigmoid-stable", true, 37, 2e-5,
       "sig(x, a, b) for x to +-3e38, a to 1e4, b to 1e7, and near the midpoint; fp64 stable logistic of the "
       "fp32-rounded exponent, floor 1e-30 (exp in fp32 carries 1.2e-7 |z| relative, <= 1.1e-5 where the value is a "
       "normal fp32 number); both in [0, 1]",
       {"out of [0, 1]"}, {}, sigmoid_grid(), 8192,
       [](Draw& d) -> Record {
         // near the midpoint, where the exponent is moderate: b in [0, 1e6], x = b (1 + small)
         double a = log_uniform(d.rng, 1e-3, 1e4), b = d.U() < 0.2 ? 1e6 : log_uniform(d.rng, 1e-3, 1e6);
         double x = b + (d.U() - 0.5) * 200.0 / a;
         if (d.U() < 0.3) x = log_uniform(d.rng, 1e-3, 1e6);
         return {0, f32(x), f32(a), f32(b), f32(std::ldexp(d.U() - 0.5, int(d.rng() % 256) - 128))};
       },
       [](const Record& rec, const float* o, Tally& t) {
         t.scan.add(o[0]);
         t.scan.add(o[1]);
         t.count("out of [0, 1]") += !(o[0] <= 1 && o[1] <= 1);
         // fp64 of the same fp32 arguments, with the GLSL's fp32 roundings of x - b and a (x - b): the
         // sigmoid's own error is measured, not the conditioning of exp at |z| up to 88
         float d = f32(double(rec[1]) - double(rec[3]));
         float z = f32(double(rec[2]) * double(d));
         double want = core::sand_sigmoid(double(z), 1.0, 0.0);
         t.err.add(o[0], want, 1e-30, "sig(" + fmt(rec[1]) + ", " + fmt(rec[2]) + ", " + fmt(rec[3]) + ")");
         t.err.add(o[1], core::sand_sigmoid(double(rec[4]), 1.0, 0.0), 1e-30, "logistic(" + fmt(rec[4]) + ")");
       }});
  // ---- Frisvad / Duff et al. basis (common/frisvad.glsl) at n = +-z
  rows.push_back(
      {"math.frisvad-basis-pm-z", true, 41, 1e-6,
       "n = +z, -z and within 1e-12 .. 1e-2 of them; basis components vs fp64 (floor 1: absolute), orthonormality "
       "and handedness within 1e-6",
       {}, {{"orthonormality_error", 1e-6}}, vec_records(1, {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}}), 8192,
       [](Draw& d) {
         double e = log_uniform(d.rng, 1e-12, 1e-2), s = d.U() < 0.5 ? -1.0 : 1.0;
         double phi = 2 * kPi * d.U();
         vec3 n = d.U() < 0.8 ? glm::normalize(vec3(e * std::cos(phi), e * std::sin(phi), s)) : random_unit(d.rng);
         return vec_record(1, n);
       },
       [](const Record& rec, const float* o, Tally& t) {
         for (int k = 0; k < 6; ++k) t.scan.add(o[k], false);
         vec3 n = get3(rec, 1);
         vec3 b1, b2;
         ref::frisvad_basis(n, b1, b2);
         vec3 g1 = out3(o), g2 = out3(o + 3);
         for (int k = 0; k < 3; ++k) {
           t.err.add(g1[k], b1[k], 1.0, "n = " + str3(n) + " b1");
           t.err.add(g2[k], b2[k], 1.0, "n = " + str3(n) + " b2");
         }
         vec3 nu = glm::normalize(n);
         double& ortho = t.maximum("orthonormality_error");
         ortho = std::max({ortho, std::fabs(glm::dot(g1, g2)), std::fabs(glm::dot(g1, nu)),
                           std::fabs(glm::dot(g2, nu)), std::fabs(glm::length(g1) - 1), std::fabs(glm::length(g2) - 1),
                           glm::length(glm::cross(g1, g2) - nu)});
       }});
  // ---- safe_normalize (common/math.glsl) of tiny, huge and non-finite vectors
  rows.push_back(
      {"math.safe-normalize", true, 43, 1e-6,
       "vectors 2^-100 .. 3e38, zero, denormal, infinite, NaN (-> the fallback z); components vs fp64 (floor 1), "
       "|result| = 1 within 1e-6",
       {"not unit length"}, {},
       vec_records(2, {{0, 0, 0}, {1e-45, 0, 0}, {1e-38, -1e-38, 0}, {3e38, 3e38, 3e38}, {-3e38, 1, 0}, {kInf, 0, 0},
                       {nan, 1, 0}, {1e-30, 1e-30, 1e-30}, {2e-30, 0, 0}}),
       8192,
       [](Draw& d) {
         double s = std::ldexp(1.0, int(d.rng() % 250) - 100);  // 2^-100 .. 2^149 (fp32 overflows at 2^128)
         vec3 v = random_unit(d.rng) * s;
         if (d.U() < 0.2) v.y *= 1e-30;
         return vec_record(2, v);
       },
       [](const Record& rec, const float* o, Tally& t) {
         for (int k = 0; k < 3; ++k) t.scan.add(o[k], false);
         vec3 v = get3(rec, 1), g = out3(o);
         t.count("not unit length") += !(std::fabs(glm::length(g) - 1) <= 1e-6);
         double m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
         bool fallback = !(m > double(f32(1e-30))) || !std::isfinite(m);
         vec3 want = fallback ? vec3(0, 0, 1) : v / glm::length(v / m) / m;
         for (int k = 0; k < 3; ++k) t.err.add(g[k], want[k], 1.0, "v = " + str3(v));
       }});
  return rows;
}

// In the fast subset: Oren-Nayar, the grain cells' keys and the porosity of shaders/sand/.
std::vector<MathRow> fast_sand_rows() {
  std::vector<MathRow> rows;
  // ---- Oren-Nayar (sand/oren_nayar.glsl) near 0 and 90 degrees
  rows.push_back(
      {"math.oren-nayar-0-90deg", true, 47, 1e-3,
       "theta_i, theta_o at 0, 1e-7 .. 1e-2 rad from 0 and from 90 deg, 90 deg, just below the horizon, sigma 0 .. "
       "pi/2, chapter 4 and world frames; L_oren max(0, n.w_i) (the product L_brdf uses, A + B <= 1.5) vs fp64, "
       "floor 1 (the product's scale: rho/pi L_i times it is the radiance); L_oren alone peaks at L_oren_max (tan "
       "beta, finite)",
       {}, {{"L_oren_max"}}, {}, 16384,
       [](Draw& d) {
         vec3 n = d.U() < 0.3 ? vec3(0, 0, d.U() < 0.5 ? 1 : -1) : random_unit(d.rng);
         auto angle = [&] {
           double u = d.U();
           if (u < 0.25) return 0.0;
           if (u < 0.5) return log_uniform(d.rng, 1e-7, 1e-2);
           if (u < 0.75) return 90 * kDeg - log_uniform(d.rng, 1e-7, 1e-2);
           return u < 0.85 ? 90 * kDeg : d.U() * 90 * kDeg;
         };
         vec3 wi = at_angle(d.rng, n, angle()), wo = at_angle(d.rng, n, angle());
         if (d.U() < 0.1) wo = wi;
         if (d.U() < 0.1) wo = at_angle(d.rng, n, 90 * kDeg + log_uniform(d.rng, 1e-7, 0.1));  // just below the horizon
         double sigma = d.U() < 0.3 ? kPi / 2 : (d.U() < 0.2 ? 0.0 : d.U() * kPi / 2);
         Record r = vec_record(3, n);
         put3(r, 4, wi);
         put3(r, 7, wo);
         r[10] = f32(sigma);
         r[11] = d.U() < 0.2 ? 32.0f : 0.0f;
         return r;
       },
       [](const Record& rec, const float* o, Tally& t) {
         t.scan.add(o[0]);
         t.scan.add(o[1]);
         double& raw_max = t.maximum("L_oren_max");
         raw_max = std::max(raw_max, double(o[0]));
         vec3 n = get3(rec, 1), wi = get3(rec, 4), wo = get3(rec, 7);
         double L = ref::L_oren(n, wi, wo, rec[10], uint32_t(rec[11]));
         double cos_ni = std::max(0.0, glm::dot(n, wi));
         t.err.add(o[1], L * cos_ni, 1.0,
                   "theta_i " + fmt(std::acos(std::min(1.0, glm::dot(n, wi))) / kDeg) + " theta_o " +
                       fmt(std::acos(std::max(-1.0, std::min(1.0, glm::dot(n, wo)))) / kDeg));
       }});
  // ---- grain cells: wrapped keys and pcg3d at huge coordinates (exact)
  rows.push_back(
      {"math.grain-cell-keys", true, 53, 1e-6,
       "grain_cell_key and pcg3d for |x| up to 3e38 and inf, noise_scale up to 1e6: keys and uniform xi exact, "
       "normalised xi within 1e-6 (floor 1)",
       {"key mismatches", "xi mismatches"}, {}, {}, 16384,
       [](Draw& d) {
         double scale = d.U() < 0.3 ? 1e6 : log_uniform(d.rng, 1, 1e6);
         double mag = d.U() < 0.1 ? log_uniform(d.rng, 1e6, 3e38) : log_uniform(d.rng, 1e-6, 1e6);
         vec3 x = vec3(d.N(), d.N(), d.N()) * mag;
         if (d.U() < 0.05) x.x = d.U() < 0.5 ? kInf : -0.0;
         Record r = vec_record(4, x);
         r[4] = f32(scale);
         r[5] = d.U() < 0.3 ? 1.0f : 0.0f;
         return r;
       },
       [](const Record& rec, const float* o, Tally& t) {
         for (int k = 6; k < 9; ++k) t.scan.add(o[k]);
         std::array<float, 3> x{rec[1], rec[2], rec[3]};
         auto key = ref::grain_cell_key(x, rec[4]);
         auto gr = ref::grain_random(key, uint32_t(rec[5]));
         for (int k = 0; k < 3; ++k) {
           uint32_t g = (uint32_t(o[2 * k]) << 16) | uint32_t(o[2 * k + 1]);
           t.count("key mismatches") += g != key[k];
           if (rec[5] == 0) t.count("xi mismatches") += o[6 + k] != gr.xi[k];
           else t.err.add(o[6 + k], gr.xi[k], 1.0, "normalised xi");
         }
       }});
  // ---- porosity exp(-P / d) (sand/porosity.glsl)
  rows.push_back(
      {"math.porosity-extremes", true, 59, 2e-5,
       "I_min = exp(-P/d) for P in {0, 1e-6, 0.1, 1} and d from 0 (and denormal) to inf; vs exp of the fp32 quotient "
       "in double, floor 1e-30 (fp32 exp: 1.2e-7 |P/d| relative); I_min in [0, 1], rho_n^intensity in [1/2, 1]",
       {"out of range"}, {}, porosity_grid(), 4096,
       [](Draw& d) -> Record { return {5, f32(d.U()), f32(log_uniform(d.rng, 1e-3, 1e6))}; },
       [](const Record& rec, const float* o, Tally& t) {
         t.scan.add(o[0]);
         t.scan.add(o[1]);
         t.count("out of range") += !(o[0] <= 1 && o[1] >= 0.5 && o[1] <= 1);
         double P = rec[1], d = rec[2];
         // fp32 quotient P / d (rounded once), the GLSL's guard max(d, 1e-30)
         double q = d > 0 ? double(f32(P / std::max(d, 1e-30))) : (P > 0 ? kInf : 0.0);
         double want = std::exp(-q);
         t.err.add(o[0], want, 1e-30, "P " + fmt(P) + " d " + fmt(d));
         t.err.add(o[1], ref::rho_n_intensity(want), 1e-30, "rho_n^intensity P " + fmt(P) + " d " + fmt(d));
       }});
  return rows;
}

// Only in the full run: transmission, the glint gate, safe_log1p and safe_pow, micro normals.
std::vector<MathRow> full_run_rows() {
  std::vector<MathRow> rows;
  // ---- transmission t (sand/transmission.glsl), T = 1, R_t in {0, 1}
  rows.push_back(
      {"math.transmission-T1-Rt01", false, 61, 1e-3,
       "t of eq. 4.31 with T = 1 (60 %), R_t in {0, 1}, w_i = -w_o and grazing views; vs fp64, floor 1e-4 (pow(1 - "
       "cos, 5) near cos = 1 carries the fp32 dot's 6e-8 absolute)",
       {}, {}, {}, 8192,
       [](Draw& d) {
         vec3 n = random_unit(d.rng);
         double th = d.U() < 0.3 ? 90 * kDeg - log_uniform(d.rng, 1e-7, 0.1) : (d.U() < 0.2 ? 0.0 : d.U() * 90 * kDeg);
         vec3 wo = at_angle(d.rng, n, th);
         vec3 wi = d.U() < 0.4 ? -wo : at_angle(d.rng, -wo, d.U() < 0.5 ? 0.0 : log_uniform(d.rng, 1e-7, 1.5));
         Record r{6};
         r[1] = d.U() < 0.6 ? 1.0f : f32(d.U());
         r[2] = d.U() < 0.4 ? 0.0f : (d.U() < 0.6 ? 1.0f : f32(d.U()));
         put3(r, 3, n);
         put3(r, 6, wo);
         put3(r, 9, wi);
         return r;
       },
       [](const Record& rec, const float* o, Tally& t) {
         t.scan.add(o[0]);
         double tr = ref::transmission_t(rec[1], rec[2], get3(rec, 3), get3(rec, 6), get3(rec, 9));
         t.err.add(o[0], tr, 1e-4, "T " + fmt(rec[1]) + " R_t " + fmt(rec[2]));
       }});
  // ---- the Gaussian gate of eq. 4.17 (sand/glints.glsl), sigma 1e-6 .. 1
  rows.push_back(
      {"math.glint-gate-sigma-1e-6-to-1", false, 67, 2e-5,
       "GDF(x, sigma), sigma 1e-6 .. 1, x on the 2^-23 grid of the grain numbers; vs fp64 exp, floor 1e-30 (the fp32 "
       "exponent r^2/2 carries 1.2e-7 r^2 relative, <= 1.1e-5 where the gate > 1e-38)",
       {}, {}, {}, 8192,
       [](Draw& d) -> Record {
         double sigma = d.U() < 0.3 ? (d.U() < 0.5 ? 1e-6 : 1.0) : log_uniform(d.rng, 1e-6, 1.0);
         // the gate reads xi_pm = 2 xi - 1, multiples of 2^-23; near 0 where the gate is open
         double x = std::ldexp(double(int64_t(d.rng() % (1u << 24)) - (1 << 23)), -23);
         if (d.U() < 0.5) x = std::ldexp(std::round(sigma * 13 * (d.U() - 0.5) * std::ldexp(1.0, 23)), -23);
         return {7, f32(x), f32(sigma)};
       },
       [](const Record& rec, const float* o, Tally& t) {
         t.scan.add(o[0]);
         double x = rec[1], s = rec[2];
         t.err.add(o[0], ref::GDF(x, s), 1e-30, "x " + fmt(x) + " sigma " + fmt(s));
       }});
  // ---- safe_log1p and safe_pow (common/math.glsl)
  rows.push_back(
      {"math.log1p-pow", false, 71, 2e-5,
       "safe_log1p from -1 to inf, safe_pow(x, 0.2 .. 5) for x up to 3e38; vs fp64 where the result is a normal fp32 "
       "number (pow's exp2(y log2 x) carries 1.2e-7 |y log2 x| relative)",
       {}, {}, log_pow_specials(), 4096,
       [](Draw& d) -> Record {
         double x =
             d.U() < 0.5 ? (d.U() - 0.5) * std::ldexp(1.0, -int(d.rng() % 60)) : log_uniform(d.rng, 1e-30, 3e38);
         double y = log_uniform(d.rng, 0.2, 5.0);
         return {8, f32(x), f32(y)};
       },
       [](const Record& rec, const float* o, Tally& t) {
         double x = rec[1], y = rec[2];
         double p = x > 0 ? std::pow(x, y) : 0.0;
         t.scan.add(o[0], false);
         if (p < 3.4e38) t.scan.add(o[1]);  // beyond, fp32 overflows as it must
         double l = reference::glint::safe_log1p(x);
         if (x > -1 + 1e-6) t.err.add(o[0], l, 1e-30, "log1p(" + fmt(x) + ")");
         if (p < 3e38 && p > 1e-37) t.err.add(o[1], p, 1e-30, "pow(" + fmt(x) + ", " + fmt(y) + ")");
       }});
  // ---- Kajs micro normals (sand/micro_normals.glsl) for axis-aligned and random views
  rows.push_back(
      {"math.micro-normals", false, 73, 2e-5,
       "cube micro normals for xi on the 2^-24 grid incl. the sphere's poles, w_o = +-z; face exact where the fp64 "
       "margin > 1e-4, m within 2e-5 (cos/sin of 2 pi xi in fp32)",
       {"face mismatches"}, {}, {}, 8192,
       [](Draw& d) {
         double xi1 = std::ldexp(double(d.rng() >> 40), -24), xi2 = std::ldexp(double(d.rng() >> 40), -24);
         if (d.U() < 0.1) xi2 = d.U() < 0.5 ? 0.0 : 1.0 - std::ldexp(1.0, -24);  // q = +-z: the basis' poles
         vec3 wo = random_unit(d.rng);
         if (d.U() < 0.2) wo = vec3(0, 0, d.U() < 0.5 ? 1 : -1);
         Record r{9, f32(xi1), f32(xi2)};
         put3(r, 3, wo);
         return r;
       },
       [](const Record& rec, const float* o, Tally& t) {
         for (int k = 0; k < 3; ++k) t.scan.add(o[k], false);
         int face;
         double margin;
         vec3 m = ref::micro_normal(rec[1], rec[2], get3(rec, 3), face, margin);
         if (margin <= 1e-4) {
           ++t.count("skipped (margin <= 1e-4)");
           return;
         }
         t.count("face mismatches") += o[3] != face;
         for (int k = 0; k < 3; ++k) t.err.add(o[k], m[k], 1.0, "xi (" + fmt(rec[1]) + ", " + fmt(rec[2]) + ")");
       },
       {"skipped (margin <= 1e-4)"}});
  return rows;
}

// Every math case, in the order run_stress runs them.
std::vector<MathRow> math_rows() {
  std::vector<MathRow> rows;
  for (auto* group : {fast_helper_rows, fast_sand_rows, full_run_rows})
    for (MathRow& row : group()) rows.push_back(std::move(row));
  return rows;
}

}  // namespace

void add_math_cases(std::vector<Case>& cases) {
  for (auto& row : math_rows())
    cases.push_back({row.name, "math", row.fast, [row](Env& env) { return run_math_case(env, row); }});
}

}  // namespace glintlab::stress

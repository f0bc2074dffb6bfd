#include "core/testkit/glint_fp64.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace glintlab::reference::glint {

namespace {
const double kPi = 3.14159265358979323846;
double sq(double x) { return x * x; }
double clamp_uv(double x) { return std::isnan(x) ? 0.0 : std::min(1e20, std::max(-1e20, x)); }
vec2 clamp2(vec2 v) { return vec2(clamp_uv(v.x), clamp_uv(v.y)); }
// Uniforms from pcg3d as the GLSL forms them
vec3 unit01(const sand::uvec3& h) {
  return vec3(std::ldexp(double(h[0] >> 8), -24), std::ldexp(double(h[1] >> 8), -24), std::ldexp(double(h[2] >> 8), -24));
}
vec3 open01(const sand::uvec3& h) {
  return vec3(std::ldexp(double(h[0] >> 8) + 0.5, -24), std::ldexp(double(h[1] >> 8) + 0.5, -24),
              std::ldexp(double(h[2] >> 8) + 0.5, -24));
}
constexpr uint32_t kGrainsSalt = 0x6A09E667u, kOffsetSalt = 0x3C6EF372u, kHalfSalt = 0xA54FF53Au;
}  // namespace

const char* twin_name(uint32_t twin) {
  return twin == kGlintGrains ? "grains" : twin == kGlintZirr ? "zirr" : twin == kGlintBeckmann ? "beckmann" : "";
}

uint32_t twin_of_gpu(uint32_t gpu_id) {
  for (uint32_t t : {kGlintGrains, kGlintZirr, kGlintBeckmann})
    if (core::find_builtin_glint_model(twin_name(t)) && core::glint_model_gpu_id(twin_name(t)) == gpu_id) return t;
  return 0u;
}

uint32_t gpu_of_twin(uint32_t twin) { return core::glint_model_gpu_id(twin_name(twin)); }

Params from_gpu(const core::SandParamsGPU& g) {
  Params p;
  const auto& models = core::builtin_glint_models();
  const core::GlintModelDecl* d = g.glint_model >= 2 && g.glint_model - 2 < models.size() ? &models[g.glint_model - 2] : nullptr;
  auto param = [&](const char* name) {
    if (d)
      for (size_t i = 0; i < d->parameters.size(); ++i)
        if (d->parameters[i].name == name) return double(g.glint_parameters[i]);
    return 0.0;
  };
  p.alpha_g = vec2(g.glint_alpha[0], g.glint_alpha[1]);
  p.relative = vec2(g.glint_alpha[2], g.glint_alpha[3]);
  p.log_density = g.glint_log_density;
  p.size_variation = param("size_variation");
  p.intensity = g.glint_intensity;
  p.light_cone = g.glint_light_cone;
  p.color_saturation = param("color_saturation");
  p.ior = g.ior;
  p.half_vector_blend = param("half_vector_blend") > 0.5;
  return p;
}

void Slack::floor_arg(double x) {
  double d = std::fabs(x - std::round(x));
  min = std::min(min, d - (4e-6 * std::fabs(x) + 1e-5));
}

void Slack::compare(double a, double b, double allowance) { min = std::min(min, std::fabs(a - b) - allowance); }

double safe_log1p(double x) {
  if (!(x > -1.0)) return -3.4e38;
  return std::log1p(std::min(x, 3.4e38));
}

uint32_t wrapped_floor(double x) {
  if (std::isnan(x)) return 0x7FC00000u;
  if (std::isinf(x)) return x > 0 ? 0x7F800000u : 0xFF800000u;
  double r = std::fmod(std::floor(x), 4294967296.0);  // exact
  if (r < 0) r += 4294967296.0;
  return static_cast<uint32_t>(r);
}

double normal_quantile(double u) {  // independent of the GLSL's fit: Halley on the exact CDF
  const double lo = std::ldexp(1.0, -25);
  u = std::min(std::max(u, lo), 1.0 - lo);
  // start anywhere sensible, then Halley steps on the exact CDF 0.5 erfc(-x / sqrt 2)
  double t = std::sqrt(-2.0 * std::log(std::min(u, 1.0 - u)));
  double x = t - (2.515517 + 0.802853 * t + 0.010328 * t * t) / (1 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t);
  if (u < 0.5) x = -x;
  for (int i = 0; i < 4; ++i) {
    double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - u;
    double d = e * std::sqrt(2 * kPi) * std::exp(0.5 * x * x);
    x = x - d / (1 + 0.5 * x * d);
  }
  return x;
}

double binomial_tail(double i, double n, double q, double u, double F_i) {
  // sec. 4.3: N = i + 1 + log_q(1 - C (u - F(i)) / (1 - F(i))), C = 1 - q^(n - i - 1)
  double C = 1.0 - std::pow(q, n - i - 1.0);
  double v = std::min(1.0, std::max(0.0, (u - F_i) / std::max(1.0 - F_i, 1e-30)));
  double t = std::log1p(-std::min(C * v, 1.0 - 5.96e-8)) / std::log(q);
  return std::min(i + 1.0 + std::floor(std::max(t, 0.0)), n);
}

double binomial_draw(double n_real, double p, double u, double u_round, Slack* slack, double n_rel_err) {
  double n = n_real > 0 ? std::min(n_real, 1e30) : 0.0;
  p = p > 0 ? std::min(p, 1.0) : 0.0;
  double n_int = std::floor(n);
  double frac = n - n_int;
  if (slack && frac > 0) slack->compare(u_round, frac, n_rel_err * n + 1e-7);
  if (u_round < frac) n_int += 1;
  bool flip = p > 0.5;
  if (slack) slack->compare(p, 0.5, 1e-7);
  double q = flip ? 1.0 - p : p;
  if (n_int == 0 || q == 0) return flip ? n_int : 0.0;
  double mean = n_int * q;
  if (slack) slack->compare(mean, kExactMean, 1e-6 * mean);
  if (mean <= kExactMean) {
    double pk = std::exp(n_int * std::log1p(-q));
    double F = pk, ratio = q / (1 - q), i = 0;
    int last = int(std::min(n_int, double(kMaxIterations)));
    for (int it = 0; it < last; ++it) {
      if (slack) slack->compare(u, F, 1e-5 * F + 1e-7);
      if (!(u >= F)) break;
      pk *= (n_int - i) / (i + 1) * ratio;
      i += 1;
      F += pk;
    }
    if (slack && !(u < F)) slack->compare(u, F, 1e-5 * F + 1e-7);
    double k = (u < F || i >= n_int) ? i : binomial_tail(i, n_int, q, u, F);
    return flip ? n_int - k : k;
  }
  // the Gaussian for the count of p itself, at z(1 - u) when flipped
  double sigma = std::sqrt(mean * (1 - q));
  double z = normal_quantile(flip ? 1 - u : u);
  double pp = flip ? p : q;
  double g = (1 - 2 * pp) / sigma;
  double kk = (1 - 6 * q * (1 - q)) / (sigma * sigma);
  double zc = z + g * (z * z - 1) / 6 + kk * (z * z * z - 3 * z) / 24 - g * g * (2 * z * z * z - 5 * z) / 36;
  double arg = n_int * pp + sigma * zc + 0.5;
  // fp32: arg is rounded once (mul_add_once) and z carries 1e-6 (1 + |z|)
  if (slack && std::fabs(arg) < 8388608.0)
    slack->compare(arg, std::round(arg), 1.2e-7 * std::fabs(arg) + 1e-6 * sigma * (1 + std::fabs(z)) + 1e-5);
  return std::min(std::max(std::floor(arg), 0.0), n_int);
}

std::vector<double> binomial_pmf(double n, double p, double& lo) {
  // mode, then the ratio recurrence both ways (no lgamma: its absolute error at
  // n = 1e12 would be 1e-3 in the log)
  std::vector<double> down, up;
  double mode = std::min(n, std::floor((n + 1) * p));
  if (p <= 0) mode = 0;
  if (p >= 1) mode = n;
  double v = 1.0;
  up.push_back(v);
  for (double k = mode; k < n && p < 1;) {
    v *= (n - k) / (k + 1) * p / (1 - p);
    k += 1;
    if (v < 1e-18) break;
    up.push_back(v);
  }
  v = 1.0;
  for (double k = mode; k > 0 && p > 0;) {
    v *= k / (n - k + 1) * (1 - p) / p;
    k -= 1;
    if (v < 1e-18) break;
    down.push_back(v);
  }
  lo = mode - double(down.size());
  std::vector<double> pmf(down.rbegin(), down.rend());
  pmf.insert(pmf.end(), up.begin(), up.end());
  double sum = 0;
  for (double x : pmf) sum += x;
  for (double& x : pmf) x /= sum;
  return pmf;
}

double beckmann_p22(const vec2& slope, const vec2& alpha) {
  double q = sq(slope.x / alpha.x) + sq(slope.y / alpha.y);
  return std::exp(-q) / (kPi * alpha.x * alpha.y);
}

double beckmann_D(const vec3& h, const vec2& center, const vec2& alpha) {
  if (!(h.z > 0)) return 0.0;
  vec2 x(h.x / h.z - center.x, h.y / h.z - center.y);
  double q = sq(x.x / alpha.x) + sq(x.y / alpha.y);
  if (!(q < 88.0)) return 0.0;  // the GLSL's cut (exp(-88) is below fp32's normal range)
  return beckmann_p22(x, alpha) / std::pow(h.z, 4);
}

double beckmann_lambda(const vec3& w, const vec2& alpha) {
  double den = std::sqrt(sq(w.x * alpha.x) + sq(w.y * alpha.y));
  if (!(den > 0)) return 0.0;
  double a = w.z / den;
  if (a >= 9.0) return 0.0;  // the GLSL's cut (Lambda < 1e-37)
  // (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)), with erf(a) - 1 = -erfc(a) (no cancellation in erf)
  return std::max(0.0, -std::erfc(a) / 2.0 + std::exp(-a * a) / (2.0 * a * std::sqrt(kPi)));
}

double smith_G2(const vec3& wi, const vec3& wo, const vec3& h, const vec2& alpha) {
  if (!(wi.z > 0) || !(wo.z > 0) || !(glm::dot(h, wi) > 0) || !(glm::dot(h, wo) > 0)) return 0.0;
  return 1.0 / (1.0 + beckmann_lambda(wi, alpha) + beckmann_lambda(wo, alpha));
}

double smith_G2_over_cos_o(const vec3& wi, const vec3& wo, const vec3& h, const vec2& alpha) {
  if (!(wo.z > 0)) return 0.0;
  return smith_G2(wi, wo, h, alpha) / wo.z;
}

vec2 beckmann_sample_slope(double u1, double u2, const vec2& alpha) {
  double r = std::sqrt(std::max(-std::log(u1), 0.0));
  return vec2(alpha.x * r * std::cos(2 * kPi * u2), alpha.y * r * std::sin(2 * kPi * u2));
}

Roughness roughness(const Params& p, double sun_cone) {
  Roughness g;
  g.cone = p.light_cone >= 0 ? p.light_cone : std::min(0.5, std::max(0.0, sun_cone));
  vec2 ag = p.alpha_g, al = p.alpha_g * p.relative;
  g.alpha_surface = ag;
  g.alpha_m = vec2(std::sqrt(std::max(0.0, sq(ag.x) - sq(al.x))), std::sqrt(std::max(0.0, sq(ag.y) - sq(al.y))));
  double ac = std::sqrt(2.0) / 4.0 * g.cone;  // disk of radius cone/2 in slope space, per-axis variance matched
  g.alpha_g = vec2(std::sqrt(sq(ag.x) + sq(ac)), std::sqrt(sq(ag.y) + sq(ac)));
  g.alpha_l = vec2(std::sqrt(sq(al.x) + sq(ac)), std::sqrt(sq(al.y) + sq(ac)));
  g.h_cell = vec2(std::max(0.5 * (al.x + 0.5 * g.cone), 1e-4), std::max(0.5 * (al.y + 0.5 * g.cone), 1e-4));
  double gm;
  if (!(std::max(g.alpha_m.x, g.alpha_m.y) > 0)) gm = 1;
  else if (g.alpha_m.y == 0) gm = 4096;
  else gm = std::min(4096.0, std::max(1.0 / 4096.0, g.alpha_m.x / g.alpha_m.y));
  g.stretch = gm > 1 ? vec2(1, 1 / gm) : vec2(gm, 1);
  g.s_ref = std::pow(10.0, -0.5 * p.log_density);
  g.hv_blend = p.half_vector_blend;
  return g;
}

vec3 glint_tint(double hue, double saturation, double N) {
  vec3 c;
  for (int k = 0; k < 3; ++k) c[k] = 1.0 + saturation / std::sqrt(std::max(N, 1.0)) * std::cos(2 * kPi * (hue - k / 3.0));
  return c;
}

Footprint footprint(vec2 dx, vec2 dy, double s_ref) {
  dx = clamp2(dx);
  dy = clamp2(dy);
  Footprint f;
  double m = std::max({std::fabs(dx.x), std::fabs(dx.y), std::fabs(dy.x), std::fabs(dy.y)});
  if (m > 0) {
    // sec. 4.2: s_c = 1 / ||M^-1||_max, M^-1 = [[dy.y, -dy.x], [-dx.y, dx.x]] / det
    double det = dx.x * dy.y - dx.y * dy.x;
    double inv_max = m / std::fabs(det);
    f.s_c = std::max(1.0 / inv_max, m / kKa);
    if (!std::isfinite(inv_max)) f.s_c = m / kKa;
    f.level_f = std::log2(f.s_c / s_ref);
  } else {
    f.s_c = 0;
    f.level_f = -1;
  }
  if (!(f.level_f > 0)) {
    f.level0 = f.level1 = 0;
    f.weight0 = 1;
    f.weight1 = 0;
  } else if (f.level_f >= kMaxLevel) {
    f.level0 = f.level1 = kMaxLevel;
    f.weight0 = 1;
    f.weight1 = 0;
  } else {
    double k = std::floor(f.level_f);
    f.level0 = int(k);
    f.level1 = f.level0 + 1;
    f.weight1 = f.level_f - k;
    f.weight0 = 1 - f.weight1;
  }
  return f;
}

Walk walk(vec2 uv, vec2 dx, vec2 dy, double cell, Slack* slack) {
  Walk w;
  w.c = clamp2(uv) / cell;
  vec2 a = clamp2(dx) / cell, b = clamp2(dy) / cell;
  double ma = std::max(std::fabs(a.x), std::fabs(a.y)), mb = std::max(std::fabs(b.x), std::fabs(b.y));
  if (slack && (ma > 0 || mb > 0)) slack->compare(ma, mb, 1e-6 * std::max(ma, mb));
  vec2 A = ma >= mb ? a : b;
  if (slack && A != vec2(0)) slack->compare(std::fabs(A.x), std::fabs(A.y), 1e-6 * std::max(std::fabs(A.x), std::fabs(A.y)));
  w.j = std::fabs(A.x) >= std::fabs(A.y) ? 0 : 1;
  double Aj = w.j == 0 ? A.x : A.y, Ai = w.j == 0 ? A.y : A.x;
  w.slope = Aj != 0 ? Ai / Aj : 0.0;
  double half_len = std::min(std::max(0.5 * std::fabs(Aj) - 0.5, 0.0), 0.5 * (kMaxColumns - 2));
  double cj = w.j == 0 ? w.c.x : w.c.y;
  w.t_lo = cj - half_len;
  w.t_hi = cj + half_len;
  if (slack) {
    slack->floor_arg(w.t_lo - 0.5);
    slack->floor_arg(w.t_hi + 0.5);
  }
  w.first = std::floor(w.t_lo - 0.5);
  double last = std::ceil(w.t_hi + 0.5) - 1;
  w.columns = int(std::min(std::max(last - w.first + 1, 1.0), double(kMaxColumns + 2)));
  return w;
}

namespace {
double tent_integral(double x) {
  if (x <= -1) return 0;
  if (x <= 0) return 0.5 * sq(x + 1);
  if (x < 1) return 1 - 0.5 * sq(1 - x);
  return 1;
}
}  // namespace

Cell walk_cell(const Walk& w, int column, int row, Slack* slack) {
  double n = w.first + column;
  double len = w.t_hi - w.t_lo;
  double wc;
  if (slack) slack->compare(len, 1e-3, 1e-6 * std::fabs(w.t_hi) + 1e-6);
  if (len > 1e-3) wc = (tent_integral(w.t_hi - n - 0.5) - tent_integral(w.t_lo - n - 0.5)) / len;
  else wc = std::max(0.0, 1 - std::fabs(0.5 * (w.t_lo + w.t_hi) - n - 0.5));
  double t = std::min(std::max(n + 0.5, w.t_lo), w.t_hi);
  double ci = w.j == 0 ? w.c.y : w.c.x, cj = w.j == 0 ? w.c.x : w.c.y;
  double x = ci + (t - cj) * w.slope - 0.5;
  if (slack) slack->floor_arg(x);
  double m = std::floor(x), f = x - m;
  Cell c;
  c.weight = std::max(wc, 0.0) * (row == 0 ? 1 - f : f);
  uint32_t col_index = wrapped_floor(n), row_index = wrapped_floor(m) + uint32_t(row);
  c.index = w.j == 0 ? uvec2{col_index, row_index} : uvec2{row_index, col_index};
  return c;
}

uvec2 coherent_seed(uvec2 cell, int level) {
  uint32_t u = cell[0] + (0x50000000u >> level), v = cell[1] + (0x30000000u >> level);
  auto tz = [](uint32_t x) {
    int n = 0;
    if (x == 0) return 32;
    while (!(x & 1u)) x >>= 1, ++n;
    return n;
  };
  int t = std::min(tz(u), tz(v));
  if (t >= 32) return {0u, 0u};
  return {u >> t, v >> t};
}

Frame frame(const vec3& t, const vec3& b, const vec3& n, const vec3& wi, const vec3& wo) {
  Frame f;
  f.wi = vec3(glm::dot(t, wi), glm::dot(b, wi), glm::dot(n, wi));
  f.wo = vec3(glm::dot(t, wo), glm::dot(b, wo), glm::dot(n, wo));
  vec3 s = f.wi + f.wo;
  double len = glm::length(s);
  f.h = len > 0 ? s / len : vec3(0);
  f.valid = f.wi.z > 0 && f.wo.z > 0 && f.h.z > 0;
  return f;
}

vec2 paraboloid_map(const vec3& h) { return vec2(h.x, h.y) / (1.0 + std::max(h.z, 0.0)); }

ZirrPixel zirr_pixel(const vec3& h, const Roughness& r) {
  ZirrPixel px;
  px.m0 = 1.0 / (kPi * r.alpha_l.x * r.alpha_l.y);  // eq. 7's D_l(0)
  // eq. 7: P(h) = D_g(h) / D_l(0) in the slope domain
  px.pmf = h.z > 0 ? std::min(1.0, beckmann_p22(vec2(h.x / h.z, h.y / h.z), r.alpha_g) / px.m0) : 0.0;
  if (h.z > 0 && !(sq(h.x / h.z / r.alpha_g.x) + sq(h.y / h.z / r.alpha_g.y) < 88.0)) px.pmf = 0.0;
  px.hp = paraboloid_map(h);
  return px;
}

namespace {

// One half-vector bin of a cell: Listing 1 lines 16-20 (glint_zirr_bin).
vec3 zirr_bin(uvec2 seed, uint32_t hx, uint32_t hy, double n_cell, const ZirrPixel& px, double size_variation,
              double saturation, double hue, Slack* slack, double* cn_rel_err) {
  sand::uvec3 hh = sand::pcg3d({seed[0], seed[1], sand::pcg3d({hx, hy, kHalfSalt})[0]});
  vec3 u = open01(hh);
  double Cn = n_cell, err = 2e-6;
  if (size_variation > 0) {
    double z = normal_quantile(u.y), s = std::fabs(1 + size_variation * z);
    Cn *= std::max(s, 1e-3);
    if (s > 1e-3) err += size_variation * 1e-6 * (1 + std::fabs(z)) / s;  // the GLSL quantile's error, relative to s
    if (slack) slack->compare(s, 1e-3, 1e-6 * (1 + std::fabs(z)) * size_variation);
  }
  if (cn_rel_err) *cn_rel_err = err;
  double rn = binomial_draw(Cn, px.pmf, u.x, u.z, slack, err);
  if (!(rn > 0)) return vec3(0);
  return (rn * px.m0 / Cn) * glint_tint(hue, saturation, rn);
}

}  // namespace

vec3 zirr_cell(uvec2 seed, double n_cell, const ZirrPixel& px, const Roughness& r, double size_variation,
               double saturation, Slack* slack, double* cn_rel_err) {
  vec3 uc = unit01(sand::pcg3d({seed[0], seed[1], kOffsetSalt}));
  vec2 harg(px.hp.x / r.h_cell.x + uc.x, px.hp.y / r.h_cell.y + uc.y);
  if (!r.hv_blend) {
    if (slack) {
      slack->floor_arg(harg.x);
      slack->floor_arg(harg.y);
    }
    return zirr_bin(seed, wrapped_floor(harg.x), wrapped_floor(harg.y), n_cell, px, size_variation, saturation, uc.z,
                    slack, cn_rel_err);
  }
  // glint_zirr_cell's blend of the four bins around harg (bin centres at k + 1/2)
  vec2 q(harg.x - 0.5, harg.y - 0.5);
  if (slack) {
    slack->floor_arg(q.x);
    slack->floor_arg(q.y);
  }
  vec2 f(q.x - std::floor(q.x), q.y - std::floor(q.y));
  uint32_t bx = wrapped_floor(q.x), by = wrapped_floor(q.y);
  vec3 acc(0);
  double err = 0;
  for (uint32_t k = 0; k < 4; ++k) {
    uint32_t dx = k & 1u, dy = k >> 1;
    double w = (dx ? f.x : 1 - f.x) * (dy ? f.y : 1 - f.y);
    if (!(w > 0)) continue;
    double e = 0;
    acc += w * zirr_bin(seed, bx + dx, by + dy, n_cell, px, size_variation, saturation, uc.z, slack, &e);
    err = std::max(err, e);
  }
  if (cn_rel_err) *cn_rel_err = err;
  return acc;
}

Zirr zirr(vec2 uv, vec2 dx, vec2 dy, const vec3& h, const Roughness& r, double size_variation, double saturation,
          Slack* slack) {
  return zirr(uv, dx, dy, h, r, zirr_pixel(h, r), size_variation, saturation, slack);
}

Zirr zirr(vec2 uv, vec2 dx, vec2 dy, const vec3& h, const Roughness& r, const ZirrPixel& px, double size_variation,
          double saturation, Slack* slack) {
  Zirr z;
  if (!(h.z > 0) || !(px.pmf > 0)) return z;
  Slack* ws = &z.walk_slack;
  Footprint fp = footprint(dx, dy, r.s_ref);
  if (fp.level_f > 0 && fp.level_f < kMaxLevel) ws->floor_arg(fp.level_f);
  ws->compare(fp.level_f, 0.0, 1e-5);
  vec2 st_uv = clamp2(uv) * r.stretch, st_dx = clamp2(dx) * r.stretch, st_dy = clamp2(dy) * r.stretch;
  vec3 reflectance(0);
  for (int g = 0; g < 2; ++g) {
    double mw = g == 0 ? fp.weight0 : fp.weight1;
    if (!(mw > 0)) continue;
    int level = g == 0 ? fp.level0 : fp.level1;
    double cell = r.s_ref * std::ldexp(1.0, level);
    double n_cell = std::ldexp(1.0, 2 * level) / (r.stretch.x * r.stretch.y);
    Walk w = walk(st_uv, st_dx, st_dy, cell, ws);
    vec3 acc(0);
    double wsum = 0, dwsum = 0, dwcr = 0;
    double e = 2.4e-7 * (std::fabs(w.c.x) + std::fabs(w.c.y) + std::fabs(w.t_hi) + 2);
    double dw = 3 * e + 2.4e-7 / std::max(w.t_hi - w.t_lo, 1e-3);  // coordinates, and the rounding of the tent integrals
    for (int col = 0; col < w.columns; ++col)
      for (int row = 0; row < 2; ++row) {
        Cell c = walk_cell(w, col, row, ws);
        // a tiny weight in double may be 0 in fp32 (exact zeros are structural and shared)
        if (c.weight > 0 && c.weight < 1e-6) ws->min = std::min(ws->min, c.weight - 1e-6);
        if (!(c.weight > 0)) continue;
        z.cells += 1;
        double ce = 0;
        vec3 Cr = zirr_cell(coherent_seed(c.index, level), n_cell, px, r, size_variation, saturation, slack, &ce);
        acc += c.weight * Cr;
        z.rel_err = std::max(z.rel_err, ce);
        wsum += c.weight;
        dwsum += dw;
        dwcr += dw * std::max({Cr.x, Cr.y, Cr.z});
      }
    if (wsum > 0) {
      reflectance += mw * acc / wsum;
      z.abs_err += mw * (dwcr + dwsum * std::max({acc.x, acc.y, acc.z}) / wsum) / wsum;
    }
  }
  z.D = reflectance / std::pow(h.z, 4);  // slope domain -> directions (|dm/dx| = |m.n|^4)
  z.abs_err /= std::pow(h.z, 4);
  if (slack) slack->min = std::min(slack->min, z.walk_slack.min);
  return z;
}

vec3 grains_D(vec2 uv, const vec3& h, const Roughness& r, double saturation, Slack* slack, double* q_out,
              vec2* x_i_out) {
  if (!(h.z > 0)) return vec3(0);
  double cell = r.s_ref * std::sqrt(r.stretch.x * r.stretch.y);
  vec2 x = clamp2(uv) * r.stretch / cell;
  if (slack) {
    slack->floor_arg(x.x);
    slack->floor_arg(x.y);
  }
  vec3 u = unit01(sand::pcg3d({wrapped_floor(x.x), wrapped_floor(x.y), kGrainsSalt}));
  vec2 x_i = beckmann_sample_slope(1.0 - u.x, u.y, r.alpha_m);
  if (q_out) *q_out = sq((h.x / h.z - x_i.x) / r.alpha_l.x) + sq((h.y / h.z - x_i.y) / r.alpha_l.y);
  if (x_i_out) *x_i_out = x_i;
  return beckmann_D(h, x_i, r.alpha_l) * glint_tint(u.z, saturation, 1.0);
}

double beckmann_model_D(const Frame& f, const Roughness& r) { return beckmann_D(f.h, vec2(0), r.alpha_g); }

vec3 glint_radiance(const vec3& D, const Frame& f, const Roughness& r, double ior, const vec3& L_i, double intensity) {
  if (!f.valid) return vec3(0);
  double F = sand::schlick(sand::fresnel_f0(ior), glm::dot(f.h, f.wo));
  // eq. 1 times L_i cos_i
  double fr = intensity * F * smith_G2(f.wi, f.wo, f.h, r.alpha_surface) / (4.0 * f.wi.z * f.wo.z) * f.wi.z;
  return L_i * fr * D;
}

Term glint_term(uint32_t model, const Params& p, vec2 uv, vec2 duv_dx, vec2 duv_dy, const vec3& t, const vec3& b,
                const vec3& n, const vec3& wi, const vec3& wo, const vec3& L_i, double sun_cone, Slack* slack) {
  Term g;
  Frame f = frame(t, b, n, wi, wo);
  if (!f.valid) return g;
  Roughness r = roughness(p, sun_cone);
  vec3 D(0);
  if (model == kGlintBeckmann) {
    D = vec3(beckmann_model_D(f, r));
  } else if (model == kGlintGrains) {
    D = grains_D(uv, f.h, r, p.color_saturation, slack);
  } else if (model == kGlintZirr) {
    Zirr z = zirr(uv, duv_dx, duv_dy, f.h, r, p.size_variation, p.color_saturation, slack);
    D = z.D;
    g.cells = z.cells;
  }
  g.L = glint_radiance(D, f, r, p.ior, L_i, p.intensity);
  return g;
}

}  // namespace glintlab::reference::glint

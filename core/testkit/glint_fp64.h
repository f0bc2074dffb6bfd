// fp64 reference of the microdetail glint models of shaders/sand/ (grains,
// zirr, beckmann; Zirr & Kaplanyan 2016), written from the paper and the
// GLSL's documented definitions, in double precision: the Beckmann terms
// with the exact erfc (std::erfc; the GLSL uses a 1.2e-7 fit), the normal
// quantile to full precision (the GLSL uses Acklam's 1.15e-9 fit), log1p
// from <cmath>, floor modulo 2^32 through fmod. Hashes (pcg3d) are exact on
// uint32. The discrete decisions (cell indices, binomial inversion steps,
// rounding) are made in double; every decision also reports its distance
// to the nearest boundary ("slack"), so a comparison with the fp32 GPU can
// skip items whose decisions fp32 rounding could flip.
#pragma once

#include "core/testkit/sand_fp64.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace glintlab::reference::glint {

using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using uvec2 = std::array<uint32_t, 2>;

// The twins of the built-in models (shaders/glint/models/<name>.glsl) have
// the ids of this file; the GPU's SandParams.glint_model
// (core::glint_model_gpu_id) maps to them by the model's name.
constexpr uint32_t kGlintGrains = 2u, kGlintZirr = 3u, kGlintBeckmann = 4u;
uint32_t twin_of_gpu(uint32_t gpu_id);  // 0: a model without a twin (or kajs, none)
uint32_t gpu_of_twin(uint32_t twin);
const char* twin_name(uint32_t twin);  // the built-in model's name; "" for no twin
constexpr double kKa = 16.0;       // GLINT_K_A
constexpr int kMaxLevel = 28;      // GLINT_MAX_LEVEL
constexpr int kMaxColumns = 40;    // GLINT_MAX_COLUMNS
constexpr double kExactMean = 24;  // BINOMIAL_EXACT_MEAN
constexpr int kMaxIterations = 48; // BINOMIAL_MAX_ITERATIONS

// The glint parameters as the GPU sees them (SandParamsGPU, fp32 promoted).
struct Params {
  vec2 alpha_g, relative;
  double log_density, size_variation, intensity, light_cone, color_saturation, ior;
  bool half_vector_blend = false;  // zirr: the four nearest half-vector bins, bilinear (glints.half_vector_blend)
};
// The model's own parameters from the slots its declaration gives them (0 where it declares none).
Params from_gpu(const core::SandParamsGPU& g);

// Tracks the smallest slack of the discrete decisions of one evaluation:
// slack = distance to the decision boundary minus an allowance for fp32
// rounding of the decided quantity. < 0: fp32 may decide differently.
struct Slack {
  double min = 1e300;
  void floor_arg(double x);                 // floor(x): |x - round(x)| vs 4e-6 |x| + 1e-5
  void compare(double a, double b, double allowance);  // a < b or a >= b
};

// ---- common/math.glsl, common/wrapped_floor.glsl, common/normal_quantile.glsl
double safe_log1p(double x);                 // log1p; -3.4e38 for x <= -1 or NaN
uint32_t wrapped_floor(double x);            // floor(x) mod 2^32 (x an fp32 value)
double normal_quantile(double u);            // Phi^-1(u), u clamped to [2^-25, 1 - 2^-25]

// ---- common/binomial.glsl
double binomial_tail(double i, double n, double q, double u, double F_i);
// Same algorithm (regimes, recurrence, Cornish-Fisher terms) in double.
// n_rel_err: relative error of the caller's n in fp32 (0: n is an exact input),
// widening the slack of the rounding decision. The final rounding of the
// Gaussian regime enters the slack only below 2^23 (beyond, fp32 cannot
// resolve single counts; compare with a tolerance there).
double binomial_draw(double n, double p, double u, double u_round, Slack* slack = nullptr, double n_rel_err = 0.0);
// Exact binomial pmf of integer n (double; recurrence from the mode, normalised),
// over [lo, hi] (all k with pmf > 1e-300 * max of that range are included).
std::vector<double> binomial_pmf(double n, double p, double& lo);

// ---- common/beckmann.glsl
double beckmann_p22(const vec2& slope, const vec2& alpha);
double beckmann_D(const vec3& h, const vec2& center, const vec2& alpha);
double beckmann_lambda(const vec3& w, const vec2& alpha);   // exact erfc; w.z > 0
double smith_G2(const vec3& wi, const vec3& wo, const vec3& h, const vec2& alpha);
double smith_G2_over_cos_o(const vec3& wi, const vec3& wo, const vec3& h, const vec2& alpha);
vec2 beckmann_sample_slope(double u1, double u2, const vec2& alpha);

// ---- sand/glint_roughness.glsl
struct Roughness {
  vec2 alpha_surface, alpha_g, alpha_l, alpha_m, stretch, h_cell;
  double s_ref, cone;
  bool hv_blend = false;
};
Roughness roughness(const Params& p, double sun_cone);

// ---- sand/glint_color.glsl
vec3 glint_tint(double hue, double saturation, double N);

// ---- sand/glint_footprint.glsl
struct Footprint {
  double s_c, level_f;
  int level0, level1;
  double weight0, weight1;
};
Footprint footprint(vec2 dx, vec2 dy, double s_ref);
struct Walk {
  vec2 c;
  int j;
  double slope, t_lo, t_hi, first;
  int columns;
};
Walk walk(vec2 uv, vec2 dx, vec2 dy, double cell, Slack* slack = nullptr);
struct Cell {
  uvec2 index;
  double weight;
};
Cell walk_cell(const Walk& w, int column, int row, Slack* slack = nullptr);
uvec2 coherent_seed(uvec2 cell, int level);

// ---- the models (glint/models/*.glsl)
struct Frame {
  vec3 wi, wo, h;
  bool valid;
};
Frame frame(const vec3& t, const vec3& b, const vec3& n, const vec3& wi, const vec3& wo);
vec2 paraboloid_map(const vec3& h);
struct ZirrPixel {
  double pmf, m0;
  vec2 hp;
};
ZirrPixel zirr_pixel(const vec3& h, const Roughness& r);
// cn_rel_err: the relative error fp32 may have in the cell's Cn (the size
// factor |1 + size_variation z| loses digits near 0), to which Cr is inversely
// proportional.
vec3 zirr_cell(uvec2 seed, double n_cell, const ZirrPixel& px, const Roughness& r, double size_variation,
               double saturation, Slack* slack = nullptr, double* cn_rel_err = nullptr);
struct Zirr {
  vec3 D{0.0};
  double cells = 0;
  Slack walk_slack;  // the decisions of the footprint and walk alone (which cells, not their counts)
  double rel_err = 0;  // largest cn_rel_err of its cells
  // error fp32 coordinates (a few ulps of the cell coordinates) may put into
  // D through the coverage weights: sum over cells of dw (Cr + mean) / sum w,
  // dw = 3 e + 2.4e-7 / len, e = 2.4e-7 (|c.x| + |c.y| + |t| + 2), per colour max
  double abs_err = 0;
};
Zirr zirr(vec2 uv, vec2 dx, vec2 dy, const vec3& h, const Roughness& r, double size_variation, double saturation,
          Slack* slack = nullptr);
// The same with the per-pixel values given (a comparison feeds the GPU's
// fp32 h, roughness and pixel values, so only the walk and the cells differ).
Zirr zirr(vec2 uv, vec2 dx, vec2 dy, const vec3& h, const Roughness& r, const ZirrPixel& px, double size_variation,
          double saturation, Slack* slack = nullptr);
// q_out: the exponent |(x_h - x_i) / alpha_l|^2 of the microdetail lobe; x_i_out its centre.
vec3 grains_D(vec2 uv, const vec3& h, const Roughness& r, double saturation, Slack* slack = nullptr,
              double* q_out = nullptr, vec2* x_i_out = nullptr);
double beckmann_model_D(const Frame& f, const Roughness& r);
vec3 glint_radiance(const vec3& D, const Frame& f, const Roughness& r, double ior, const vec3& L_i, double intensity);

// sand/glint_models.glsl: the term of one shading point.
struct Term {
  vec3 L{0.0};
  double cells = 0;
};
Term glint_term(uint32_t model, const Params& p, vec2 uv, vec2 duv_dx, vec2 duv_dy, const vec3& t, const vec3& b,
                const vec3& n, const vec3& wi, const vec3& wo, const vec3& L_i, double sun_cone, Slack* slack = nullptr);

}  // namespace glintlab::reference::glint

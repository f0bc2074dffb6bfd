// fp64 reference of the Kajs 2022 sand material (thesis chapter 4 and the
// Appendix A options of shaders/sand/), written independently of the GLSL:
// same function names, double precision, the thesis formulas in their
// literal form where that is numerically safe in double (eq. 4.7, 4.22,
// 4.25, 4.31 with pow; Oren-Nayar through azimuth angles; the sigmoid
// through tanh). pcg3d is exact on uint32. The grain cell key is defined on
// the fp32 value floor(fp32(x_obj * noise_scale)), so it is computed with
// fp32 rounding here too (that is its definition, not an approximation).
#pragma once

#include "core/material/sand_material.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace glintlab::reference::sand {

using vec3 = glm::dvec3;
using uvec3 = std::array<uint32_t, 3>;

// Bits and modes as in shaders/sand/sand_params.glsl.
constexpr uint32_t kCompatRandNormalized = 1u, kCompatIntensityXi1 = 2u, kCompatGateXi1 = 4u, kCompatGlintSky = 8u,
                   kCompatFresnelAbs = 16u, kCompatOrenNayarWorld = 32u;
constexpr uint32_t kFresnelMacroNormal = 0u, kFresnelLightView = 1u;
constexpr uint32_t kGlintNone = 0u, kGlintKajs = 1u;  // Params::glint_model, else a twin id (glint_fp64.h)

struct Params {
  std::array<vec3, 8> palette;
  vec3 I_glints;
  double SSS, R_s, T, R_t, sigma_g, P, noise_scale, ior, scattering, absorption, sigma_on, sig_a, sig_b;
  uint32_t appendix_compat, fresnel_half_vector, glint_model;
  float noise_scale_f32;  // the fp32 scale that seeds the cells
  uint32_t energy_consistent;
  core::SandParamsGPU gpu;  // as packed: the glint models read their parameters from it (glint_reference.h)
};
// The values the GPU sees (fp32 packed) promoted to double.
Params from_gpu(const core::SandParamsGPU& g);

struct Surface {
  std::array<float, 3> x_obj;  // fp32 object position (seeds the cells)
  vec3 n, wo;
  double dist;
  vec3 t{1, 0, 0}, b{0, 1, 0};  // tangent frame of the glint models
  glm::dvec2 uv{0.0}, duv_dx{0.0}, duv_dy{0.0};
};
struct Light {
  vec3 wi, L_i, L_sky_omega;
  double cone = 0.0;  // the sun's angular radius
};

uvec3 pcg3d(uvec3 v);                                                  // Jarzynski & Olano 2020
uvec3 grain_cell_key(const std::array<float, 3>& x_obj, float noise_scale);
struct GrainRandom {
  vec3 xi, xi_pm;
};
GrainRandom grain_random(const uvec3& key, uint32_t appendix_compat);
vec3 sphere_direction(double xi1, double xi2);                          // eq. 4.1
void frisvad_basis(const vec3& n, vec3& b1, vec3& b2);                  // Frisvad 2012 / Duff et al. 2017
// Face 0..5 (+b1,+b2,+q,-b1,-b2,-q); margin = best dot - second best dot.
vec3 micro_normal(double xi1, double xi2, const vec3& wo, int& face, double& margin);
int palette_index(const vec3& xi);                                      // eq. 4.3-4.4
vec3 rho_m(const Params& p, int index);                                 // eq. 4.4
vec3 rho_n(const Params& p);                                            // eq. 4.8
double I_min(double P, double dist);                                    // eq. 4.6
double rho_m_intensity(double I_min_, double xi);                       // eq. 4.7
double rho_n_intensity(double I_min_);                                  // eq. 4.9
double f_s(double scattering, double SSS);                              // eq. 4.12
double f_e(double absorption, double SSS);                              // eq. 4.13
vec3 L_d(const vec3& rho, double f_s_, double f_e_, const vec3& L_i, const vec3& L_sky, double cos_ni);  // eq. 4.11
double fresnel_f0(double ior);                                          // eq. 4.15
double schlick(double f0, double cos_ho);                               // eq. 4.14
double fresnel_cos(const vec3& n, const vec3& wi, const vec3& wo, uint32_t mode, uint32_t compat);
double F_strength(double R_s);                                          // eq. 4.22
vec3 L_f(double f, const vec3& L_sky, const vec3& L_i, double cos_ni);  // eq. 4.16
double GDF(double x, double sigma);                                     // eq. 4.17
double g_glint(double gdf, const vec3& wo, const vec3& wi, const vec3& m, double cos_ni);  // eq. 4.18
double G_strength(double R_s);                                          // eq. 4.21
vec3 L_g(double g, const vec3& L_i, const vec3& L_sky, const vec3& I_glints, uint32_t compat);  // eq. 4.19-4.20
double T_ext(double T);                                                 // eq. 4.25
double R_t_star(double R_t);                                            // eq. 4.29
double R_t_strength(double R_t);                                        // eq. 4.30
double transmission_t(double T, double R_t, const vec3& n, const vec3& wo, const vec3& wi);  // eq. 4.31
vec3 L_t(const vec3& rho_n_, const vec3& L_i, double t);                // eq. 4.32
double L_oren(const vec3& n, const vec3& wi, const vec3& wo, double sigma, uint32_t compat);  // eq. 4.34
vec3 L_brdf(const vec3& rho_n_, double f_s_, double f_e_, double L_oren_, double cos_ni, const vec3& L_i,
            const vec3& L_sky, double fresnel_weight, double T_ext_);   // eq. 4.35
vec3 L_far(const vec3& L_brdf_, const vec3& L_f_, const vec3& L_t_, double rho_n_intensity_);  // eq. 4.36
double sig(double x, double a, double b);                               // eq. 4.37
vec3 L_close(const vec3& L_d_, const vec3& L_s_, const vec3& L_t_, double rho_m_intensity_);  // eq. 4.33
vec3 L_final(const vec3& L_close_, const vec3& L_far_, double sig_);   // eq. 4.38
// The glint term's part of L_final (sand/sand.glsl sand_glint_radiance): eq. 4.38, 4.33 and 4.36 are
// linear in the glint terms, G = (1 - sig) rho_m^intensity L_g + sig rho_n^intensity L_g_far.
vec3 glint_radiance(const vec3& L_g_, const vec3& L_g_far_, double rho_m_intensity_, double rho_n_intensity_,
                    double sig_);
// G's share of L_final's Rec. 709 luma in [0, 1]; 0 where L_final's luma is not positive.
double glint_share(const vec3& G, const vec3& L_final_);
// shaders/sand/energy.glsl: 1 for the thesis; pi and 1/pi when energy consistent
double sky_diffuse_scale(uint32_t energy_consistent);
double sun_lobe_scale(uint32_t energy_consistent);

// Pruning as the SAND_* defines (all on = the full material).
struct Features {
  bool transmission = true, glints = true, close = true, far = true;
};

struct Terms {
  vec3 xi{0}, xi_pm{0};
  int face = 0;
  vec3 m{0};
  int palette_index = 0;
  vec3 rho_m{0}, rho_n{0};
  double I_min = 0, rho_m_intensity = 0, rho_n_intensity = 0, f_s = 0, f_e = 0, F_Rs = 0, G_Rs = 0, f = 0, gdf = 0,
         g = 0;
  vec3 L_d{0}, L_f{0}, L_g{0}, L_s{0};
  double T_ext = 1, t = 0;
  vec3 L_t{0};
  double L_oren = 0;
  vec3 L_brdf{0}, L_far{0}, L_close{0};
  double sig = 0;
  vec3 L_final{0};
  // distances to the decision boundaries of the discontinuous terms
  double face_margin = 1e300;     // best - second best cube-face dot
  double palette_margin = 1e300;  // min |xi - 0.5|
  double gate_x = 0;              // the value the Gaussian gate reads
  double glint_cells = 0;         // zirr: cells visited
  vec3 L_g_far{0};                // beckmann glints of the far field (grains/zirr/beckmann)
  double glint_slack = 1e300;     // glint_reference.h Slack of the grains/zirr decisions
};
Terms sand_terms(const Params& p, const Surface& s, const Light& l, const Features& features = {});

}  // namespace glintlab::reference::sand

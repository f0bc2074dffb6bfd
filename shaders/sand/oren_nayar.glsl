// Far-field diffuse: Oren-Nayar (Kajs 2022 eq. 4.34, after Pharr et al.)
// with the subsurface approximation, L_brdf (eq. 4.35), and L_far (eq. 4.36).
#ifndef GLINTLAB_SAND_OREN_NAYAR_GLSL
#define GLINTLAB_SAND_OREN_NAYAR_GLSL

#include "common/math.glsl"
#include "sand/sand_params.glsl"

// Kajs eq. 4.34: A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta),
// angles measured from the macro normal n (sigma in radians). Back-facing
// directions are clamped to the horizon (cos = 0). tan(beta) is formed as
// sin/max(cos, OREN_NAYAR_MIN_COS), finite at grazing; L_brdf multiplies by
// max(0, n.w_i), which keeps the product bounded. The exact product
// L_oren cos_i jumps from B sin(theta_o) cos(dphi) to 0 when w_i crosses the
// horizon; the floor on cos turns the jump into a ramp of slope
// B / OREN_NAYAR_MIN_COS over cos_i in [0, OREN_NAYAR_MIN_COS], and the fp32
// cosines (dot products, ~1.2e-7 absolute) move the value by that slope
// times 1.2e-7. A floor of 1e-6 would give up to 1.2e-2
// absolute (A + B ~ 1: 1 % of the diffuse at a grazing sun; measured 1.25e-2
// by `glintlab stress`, math.oren-nayar-0-90deg); at 1e-4 it is 1.2e-4 and
// the model differs from the exact one only within 1e-4 rad (0.006 deg) of
// the horizon, where the exact one is discontinuous. With SAND_COMPAT_OREN_NAYAR_WORLD the
// angles are taken against the world z axis with |cos| and tan(beta) is
// saturated, as Appendix A's Loren() does.
#define OREN_NAYAR_MIN_COS 1e-4

float L_oren(vec3 n, vec3 wi, vec3 wo, float sigma, uint appendix_compat) {
  bool world = (appendix_compat & SAND_COMPAT_OREN_NAYAR_WORLD) != 0u;
  vec3 N = world ? vec3(0.0, 0.0, 1.0) : n;
  float s2 = sigma * sigma;
  float A = 1.0 - s2 / (2.0 * (s2 + 0.33));
  float B = 0.45 * s2 / (s2 + 0.09);
  float ci_raw = dot(N, wi);
  float co_raw = dot(N, wo);
  float cos_i = world ? min(abs(ci_raw), 1.0) : clamp(ci_raw, 0.0, 1.0);
  float cos_o = world ? min(abs(co_raw), 1.0) : clamp(co_raw, 0.0, 1.0);
  // sin from the cross product (sqrt(1 - cos^2) loses half the digits near
  // cos = 1); a direction below the horizon is clamped to it (sin = 1).
  float sin_i = (world || ci_raw > 0.0) ? min(length(cross(N, wi)), 1.0) : 1.0;
  float sin_o = (world || co_raw > 0.0) ? min(length(cross(N, wo)), 1.0) : 1.0;
  // cos(phi_i - phi_o) from the tangent-plane projections
  vec3 p_i = wi - N * ci_raw;
  vec3 p_o = wo - N * co_raw;
  float denom = sqrt(dot(p_i, p_i) * dot(p_o, p_o));
  bool azimuth_defined = denom > 1e-20 && (!world || (sin_i > 0.0001 && sin_o > 0.0001));
  float cos_dphi = azimuth_defined ? clamp(dot(p_i, p_o) / denom, -1.0, 1.0) : 0.0;
  float sin_alpha, tan_beta;
  if (cos_i > cos_o) {  // theta_i < theta_o: alpha = theta_o, beta = theta_i
    sin_alpha = sin_o;
    tan_beta = sin_i / max(cos_i, OREN_NAYAR_MIN_COS);
  } else {
    sin_alpha = sin_i;
    tan_beta = sin_o / max(cos_o, OREN_NAYAR_MIN_COS);
  }
  if (world) tan_beta = min(tan_beta, 1.0);
  return A + B * max(0.0, cos_dphi) * sin_alpha * tan_beta;
}

// Kajs eq. 4.35 (without the (1 - f) and T_ext updates, applied by the caller
// through `fresnel_weight` = 1 - f and `T_ext_`).
vec3 L_brdf(vec3 rho_n_, float f_s_, float f_e_, float L_oren_, float cos_ni, vec3 L_i, vec3 L_sky,
            float fresnel_weight, float T_ext_) {
  vec3 L = rho_n_ * INV_PI * L_i * (f_s_ + (1.0 - f_s_) * L_oren_ * cos_ni);
  L += rho_n_ * INV_PI * L_sky;
  L *= f_e_;
  L *= fresnel_weight;
  L *= T_ext_;
  return L;
}

// Kajs eq. 4.36
vec3 L_far(vec3 L_brdf_, vec3 L_f_, vec3 L_t_, float rho_n_intensity_) {
  return (L_brdf_ + L_f_ + L_t_) * rho_n_intensity_;
}

#endif  // GLINTLAB_SAND_OREN_NAYAR_GLSL

// Glints: Gaussian gate per grain, mirror term of the micro normal and the
// roughness strength G(R_s) (Kajs 2022 sec. 4.2.4, eq. 4.17-4.21).
#ifndef GLINTLAB_SAND_GLINTS_GLSL
#define GLINTLAB_SAND_GLINTS_GLSL

#include "common/math.glsl"
#include "sand/sand_params.glsl"

// Kajs eq. 4.17 with mu = 0: exp(-x^2 / (2 sigma^2)), formed as
// exp(-r^2/2) with r = |x| / sigma (no pow of a negative base; r is cut at
// 40, where the value is below fp32's smallest normal, so sigma -> 0 gives 0
// instead of 0/0 or inf).
float GDF(float x, float sigma) {
  float r = abs(x) / max(sigma, 1e-30);
  return r < 40.0 ? exp(-0.5 * r * r) : 0.0;
}

// Kajs eq. 4.18: g = GDF(xi) max(0, w_o . r_m) max(0, n.w_i), r_m the mirror
// of the light direction about the micro normal m. Eq. 4.18 prints
// w_i - 2 m (m.w_i), which is -r_m (negative at a glint); Appendix A uses
// reflect(-w_i, m) = 2 m (m.w_i) - w_i under max(0, .), as here.
float g_glint(float gdf, vec3 wo, vec3 wi, vec3 m, float cos_ni) {
  vec3 r_m = 2.0 * dot(m, wi) * m - wi;
  return gdf * max(0.0, dot(wo, r_m)) * cos_ni;
}

// Kajs eq. 4.21 (the exponent is bounded for R_s in [0, 1]).
float G_strength(float R_s) { return clamp(1.0 / (1.0 + exp(13.5 * (R_s - 0.4))), 0.0, 1.0); }

// Kajs eq. 4.19-4.20: L_g = L_i g I_glints (sun only); Appendix A
// (SAND_COMPAT_GLINT_SKY) lights glints by (L_sky + L_i).
vec3 L_g(float g, vec3 L_i, vec3 L_sky, vec3 I_glints, uint appendix_compat) {
  vec3 L = (appendix_compat & SAND_COMPAT_GLINT_SKY) != 0u ? L_sky + L_i : L_i;
  return L * g * I_glints;
}

#endif  // GLINTLAB_SAND_GLINTS_GLSL

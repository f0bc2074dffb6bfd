// Macro-scale Fresnel reflectance with the roughness strength F(R_s)
// (Kajs 2022 sec. 4.2.4, eq. 4.14-4.16, 4.22).
#ifndef GLINTLAB_SAND_FRESNEL_GLSL
#define GLINTLAB_SAND_FRESNEL_GLSL

#include "common/math.glsl"
#include "sand/sand_params.glsl"

// Kajs eq. 4.15 with n_1 = 1 (air), n_2 = ior.
float fresnel_f0(float ior) {
  float r = (1.0 - ior) / (1.0 + ior);
  return r * r;
}

// Kajs eq. 4.14 (Schlick 1994) for a given cos = w_h . w_o in [0, 1].
float schlick(float f0, float cos_ho) {
  float m = 1.0 - clamp(cos_ho, 0.0, 1.0);
  float m2 = m * m;
  return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// The cosine of eq. 4.14. SAND_FRESNEL_MACRO_NORMAL: w_h is the halfway
// vector of w_i and its mirror direction about n, i.e. n (chapter 4 text,
// and what Appendix A computes as normalize(l + reflect(-l, n)) for
// n.w_i > 0); SAND_FRESNEL_LIGHT_VIEW: w_h = normalize(w_i + w_o).
// Back-facing (w_h.w_o < 0) gives 0 (f = 1), or |w_h.w_o| with
// SAND_COMPAT_FRESNEL_ABS as in Appendix A.
float fresnel_cos(vec3 n, vec3 wi, vec3 wo, uint mode, uint appendix_compat) {
  vec3 h = mode == SAND_FRESNEL_LIGHT_VIEW ? safe_normalize(wi + wo, n) : n;
  float c = dot(h, wo);
  return (appendix_compat & SAND_COMPAT_FRESNEL_ABS) != 0u ? min(abs(c), 1.0) : clamp(c, 0.0, 1.0);
}

// Kajs eq. 4.22 (min(1, .) and >= 0 on [0, 1]; saturate as Appendix A).
float F_strength(float R_s) {
  float r = R_s;
  float poly = ((((-20.80 * r + 60.0) * r - 55.90) * r + 14.55) * r + 2.0) * r + 0.25;
  return clamp(poly, 0.0, 1.0);
}

// Kajs eq. 4.16: L_f = f (L_sky^Omega + L_i max(0, n.w_i)).
vec3 L_f(float f, vec3 L_sky, vec3 L_i, float cos_ni) { return f * (L_sky + L_i * cos_ni); }

#endif  // GLINTLAB_SAND_FRESNEL_GLSL

// The anisotropic Beckmann distribution and its Smith masking-shadowing: the
// one implementation in the shader tree (Zirr & Kaplanyan 2016 sec. 3 use
// Beckmann throughout because two Beckmann lobes convolve to a Beckmann lobe,
// eq. 3-4). Directions are in the local frame (x = tangent u, y = bitangent v,
// z = macro normal); alpha = (alpha_u, alpha_v).
#ifndef GLINTLAB_COMMON_BECKMANN_GLSL
#define GLINTLAB_COMMON_BECKMANN_GLSL

#include "common/math.glsl"

// Slope-domain ("parallel plane", Zirr & Kaplanyan 2016 Fig. 2) density of
// slopes x = m.xy / m.z: a bivariate Gaussian with sigma = alpha / sqrt(2)
// per axis (sec. 3, "alpha = sqrt(2) sigma"):
//   P22(x) = exp(-(x_u^2 / alpha_u^2 + x_v^2 / alpha_v^2)) / (pi alpha_u alpha_v).
// The exponent is cut at 88 (e^-88 is below fp32's smallest normal), so no
// exp argument underflows into denormals or overflows for any slope.
float beckmann_p22(vec2 slope, vec2 alpha) {
  vec2 r = slope / alpha;
  float q = dot(r, r);
  return q < 88.0 ? exp(-q) * INV_PI / (alpha.x * alpha.y) : 0.0;
}

// The NDF of a unit direction h (eq. 2) for a lobe whose slopes are centred
// at `center` (0: the usual Beckmann NDF; a microdetail's slope m: the
// D_l(h - m) of eq. 7):
//   D(h) = P22(h.xy / h.z - center) / h.z^4
// (|dm/dx| = |m.n|^4, the Jacobian after eq. 5); 0 for h.z <= 0. The
// exponent |h.xy/h.z - center|^2 / alpha^2 is formed as
// |(h.xy - center h.z) / alpha|^2 / h.z^2 and compared with 88 before any
// division by h.z, so grazing h gives 0, not inf * 0. alpha > 0.
float beckmann_D(vec3 h, vec2 center, vec2 alpha) {
  if (!(h.z > 0.0)) return 0.0;
  vec2 r = (h.xy - center * h.z) / alpha;
  float z2 = h.z * h.z;
  float q = dot(r, r);
  if (!(q < 88.0 * z2)) return 0.0;
  return exp(-q / z2) * INV_PI / (alpha.x * alpha.y * z2 * z2);
}

// erfc(x) for x >= 0 (Press et al., Numerical Recipes, "erfcc": Chebyshev
// fit, fractional error < 1.2e-7 everywhere).
float erfc_nonneg(float x) {
  float t = 1.0 / (1.0 + 0.5 * x);
  float y = -x * x - 1.26551223 +
            t * (1.00002368 +
                 t * (0.37409196 +
                      t * (0.09678418 +
                           t * (-0.18628806 +
                                t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277))))))));
  return t * exp(y);
}

// Smith's Lambda for the Beckmann distribution (Walter et al. 2007 eq. 25,
// Heitz 2014 eq. 86 with the anisotropic alpha of the direction's azimuth):
//   a = w.z / sqrt(w.x^2 alpha_u^2 + w.y^2 alpha_v^2),
//   Lambda = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))
//          = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2,
// here multiplied by w.z: with den = w.z / a,
//   w.z Lambda = (den exp(-a^2) / sqrt(pi) - w.z erfc(a)) / 2,
// which stays finite as w.z -> 0 (-> den / (2 sqrt(pi))), where Lambda -> inf.
// w.z > 0 (callers check); a >= 9 gives 0 (Lambda < 1e-37).
float beckmann_z_lambda(vec3 w, vec2 alpha) {
  vec2 s = w.xy * alpha;
  float den = sqrt(dot(s, s));
  if (!(den > 0.0)) return 0.0;  // w along the normal
  float a = w.z / den;
  if (a >= 9.0) return 0.0;
  const float INV_SQRT_PI = 0.56418958354775628695;
  return max(0.5 * (den * exp(-a * a) * INV_SQRT_PI - w.z * erfc_nonneg(a)), 0.0);
}

// Lambda itself (w.z > 0), capped at 1e20 where w.z is so small that it
// would overflow.
float beckmann_lambda(vec3 w, vec2 alpha) { return min(beckmann_z_lambda(w, alpha) / w.z, 1e20); }

// Height-correlated Smith masking-shadowing (Heitz 2014 eq. 99), divided by
// cos_o = wo.z, the form the microfacet BRDF needs (f cos_i = F D G2 / (4 cos_o)):
//   G2 / cos_o = 1 / (wo.z (1 + Lambda(wi)) + wo.z Lambda(wo)),
// bounded by 2 sqrt(pi) / alpha at grazing wo instead of 0 / 0. 0 unless both
// directions and the microfacet h lie on the front side (the Heaviside
// factors of eq. 99).
float smith_G2_over_cos_o(vec3 wi, vec3 wo, vec3 h, vec2 alpha) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0) || !(dot(h, wi) > 0.0) || !(dot(h, wo) > 0.0)) return 0.0;
  return 1.0 / (wo.z * (1.0 + beckmann_lambda(wi, alpha)) + beckmann_z_lambda(wo, alpha));
}

// G2 itself (Heitz 2014 eq. 99), in [0, 1].
float smith_G2(vec3 wi, vec3 wo, vec3 h, vec2 alpha) {
  return min(wo.z * smith_G2_over_cos_o(wi, wo, h, alpha), 1.0);
}

// A slope drawn from P22 (Box-Muller: sigma = alpha / sqrt(2) per axis, so
// x = alpha sqrt(-ln u1) (cos 2 pi u2, sin 2 pi u2)); u1 in (0, 1], u2 in [0, 1).
vec2 beckmann_sample_slope(float u1, float u2, vec2 alpha) {
  float r = sqrt(max(-log(u1), 0.0));
  float phi = TWO_PI * u2;
  return alpha * r * vec2(cos(phi), sin(phi));
}

#endif  // GLINTLAB_COMMON_BECKMANN_GLSL

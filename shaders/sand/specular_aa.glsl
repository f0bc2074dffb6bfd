// Geometric specular anti-aliasing, the material option "specular_aa" (core/material/sand_material.h,
// SandSpecularAA): the Beckmann roughness alpha_g of a glint_D model widened by how far the surface's
// normal turns within the pixel, so that a lobe narrower than the pixel's spread of normals is not
// point-sampled. SAND_SPECULAR_AA picks the method (sand.frag includes this file only when it is set):
//
//   1  kaplanyan2016  Kaplanyan, Hill, Patney, Lefohn 2016, "Filtering distributions of normals for
//      shading antialiasing" (HPG). The half vector in the slope (parallel-plane) domain of the
//      tangent frame, p = (h.t, h.b) / h.n; the pixel's footprint there is the bounding rectangle of
//      its screen derivatives, b = |dp/dx| + |dp/dy| per axis. A box of half extent r = b / 2 is
//      replaced by a Gaussian of variance r^2 = sigma^2 b^2 (sigma^2 = 1/4), and Beckmann lobes
//      convolve by adding twice their slope variance to alpha^2:
//        alpha^2 += min(2 sigma^2 b^2, kappa),  kappa = 0.18 (= 2 * 0.3^2: r at most 0.3).
//   2  tokuyoshi2019  Tokuyoshi & Kaplanyan 2019, "Improved geometric specular antialiasing" (I3D),
//      the isotropic kernel from the derivatives of the unit normal, in both axes:
//        alpha^2 += min(2 sigma^2 (|dn/dx|^2 + |dn/dy|^2), kappa),  sigma^2 = 0.25, kappa = 0.18.
//   3  tokuyoshi2021  Tokuyoshi & Kaplanyan 2021, "Stable geometric specular antialiasing with
//      projected-space NDF filtering" (JCGT 10(2)). The half vector in the projected space of the
//      tangent frame, q = (h.t, h.b) (not divided by h.n, whose derivatives blow up at grazing
//      angles); the kernel's covariance 2 Sigma = 2 sigma^2 (dq/dx dq/dx^T + dq/dy dq/dy^T) (eq. 3),
//      sigma^2 = 1 / (2 pi); the lobe's projected-space roughness alpha_p^2 = alpha^2 / (1 - alpha^2)
//      (eq. 4) is widened there, A_p = diag(alpha_p^2) + 2 Sigma (eq. 6), and mapped back,
//      A = A_p (I + A_p)^-1 (eq. 7). glintlab's lobes are axis-aligned in (t, b), so the diagonal of
//      2 Sigma is kept (the paper's axis-aligned form) and clamped to kappa = 0.18:
//        a_p = alpha^2 / (1 - alpha^2) + min(2 sigma^2 (dq_i/dx^2 + dq_i/dy^2), kappa),
//        alpha^2 = a_p / (1 + a_p).
//
// alpha_g is widened; alpha_l, one microdetail's lobe, is kept (the methods filter the distribution
// of normals over the pixel, which for a glint_D model is D_g and the spread of microdetail normals
// alpha_m, not a microdetail): the relative roughness alpha_l / alpha_g becomes
// alpha_l / alpha_g'. alpha^2 stays <= 1 (every method saturates it). Where the macro normal does not
// turn within the pixel (dn/dx = dn/dy = 0: a plane) nothing changes, not even by rounding: the
// half-vector methods would widen by the turn of the view across the pixel alone, which is not the
// geometric aliasing they are for (a pixel subtends a few milliradians), and a plane stays
// bit-identical to "none".
#ifndef GLINTLAB_SAND_SPECULAR_AA_GLSL
#define GLINTLAB_SAND_SPECULAR_AA_GLSL

#define SPECULAR_AA_KAPLANYAN2016 1
#define SPECULAR_AA_TOKUYOSHI2019 2
#define SPECULAR_AA_TOKUYOSHI2021 3

// The screen derivatives a method reads (each times the sample's share of the pixel, as the surface
// pass scales its uv footprint): of the unit macro normal n (world), and of the half vector's
// tangent-frame coordinates in the method's domain (p for kaplanyan2016, q for tokuyoshi2021).
struct SpecularAAInput {
  vec3 dn_dx, dn_dy;
  vec2 dh_dx, dh_dy;
};

// The kernel's alpha^2 per axis (t, b), clamped to kappa; NaN (a derivative that is not finite) counts
// as the widest, kappa.
vec2 specular_aa_kernel(SpecularAAInput d, float sigma2, float kappa) {
#if SAND_SPECULAR_AA == SPECULAR_AA_KAPLANYAN2016
  vec2 b = abs(d.dh_dx) + abs(d.dh_dy);
  vec2 k = 2.0 * sigma2 * b * b;
#elif SAND_SPECULAR_AA == SPECULAR_AA_TOKUYOSHI2019
  vec2 k = vec2(2.0 * sigma2 * (dot(d.dn_dx, d.dn_dx) + dot(d.dn_dy, d.dn_dy)));
#else
  vec2 k = 2.0 * sigma2 * (d.dh_dx * d.dh_dx + d.dh_dy * d.dh_dy);
#endif
  return min(mix(k, vec2(kappa), isnan(k)), vec2(kappa));
}

// The material's glint_alpha (xy = alpha_g (t, b), zw = alpha_l / alpha_g) with alpha_g widened and
// alpha_l kept; unchanged where the normal does not turn.
vec4 specular_aa_glint_alpha(vec4 glint_alpha, SpecularAAInput d, float sigma2, float kappa) {
  if (all(equal(d.dn_dx, vec3(0.0))) && all(equal(d.dn_dy, vec3(0.0)))) return glint_alpha;
  vec2 a = glint_alpha.xy, k = specular_aa_kernel(d, sigma2, kappa);
#if SAND_SPECULAR_AA == SPECULAR_AA_TOKUYOSHI2021
  vec2 a2 = a * a;
  vec2 ap = a2 / max(1.0 - a2, 1e-6) + k;  // eq. 4, eq. 6 (diagonal); alpha = 1 stays 1 below
  vec2 wide = sqrt(ap / (1.0 + ap));       // eq. 7
#else
  vec2 wide = sqrt(min(a * a + k, vec2(1.0)));
#endif
  wide = max(wide, a);  // rounding never narrows
  return vec4(wide, glint_alpha.zw * (a / wide));
}

#endif  // GLINTLAB_SAND_SPECULAR_AA_GLSL

// The microfacet BRDF that turns the NDF of every glint_D model
// (glint/query.glsl) into radiance: Zirr & Kaplanyan 2016 eq. 1,
// Cook-Torrance with a Beckmann masking term and Fresnel (sec. 3 "we are
// using the Eq. 1 with appropriate Fresnel term and a Beckmann
// shadowing-masking term").
#ifndef GLINTLAB_SAND_GLINT_RADIANCE_GLSL
#define GLINTLAB_SAND_GLINT_RADIANCE_GLSL

#include "common/math.glsl"
#include "common/beckmann.glsl"
#include "sand/fresnel.glsl"
#include "sand/glint_roughness.glsl"

// w_i, w_o and the half vector in the local frame (x = t along u, y = b along
// v, z = n). valid: both directions above the surface and w_i + w_o != 0.
struct GlintFrame { vec3 wi; vec3 wo; vec3 h; bool valid; };

GlintFrame glint_frame(vec3 t, vec3 b, vec3 n, vec3 wi, vec3 wo) {
  GlintFrame f;
  f.wi = vec3(dot(t, wi), dot(b, wi), dot(n, wi));
  f.wo = vec3(dot(t, wo), dot(b, wo), dot(n, wo));
  f.h = safe_normalize(f.wi + f.wo, vec3(0.0));
  f.valid = f.wi.z > 0.0 && f.wo.z > 0.0 && f.h.z > 0.0;
  return f;
}

// Radiance of a microfacet BRDF under the sun, L = f L_i cos_i with
// f = F D G2 / (4 cos_i cos_o) (eq. 1), i.e. L = L_i F D G2 / (4 cos_o):
// D is the (estimated) NDF value at h per colour channel, F Schlick with the
// sand's ior (Kajs eq. 4.14-4.15, the one Schlick of sand/fresnel.glsl) at
// h.w_o, G2 height-correlated Smith with the surface roughness alpha_g.
// L_i is the sun's normal irradiance (DIFFERENCES.md "Units"): the sun is a
// directional light; its solid angle enters only as the light cone
// (sand/glint_roughness.glsl).
vec3 glint_radiance(vec3 D, GlintFrame f, GlintRoughness r, float ior, vec3 L_i, float intensity) {
  if (!f.valid) return vec3(0.0);
  float F = schlick(fresnel_f0(ior), dot(f.h, f.wo));
  float G_cos = smith_G2_over_cos_o(f.wi, f.wo, f.h, r.alpha_surface);
  return L_i * (intensity * F * 0.25 * G_cos) * D;
}

#endif  // GLINTLAB_SAND_GLINT_RADIANCE_GLSL

// The anisotropic GGX (Trowbridge-Reitz) NDF, the smooth limit of glint
// models that target GGX (a glint model's declaration "limit=ggx"). Local
// frame as common/beckmann.glsl; alpha = (alpha_u, alpha_v) > 0.
#ifndef GLINTLAB_COMMON_GGX_GLSL
#define GLINTLAB_COMMON_GGX_GLSL

#include "common/math.glsl"

// D(h) = 1 / (pi alpha_u alpha_v ((h.x / alpha_u)^2 + (h.y / alpha_v)^2 + h.z^2)^2),
// normalised as beckmann_D (the integral of D(h) h.z over the hemisphere is 1);
// 0 for h.z <= 0. The bracket is at least h.z^2 > 0 and at most 2e6 for a unit
// h and alpha >= 1e-3, so its square neither overflows nor vanishes.
float ggx_D(vec3 h, vec2 alpha) {
  if (!(h.z > 0.0)) return 0.0;
  vec2 r = h.xy / alpha;
  float t = dot(r, r) + h.z * h.z;
  return INV_PI / (alpha.x * alpha.y * t * t);
}

#endif  // GLINTLAB_COMMON_GGX_GLSL

// Diffuse reflectance with the subsurface-scattering approximation
// (Kajs 2022 sec. 4.2.3, eq. 4.10-4.13).
#ifndef GLINTLAB_SAND_DIFFUSE_GLSL
#define GLINTLAB_SAND_DIFFUSE_GLSL

#include "common/math.glsl"

// Kajs eq. 4.12
float f_s(float scattering, float SSS) { return scattering * SSS; }

// Kajs eq. 4.13
float f_e(float absorption, float SSS) { return exp(-absorption * SSS); }

// Kajs eq. 4.11 (eq. 4.10 for f_s = 0, f_e = 1). cos_ni = max(0, n . w_i).
vec3 L_d(vec3 rho, float f_s_, float f_e_, vec3 L_i, vec3 L_sky, float cos_ni) {
  vec3 L = rho * INV_PI * L_i * (f_s_ + (1.0 - f_s_) * cos_ni);
  L += rho * INV_PI * L_sky;
  return f_e_ * L;
}

#endif  // GLINTLAB_SAND_DIFFUSE_GLSL

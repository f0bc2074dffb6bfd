// Grain colour rho_m from the 8-colour palette and macro colour rho_n
// (Kajs 2022 sec. 4.2.2).
#ifndef GLINTLAB_SAND_GRAIN_COLOR_GLSL
#define GLINTLAB_SAND_GRAIN_COLOR_GLSL

#include "sand/sand_params.glsl"

// Kajs eq. 4.3-4.4: index = 4 xi_1^binary + 2 xi_2^binary + xi_3^binary, xi in [0, 1].
uint palette_index(vec3 xi) {
  uvec3 b = uvec3(greaterThanEqual(xi, vec3(0.5)));  // eq. 4.3
  return 4u * b.x + 2u * b.y + b.z;
}

// Kajs eq. 4.4
vec3 rho_m(SandParams p, uint index) { return p.palette[index].rgb; }

// Kajs eq. 4.8
vec3 rho_n(SandParams p) {
  vec3 s = vec3(0.0);
  for (int i = 0; i < 8; ++i) s += p.palette[i].rgb;
  return s * 0.125;
}

#endif  // GLINTLAB_SAND_GRAIN_COLOR_GLSL

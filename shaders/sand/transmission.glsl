// Transmission through the grain aggregate (Kajs 2022 sec. 4.2.5, eq. 4.25-4.32).
#ifndef GLINTLAB_SAND_TRANSMISSION_GLSL
#define GLINTLAB_SAND_TRANSMISSION_GLSL

#include "common/math.glsl"

// Kajs eq. 4.25 (saturated as Appendix A; on [0, 1] it lies in [0.1, 1]).
float T_ext(float T) {
  float poly = (((-3.2 * T + 4.8) * T - 2.2) * T - 0.3) * T + 1.0;
  return clamp(poly, 0.0, 1.0);
}

// Kajs eq. 4.29
float R_t_star(float R_t) { return 0.2 + R_t * (0.4 - 0.2); }

// Kajs eq. 4.30
float R_t_strength(float R_t) { return 1.0 - 0.9 * R_t; }

// Kajs eq. 4.31: t = R_t^strength T (1 - max(0, n.w_o))^(1/R_t*) max(0, -w_o.w_i).
float transmission_t(float T, float R_t, vec3 n, vec3 wo, vec3 wi) {
  float base = 1.0 - clamp(dot(n, wo), 0.0, 1.0);
  float t = R_t_strength(R_t) * T * safe_pow(base, 1.0 / R_t_star(R_t)) * max(0.0, -dot(wo, wi));
  return clamp(t, 0.0, 1.0);
}

// Kajs eq. 4.32
vec3 L_t(vec3 rho_n_, vec3 L_i, float t) { return rho_n_ * L_i * t; }

#endif  // GLINTLAB_SAND_TRANSMISSION_GLSL

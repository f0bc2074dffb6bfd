// Distance-based transition from micro (close) to macro (far) shading
// (Kajs 2022 sec. 4.3, eq. 4.33, 4.37-4.38).
#ifndef GLINTLAB_SAND_TRANSITION_GLSL
#define GLINTLAB_SAND_TRANSITION_GLSL

#include "common/math.glsl"

// Kajs eq. 4.37: 1 / (1 + e^{-a (x - b)}), in the overflow-free form.
float sig(float x, float a, float b) { return stable_logistic(a * (x - b)); }

// Kajs eq. 4.33: L_close = (L_d + L_s + L_t) rho_m^intensity.
vec3 L_close(vec3 L_d_, vec3 L_s_, vec3 L_t_, float rho_m_intensity_) {
  return (L_d_ + L_s_ + L_t_) * rho_m_intensity_;
}

// Kajs eq. 4.38
vec3 L_final(vec3 L_close_, vec3 L_far_, float sig_) { return (1.0 - sig_) * L_close_ + sig_ * L_far_; }

#endif  // GLINTLAB_SAND_TRANSITION_GLSL

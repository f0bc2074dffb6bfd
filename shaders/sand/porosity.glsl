// Porosity as a per-grain intensity (Kajs 2022 sec. 4.2.2, eq. 4.5-4.9).
#ifndef GLINTLAB_SAND_POROSITY_GLSL
#define GLINTLAB_SAND_POROSITY_GLSL

// Kajs eq. 4.6: I_min = exp(-P / dist). dist -> 0 gives 0 (P > 0) or 1
// (P = 0) without forming 0/0; exp of a large negative only underflows.
float I_min(float P, float dist) {
  float d = max(dist, 1e-30);
  return clamp(exp(-(P / d)), 0.0, 1.0);
}

// Kajs eq. 4.7: I_min + (1 - (xi (1 - I_min) + I_min)) = 1 - xi (1 - I_min),
// uniform in [I_min, 1] for xi uniform in [0, 1].
float rho_m_intensity(float I_min_, float xi) { return 1.0 - xi * (1.0 - I_min_); }

// Kajs eq. 4.9: mean of eq. 4.7 over xi.
float rho_n_intensity(float I_min_) { return I_min_ + (1.0 - I_min_) * 0.5; }

#endif  // GLINTLAB_SAND_POROSITY_GLSL

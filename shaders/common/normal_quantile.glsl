// Inverse of the standard normal CDF, Phi^-1(u) = sqrt(2) erfinv(2u - 1), by
// Giles' single-precision erfinv ("Approximating the erfinv function", GPU
// Computing Gems Jade, 2011): polynomials in w = -ln(1 - x^2) without
// cancellation, relative error < 1e-7 before fp32 rounding. Monotone in u,
// so a Gaussian drawn by inversion changes continuously with its parameters
// for a fixed seed.
#ifndef GLINTLAB_COMMON_NORMAL_QUANTILE_GLSL
#define GLINTLAB_COMMON_NORMAL_QUANTILE_GLSL

// u in (0, 1), clamped to [2^-25, 1 - 2^-25] (|z| <= 5.46), so 0 and 1 give
// finite values. w = -ln(4 u (1 - u)) equals -ln(1 - x^2) for x = 2u - 1
// without forming 1 - x^2; callers pass (k + 0.5) 2^-24 for a 24-bit k, for
// which 1 - u and 2u - 1 are exact.
float normal_quantile(float u) {
  u = clamp(u, 2.98023224e-8, 1.0 - 2.98023224e-8);
  float x = 2.0 * u - 1.0;
  float w = -log(4.0 * u * (1.0 - u));
  float p;
  if (w < 5.0) {
    w -= 2.5;
    p = 2.81022636e-08;
    p = 3.43273939e-07 + p * w;
    p = -3.5233877e-06 + p * w;
    p = -4.39150654e-06 + p * w;
    p = 0.00021858087 + p * w;
    p = -0.00125372503 + p * w;
    p = -0.00417768164 + p * w;
    p = 0.246640727 + p * w;
    p = 1.50140941 + p * w;
  } else {
    w = sqrt(w) - 3.0;
    p = -0.000200214257;
    p = 0.000100950558 + p * w;
    p = 0.00134934322 + p * w;
    p = -0.00367342844 + p * w;
    p = 0.00573950773 + p * w;
    p = -0.0076224613 + p * w;
    p = 0.00943887047 + p * w;
    p = 1.00167406 + p * w;
    p = 2.83297682 + p * w;
  }
  return 1.41421356237 * p * x;
}

#endif  // GLINTLAB_COMMON_NORMAL_QUANTILE_GLSL

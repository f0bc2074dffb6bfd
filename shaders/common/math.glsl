// Shared scalar/vector helpers and constants. Numerically safe forms only:
// no normalize of zero vectors, no pow of negatives, no exp overflow.
#ifndef GLINTLAB_COMMON_MATH_GLSL
#define GLINTLAB_COMMON_MATH_GLSL

const float PI = 3.14159265358979323846;
const float TWO_PI = 6.28318530717958647692;
const float INV_PI = 0.31830988618379067154;

float saturate(float x) { return clamp(x, 0.0, 1.0); }
vec2 saturate(vec2 x) { return clamp(x, vec2(0.0), vec2(1.0)); }
vec3 saturate(vec3 x) { return clamp(x, vec3(0.0), vec3(1.0)); }

float max3(vec3 v) { return max(v.x, max(v.y, v.z)); }

// Unit vector along v, or `fallback` when v is zero, denormal or not finite.
// Scales by the largest component first so huge vectors do not overflow dot().
vec3 safe_normalize(vec3 v, vec3 fallback) {
  float s = max3(abs(v));
  if (!(s > 1e-30) || isinf(s)) return fallback;
  vec3 u = v / s;
  return u * inversesqrt(dot(u, u));
}
vec3 safe_normalize(vec3 v) { return safe_normalize(v, vec3(0.0, 0.0, 1.0)); }

// x^y for y > 0, defined as 0 for x <= 0 (GLSL pow is undefined for x < 0).
float safe_pow(float x, float y) { return x > 0.0 ? exp2(y * log2(x)) : 0.0; }

// Logistic 1/(1+e^-z) without overflow: only e^{-|z|} <= 1 is ever formed.
float stable_logistic(float z) {
  float e = exp(-abs(z));
  return z >= 0.0 ? 1.0 / (1.0 + e) : e / (1.0 + e);
}

#endif  // GLINTLAB_COMMON_MATH_GLSL

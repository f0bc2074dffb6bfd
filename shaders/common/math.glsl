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
// NaN is tested per component: max() of a NaN and a number may return the
// number, so the largest component alone would let (NaN, 1, 0) through.
vec3 safe_normalize(vec3 v, vec3 fallback) {
  float s = max3(abs(v));
  if (!(s > 1e-30) || isinf(s) || any(isnan(v))) return fallback;
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

// log(1 + x) for x > -1, accurate where 1 + x rounds (x = -1e-12 gives -1e-12,
// where log(1.0 + x) gives 0). |x| <= 0.5: 2 atanh(t), t = x / (2 + x), by its
// odd series (|t| <= 1/3, 8 terms: truncation < 2e-9 relative); otherwise log.
// Finite for every input.
float safe_log1p(float x) {
  if (!(x > -1.0)) return -3.4e38;  // log(0) and below: a finite -huge, never NaN
  if (abs(x) > 0.5) return log(1.0 + min(x, 3.4e38));  // +inf: log(3.4e38), finite
  float t = x / (2.0 + x);
  float t2 = t * t;
  float s = 1.0 / 15.0;
  s = s * t2 + 1.0 / 13.0;
  s = s * t2 + 1.0 / 11.0;
  s = s * t2 + 1.0 / 9.0;
  s = s * t2 + 1.0 / 7.0;
  s = s * t2 + 1.0 / 5.0;
  s = s * t2 + 1.0 / 3.0;
  s = s * t2 + 1.0;
  return 2.0 * t * s;
}

// a b + c rounded once (up to the rounding of the small part): a b is split
// exactly into prod + err (Dekker's product with Veltkamp's splitting, which
// needs no fma; `precise` forbids the compiler to fuse or reassociate it),
// then prod + (err + c). GLSL's fma() may be evaluated as a b + c in two
// roundings, which beyond 2^24 moves the result by up to half an fp32 step.
// |a|, |b| < 8e34 (the split multiplies by 4097).
float mul_add_once(float a, float b, float c) {
  precise float prod = a * b;
  precise float ca = 4097.0 * a;
  precise float a_hi = ca - (ca - a);
  precise float a_lo = a - a_hi;
  precise float cb = 4097.0 * b;
  precise float b_hi = cb - (cb - b);
  precise float b_lo = b - b_hi;
  precise float err = ((a_hi * b_hi - prod) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
  precise float r = prod + (err + c);
  return r;
}

#endif  // GLINTLAB_COMMON_MATH_GLSL

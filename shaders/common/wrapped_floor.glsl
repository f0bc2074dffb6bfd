// Integer cell coordinates without float -> int conversion of out-of-range
// values (undefined in GLSL): floor(x) modulo 2^32 as a uint, exact for every
// finite fp32 x. Cell indices that wrap keep integer arithmetic consistent
// (2 floor(x) = floor(2x) or floor(2x) - 1 modulo 2^32), which the coherent
// multilevel hashing of Zirr & Kaplanyan 2016 sec. 4.1 relies on; the
// Kajs grains use the bit pattern of floor() instead (sand/micro_normals.glsl).
#ifndef GLINTLAB_COMMON_WRAPPED_FLOOR_GLSL
#define GLINTLAB_COMMON_WRAPPED_FLOOR_GLSL

// |floor(x)| < 2^31: int() is exact and defined. Otherwise floor(x) = m 2^e
// with the 24-bit significand m and e >= 8, so its value modulo 2^32 is
// (m << e) for e < 32 and 0 beyond, negated in two's complement for x < 0.
// +-inf and NaN give fixed keys (0x7F800000, 0xFF800000, 0x7FC00000).
uint wrapped_floor(float x) {
  if (isnan(x)) return 0x7FC00000u;
  if (isinf(x)) return x > 0.0 ? 0x7F800000u : 0xFF800000u;
  float c = floor(x);
  if (abs(c) < 2147483648.0) return uint(int(c));
  uint bits = floatBitsToUint(c);
  uint e = ((bits >> 23u) & 0xFFu) - 150u;  // >= 8 here
  uint mag = e >= 32u ? 0u : ((bits & 0x7FFFFFu) | 0x800000u) << e;
  return (bits >> 31u) != 0u ? 0u - mag : mag;
}
uvec2 wrapped_floor(vec2 x) { return uvec2(wrapped_floor(x.x), wrapped_floor(x.y)); }

#endif  // GLINTLAB_COMMON_WRAPPED_FLOOR_GLSL

#version 450
// GPU harness for the scalar helpers of the glint models (tests/core/material/
// glint_models.cpp): wrapped_floor, safe_log1p, normal_quantile, the binomial
// draw and the coherent seeds. Input record (GLINT_MATH_IN floats):
//   0 x, 1 u, 2-5 binomial n, p, u, u_round, 6-9 cell (u >> 16, u & 0xFFFF,
//   v >> 16, v & 0xFFFF), 10 level.
// Output record (GLINT_MATH_OUT floats): 0-1 wrapped_floor(x) as (hi16, lo16),
// 2 safe_log1p(x), 3 normal_quantile(u), 4 binomial_draw, 5-8 the coherent
// seed as (u hi16, u lo16, v hi16, v lo16). uints travel as 16-bit halves
// (exact in fp32).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "common/math.glsl"
#include "common/wrapped_floor.glsl"
#include "common/normal_quantile.glsl"
#include "common/binomial.glsl"
#include "sand/glint_footprint.glsl"

#define GLINT_MATH_IN 12u
#define GLINT_MATH_OUT 12u

void put_uint(uint o, uint v) { outputs[o] = float(v >> 16u); outputs[o + 1u] = float(v & 0xFFFFu); }
uint get_uint(uint i) { return (uint(inputs[i]) << 16u) | uint(inputs[i + 1u]); }

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * GLINT_MATH_IN, o = id * GLINT_MATH_OUT;
  float x = inputs[i];
  put_uint(o + 0u, wrapped_floor(x));
  outputs[o + 2u] = safe_log1p(x);
  outputs[o + 3u] = normal_quantile(inputs[i + 1u]);
  outputs[o + 4u] = binomial_draw(inputs[i + 2u], inputs[i + 3u], inputs[i + 4u], inputs[i + 5u]);
  uvec2 seed = glint_coherent_seed(uvec2(get_uint(i + 6u), get_uint(i + 8u)), int(inputs[i + 10u]));
  put_uint(o + 5u, seed.x);
  put_uint(o + 7u, seed.y);
  for (uint k = 9u; k < GLINT_MATH_OUT; ++k) outputs[o + k] = 0.0;
}

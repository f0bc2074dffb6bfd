#version 450
// GPU harness of the kemppinen glint model's parts (tests/core/material/
// glint_kemppinen.cpp): the disk map, the compensation term of one LOD and
// the mean of the LOD roulette, evaluated by the model's own functions.
// Input record (KEMPPINEN_IN floats):
//   MODE 0 (disk): 0-2 h, 3-4 alpha, 5-6 relative roughness.
//     Output: 0-1 x (unit square), 2 ndf (= d / pi; beckmann_D with KEMPPINEN_BECKMANN), 3-4 sigma (square units).
//   MODE 1 (compensation): 0 LOD, 1-2 uv, 3-4 duv_dx, 5-6 duv_dy, 7 sqrt(N),
//     8 filter, 9-10 disk position x, 11-12 sigma (square units).
//     Output: 0 C, 1 M_A(square), 2 M_A(block), 3 M_S(block), 4-5 fs, 6-7 fa,
//     8-9 ka, 10-12 spatial covariance (cells^2: xx, yy, xy).
//   MODE 2 (roulette): 0 w, 1 r. Output: 0 the mean over r of the roulette
//     weight at w, 1 the roulette weight at (r, w).
//   MODE 3 (LOD): 0-1 duv_dx, 2-3 duv_dy, 4 sqrt(N), 5 filter, 6 lod_offset.
//     Output: 0 lambda.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#define GLINT_MODEL_PARAMETERS float filter_width; float lod_offset;
#include "glint/models/kemppinen.glsl"

#ifndef MODE
#define MODE 0
#endif
#define KEMPPINEN_IN 16u
#define KEMPPINEN_OUT 16u

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * KEMPPINEN_IN, o = id * KEMPPINEN_OUT;
  for (uint k = 0u; k < KEMPPINEN_OUT; ++k) outputs[o + k] = 0.0;
#if MODE == 0
  KemppinenDisk d = kemppinen_disk(vec3(inputs[i], inputs[i + 1u], inputs[i + 2u]), vec2(inputs[i + 3u], inputs[i + 4u]),
                                   vec2(inputs[i + 5u], inputs[i + 6u]));
  outputs[o] = d.x.x;
  outputs[o + 1u] = d.x.y;
  outputs[o + 2u] = d.ndf;
  outputs[o + 3u] = d.sigma.x;
  outputs[o + 4u] = d.sigma.y;
#elif MODE == 1
  KemppinenDisk d;
  d.x = vec2(inputs[i + 9u], inputs[i + 10u]);
  d.ndf = 1.0;
  d.sigma = vec2(inputs[i + 11u], inputs[i + 12u]);
  KemppinenLevel v = kemppinen_level(inputs[i], vec2(inputs[i + 1u], inputs[i + 2u]), vec2(inputs[i + 3u], inputs[i + 4u]),
                                     vec2(inputs[i + 5u], inputs[i + 6u]), inputs[i + 7u], inputs[i + 8u], d);
  KemppinenCompensation c = kemppinen_compensation(v);
  outputs[o] = c.value;
  outputs[o + 1u] = c.square;
  outputs[o + 2u] = c.block_a;
  outputs[o + 3u] = c.block_s;
  outputs[o + 4u] = v.fs.x;
  outputs[o + 5u] = v.fs.y;
  outputs[o + 6u] = v.fa.x;
  outputs[o + 7u] = v.fa.y;
  outputs[o + 8u] = float(v.ka.x);
  outputs[o + 9u] = float(v.ka.y);
  outputs[o + 10u] = v.cov.x;
  outputs[o + 11u] = v.cov.y;
  outputs[o + 12u] = v.cov.z;
#elif MODE == 3
  outputs[o] = kemppinen_lod(vec2(inputs[i], inputs[i + 1u]), vec2(inputs[i + 2u], inputs[i + 3u]), inputs[i + 4u],
                             inputs[i + 5u], inputs[i + 6u] > 0.5);
#else
  outputs[o] = kemppinen_roulette_mean(inputs[i]);
  outputs[o + 1u] = kemppinen_roulette(inputs[i + 1u], inputs[i]);
#endif
}

#version 450
// Box filter of a supersampled surface pass (core/render/surface_pass.h,
// option `supersample`): each pixel of the output is the mean of its f x f
// block of the high-resolution accumulation (colour and coverage).
// With HALVES (option `halves`) it also writes the means of the block's two
// checkerboard halves: the cells with i + j even (half A, ceil(f^2 / 2) cells)
// and odd (half B, floor(f^2 / 2)); each covers the pixel evenly, and the
// block's mean is summed as without them, to the same bits.
#ifndef HALVES
#define HALVES 0
#endif
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D hi;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D dst;
#if HALVES
layout(set = 0, binding = 2, rgba32f) uniform writeonly image2D dst_a;
layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D dst_b;
#endif
layout(push_constant) uniform Push { ivec4 size_factor; };  // width, height, factor f

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size_factor.xy))) return;
  int f = size_factor.z;
  vec4 sum = vec4(0.0);
#if HALVES
  vec4 sum_a = vec4(0.0), sum_b = vec4(0.0);
#endif
  for (int j = 0; j < f; ++j)
    for (int i = 0; i < f; ++i) {
      vec4 c = texelFetch(hi, p * f + ivec2(i, j), 0);
      sum += c;
#if HALVES
      if (((i + j) & 1) == 0) sum_a += c;
      else sum_b += c;
#endif
    }
  imageStore(dst, p, sum / float(f * f));
#if HALVES
  imageStore(dst_a, p, sum_a / float((f * f + 1) / 2));
  imageStore(dst_b, p, sum_b / float((f * f) / 2));
#endif
}

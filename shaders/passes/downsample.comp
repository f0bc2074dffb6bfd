#version 450
// Box filter of a supersampled surface pass (core/render/surface_pass.h,
// option `supersample`): each pixel of the output is the mean of its f x f
// block of the high-resolution accumulation (colour and coverage).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D hi;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D dst;
layout(push_constant) uniform Push { ivec4 size_factor; };  // width, height, factor f

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size_factor.xy))) return;
  int f = size_factor.z;
  vec4 sum = vec4(0.0);
  for (int j = 0; j < f; ++j)
    for (int i = 0; i < f; ++i) sum += texelFetch(hi, p * f + ivec2(i, j), 0);
  imageStore(dst, p, sum / float(f * f));
}

#version 450
// Resolve of a surface pass's own colour image (core/render/surface_pass.h):
// for option `supersample` each pixel of the output is the mean of its f x f
// block of the high-resolution accumulation (colour and coverage); for a sum
// of opaque samples (f = 1) each sample is added to the output (w = 1) or,
// the first, written (w = 0).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D hi;
layout(set = 0, binding = 1, rgba32f) uniform image2D dst;
layout(push_constant) uniform Push { ivec4 size_factor; };  // width, height, factor f, add

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size_factor.xy))) return;
  int f = size_factor.z;
  vec4 sum = vec4(0.0);
  for (int j = 0; j < f; ++j)
    for (int i = 0; i < f; ++i) sum += texelFetch(hi, p * f + ivec2(i, j), 0);
  vec4 mean = sum / float(f * f);
  imageStore(dst, p, size_factor.w != 0 ? imageLoad(dst, p) + mean : mean);
}

#version 450
// Test pass of the frame graph (tests/core/render/frame_graph.cpp): acc =
// src + (history valid ? previous acc : 0), so after n frames without a reset
// acc = n * src.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 1) uniform sampler2D previous;
layout(set = 0, binding = 2, rgba32f) uniform writeonly image2D acc;
layout(push_constant) uniform Push { vec4 size_valid; };
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, ivec2(size_valid.xy)))) return;
  vec4 v = texelFetch(src, p, 0);
  if (size_valid.z > 0.5) v += texelFetch(previous, p, 0);
  imageStore(acc, p, v);
}

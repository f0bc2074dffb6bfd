#version 450
// Binomial draws for the distribution tests: input (n, p, u, u_round) per
// item, output the count (common/binomial.glsl).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "common/binomial.glsl"

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = 4u * id;
  outputs[id] = binomial_draw(inputs[i], inputs[i + 1u], inputs[i + 2u], inputs[i + 3u]);
}

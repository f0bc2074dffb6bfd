#version 450
// The pieces of the `deliot` glint model (glint/models/deliot.glsl) that its
// independent checks read (tests/core/material/glint_deliot.cpp):
//  - with DELIOT_TEST_NOISE=SIZE: input (x, y) texel index, output (u, g),
//    the uniform and normal at that texel of the SIZE x SIZE noise texture;
//  - otherwise: input (n, p, u, g), output (count, gate), one draw of the
//    distributed binomial law from the uniform u and the normal g, and its
//    gate (the count with the Gaussian part forced to 0: 1 for u < P1).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#define GLINT_MODEL_PARAMETERS float screen_space_scale; float density_randomization; float noise_size; float floor_levels;
#include "glint/models/deliot.glsl"

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
#ifdef DELIOT_TEST_NOISE
  vec2 v = deliot_noise(uvec2(inputs[2u * id], inputs[2u * id + 1u]), uint(DELIOT_TEST_NOISE));
  outputs[2u * id] = v.x;
  outputs[2u * id + 1u] = v.y;
#else
  uint i = 4u * id;
  DeliotBinomial b = deliot_binomial(inputs[i], inputs[i + 1u]);
  outputs[2u * id] = deliot_count(b, inputs[i + 2u], inputs[i + 3u]);
  outputs[2u * id + 1u] = deliot_count(b, inputs[i + 2u], -1e30);
#endif
}

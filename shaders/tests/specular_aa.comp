#version 450
// GPU harness of sand/specular_aa.glsl (tests/core/material/specular_aa.cpp): the widened glint_alpha
// of the method SAND_SPECULAR_AA, from given derivatives.
// Input record (16 floats): 0-3 glint_alpha (alpha_g t, b; relative roughness t, b), 4-6 dn/dx,
// 7-9 dn/dy, 10-11 dh/dx, 12-13 dh/dy, 14 sigma^2, 15 kappa.
// Output record (6 floats): 0-3 the widened glint_alpha, 4-5 the kernel's alpha^2 (t, b).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "sand/specular_aa.glsl"

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * 16u, o = id * 6u;
  vec4 alpha = vec4(inputs[i], inputs[i + 1u], inputs[i + 2u], inputs[i + 3u]);
  SpecularAAInput d = SpecularAAInput(vec3(inputs[i + 4u], inputs[i + 5u], inputs[i + 6u]),
                                      vec3(inputs[i + 7u], inputs[i + 8u], inputs[i + 9u]),
                                      vec2(inputs[i + 10u], inputs[i + 11u]), vec2(inputs[i + 12u], inputs[i + 13u]));
  float sigma2 = inputs[i + 14u], kappa = inputs[i + 15u];
  vec4 wide = specular_aa_glint_alpha(alpha, d, sigma2, kappa);
  vec2 k = specular_aa_kernel(d, sigma2, kappa);
  outputs[o] = wide.x;
  outputs[o + 1u] = wide.y;
  outputs[o + 2u] = wide.z;
  outputs[o + 3u] = wide.w;
  outputs[o + 4u] = k.x;
  outputs[o + 5u] = k.y;
}

#version 450
// GPU harness for the SH irradiance of shaders/common/environment.glsl
// (tests/core/scene/environment_gpu.cpp). Inputs: 27 floats = the nine E_lm (rgb)
// shared by every item, then 3 floats (a normal, not necessarily unit) per
// item. Outputs per item: env_sh_irradiance(n).rgb, env_irradiance(n).rgb.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

vec4 env_sh[9];
#define ENV_NO_MAP
#include "common/environment.glsl"

#define ENV_SH_FLOATS 27u
#define ENV_OUT_STRIDE 6u

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  for (uint k = 0u; k < 9u; ++k)
    env_sh[k] = vec4(inputs[3u * k], inputs[3u * k + 1u], inputs[3u * k + 2u], 0.0);
  uint i = ENV_SH_FLOATS + 3u * id;
  vec3 n = vec3(inputs[i], inputs[i + 1u], inputs[i + 2u]);
  vec3 E = env_sh_irradiance(n);
  vec3 L = env_irradiance(n);
  uint o = ENV_OUT_STRIDE * id;
  outputs[o + 0u] = E.x; outputs[o + 1u] = E.y; outputs[o + 2u] = E.z;
  outputs[o + 3u] = L.x; outputs[o + 4u] = L.y; outputs[o + 5u] = L.z;
}

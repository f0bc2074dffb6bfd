#version 450
// Test shader: writes an analytic function of the interpolated world position
// and the pixel centre, for the fp64 pixel-by-pixel comparison in
// tests/core_renderer.cpp. rgb = world position x, z and
// f = exp(-0.1 |x|) * (1 + 0.5 sin(3 x.x) cos(2 x.z)); alpha = weight.
#include "common/frame.glsl"

layout(location = 0) in vec3 v_x_obj;
layout(location = 1) in vec3 v_x;
layout(location = 2) in vec3 v_n;
layout(location = 3) in vec4 v_t;
layout(location = 4) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

void main() {
  float f = exp(-0.1 * length(v_x)) * (1.0 + 0.5 * sin(3.0 * v_x.x) * cos(2.0 * v_x.z));
  float w = sample_jitter_weight.z;
  out_color = vec4(v_x.x * w, v_x.z * w, f * w, w);
}

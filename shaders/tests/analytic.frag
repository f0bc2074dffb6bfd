#version 450
// Test shader: writes an analytic function of the interpolated world position
// and the pixel centre, for the fp64 pixel-by-pixel comparison in
// tests/core/render/renderer.cpp. rgb = world position x, z and
// f = exp(-0.1 |x|) * (1 + 0.5 sin(3 x.x) cos(2 x.z)); alpha = weight.
#include "common/frame.glsl"

#include "common/surface_interface.glsl"
layout(location = 0) out vec4 out_color;

void main() {
  float f = exp(-0.1 * length(v_x)) * (1.0 + 0.5 * sin(3.0 * v_x.x) * cos(2.0 * v_x.z));
  float w = sample_jitter_weight.z;
  out_color = vec4(v_x.x * w, v_x.z * w, f * w, w);
}

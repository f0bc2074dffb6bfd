#version 450
// Test shader: writes exactly representable functions of the pixel index, so
// readback can be compared bit for bit (tests/core/render/renderer.cpp).
#include "common/frame.glsl"
#include "common/surface_interface.glsl"
layout(location = 0) out vec4 out_color;
void main() {
  vec2 p = floor(gl_FragCoord.xy);
  out_color = vec4(p.x, p.y, p.y * 1000.0 + p.x, 1.0) * sample_jitter_weight.z;
}

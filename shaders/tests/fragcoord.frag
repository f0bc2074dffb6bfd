#version 450
// Test shader: writes exactly representable functions of the pixel index, so
// readback can be compared bit for bit (tests/core_renderer.cpp).
#include "common/frame.glsl"
// Declared (unused) so the interface matches surface.vert exactly.
layout(location = 0) in vec3 v_x_obj;
layout(location = 1) in vec3 v_x;
layout(location = 2) in vec3 v_n;
layout(location = 3) in vec4 v_t;
layout(location = 4) in vec2 v_uv;
layout(location = 0) out vec4 out_color;
void main() {
  vec2 p = floor(gl_FragCoord.xy);
  out_color = vec4(p.x, p.y, p.y * 1000.0 + p.x, 1.0) * sample_jitter_weight.z;
}

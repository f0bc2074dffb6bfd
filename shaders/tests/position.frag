#version 450
// Test shader: rgb = world position of the surface point, alpha = weight;
// with SURFACE_MOTION also its motion vector (tests/core/render/motion.cpp).
#include "common/frame.glsl"
#include "common/surface_interface.glsl"
#include "common/motion.glsl"
layout(location = 0) out vec4 out_color;
#if SURFACE_MOTION
layout(location = 1) out vec4 out_motion;
#endif
void main() {
  float w = sample_jitter_weight.z;
  out_color = vec4(v_x * w, w);
#if SURFACE_MOTION
  out_motion = surface_motion(v_pix, v_prev_pix, v_eye_offset, v_prev_eye_offset);
#endif
}

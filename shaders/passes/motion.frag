#version 450
// The cheapest surface program: no shading (colour = 0, alpha = coverage),
// only the motion vectors and distances of common/motion.glsl when
// SURFACE_MOTION is on. Serves the runner's motion pass (the exact vectors the
// flicker metric needs, shared by every variant and the reference) and is the
// floor of the throughput benchmark (geometry and passes without material).
#include "common/frame.glsl"
#include "common/surface_interface.glsl"
#include "common/motion.glsl"

layout(location = 0) out vec4 out_color;
#if SURFACE_MOTION
layout(location = 1) out vec4 out_motion;
#endif
#if SURFACE_GLINT
layout(location = 2) out vec4 out_glint;  // no material, no glints
#endif

void main() {
  out_color = vec4(0.0, 0.0, 0.0, sample_jitter_weight.z);
#if SURFACE_MOTION
  out_motion = surface_motion(v_pix, v_prev_pix, v_eye_offset, v_prev_eye_offset);
#endif
#if SURFACE_GLINT
  out_glint = vec4(0.0);
#endif
}

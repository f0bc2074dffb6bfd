#version 450
// Background: environment radiance along the (unjittered) view ray, drawn only
// where no surface wrote depth; with SURFACE_MOTION also its motion vector.
#include "common/frame.glsl"
layout(set = 0, binding = 2) uniform sampler2D env_map;
#include "common/environment.glsl"
#include "common/motion.glsl"

layout(location = 0) in vec3 v_ray;  // unnormalised view ray (passes/sky.vert)
#if SURFACE_MOTION
layout(location = 1) in vec3 v_pix;
layout(location = 2) in vec3 v_prev_pix;
#endif
layout(location = 0) out vec4 out_color;
#if SURFACE_MOTION
layout(location = 1) out vec4 out_motion;  // camera rotation only (common/motion.glsl)
#endif
#if SURFACE_GLINT
layout(location = 2) out vec4 out_glint;  // the sky has no glints
#endif

void main() {
  float len = length(v_ray);
  vec3 dir = len > 0.0 ? v_ray / len : vec3(0.0, 1.0, 0.0);
  vec3 L = max(env_radiance(dir, 0.0), vec3(0.0));
  float w = sample_jitter_weight.z;
  out_color = vec4(L * w, 0.0);
#if SURFACE_MOTION
  out_motion = sky_motion(v_pix, v_prev_pix);
#endif
#if SURFACE_GLINT
  out_glint = vec4(0.0);
#endif
}

// Motion vectors and the distances that flag disocclusions, written by the
// surface pass into its "motion" target (RGBA32F) when SURFACE_MOTION is on:
//   xy = v_t = p_t - p_{t-1}: the pixel motion of the surface point, in pixels
//        (continuous pixel coordinates of core/scene/camera.h, unjittered
//        matrices of both frames); the point was at p - v in frame t-1
//   z  = its distance to the eye in frame t (0: no surface, the sky)
//   w  = its distance to the eye in frame t-1, or -1 when it was behind the
//        previous camera (off-screen)
// A consumer compares w with the previous frame's z at p - v: a nearer surface
// there means the point was hidden (disocclusion).
#ifndef GLINTLAB_MOTION_GLSL
#define GLINTLAB_MOTION_GLSL

#include "common/frame.glsl"

#ifndef SURFACE_MOTION
#define SURFACE_MOTION 0
#endif

// Continuous pixel coordinates of a clip-space position (w > 0).
vec2 clip_to_pixel(vec4 clip) { return (clip.xy / clip.w * 0.5 + 0.5) * frame_resolution.xy; }

vec4 surface_motion(vec3 x, vec3 prev_x) {
  vec4 c = frame_view_proj * vec4(x, 1.0);
  vec4 c_prev = frame_prev_view_proj * vec4(prev_x, 1.0);
  float d = length(x - frame_camera_pos.xyz);
  if (!(c.w > 1e-20) || !(c_prev.w > 1e-20)) return vec4(0.0, 0.0, d, -1.0);
  vec2 v = clip_to_pixel(c) - clip_to_pixel(c_prev);
  return vec4(v, d, length(prev_x - frame_prev_camera_pos.xyz));
}

// The sky is at infinity: only the camera's rotation moves it.
vec4 sky_motion(vec3 dir) {
  vec4 c = frame_view_proj * vec4(dir, 0.0);
  vec4 c_prev = frame_prev_view_proj * vec4(dir, 0.0);
  if (!(c.w > 1e-20) || !(c_prev.w > 1e-20)) return vec4(0.0, 0.0, 0.0, -1.0);
  return vec4(clip_to_pixel(c) - clip_to_pixel(c_prev), 0.0, 0.0);
}

#endif

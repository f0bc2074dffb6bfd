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

// The continuous pixel position of clip-space point `clip`, homogeneous:
// (x, y, w) with the pixel at (x / w, y / w), for w > 0. Linear in clip, so the
// vertex stage computes it per vertex and the rasteriser interpolates it
// exactly (perspective-correct interpolation reproduces what is affine in the
// surface point); the fragment stage then reads no matrix from the frame's
// uniform block (on lavapipe each value read there costs a bounds-checked load
// per eight fragments, and the two matrices and the eyes were 38 of them).
vec3 clip_to_pixel_h(vec4 clip) { return vec3((clip.xy * 0.5 + 0.5 * clip.w) * frame_resolution.xy, clip.w); }

// The motion target's value of a surface point from what the vertex stage
// interpolated: its homogeneous pixel positions now and in frame t-1, and its
// offsets from the eye now and then (passes/surface.vert).
vec4 surface_motion(vec3 pix, vec3 prev_pix, vec3 eye_offset, vec3 prev_eye_offset) {
  float d = length(eye_offset);
  if (!(pix.z > 1e-20) || !(prev_pix.z > 1e-20)) return vec4(0.0, 0.0, d, -1.0);
  return vec4(pix.xy / pix.z - prev_pix.xy / prev_pix.z, d, length(prev_eye_offset));
}

// The sky is at infinity: only the camera's rotation moves it. pix, prev_pix:
// clip_to_pixel_h of the view ray as a direction (w = 0) in both frames.
vec4 sky_motion(vec3 pix, vec3 prev_pix) {
  if (!(pix.z > 1e-20) || !(prev_pix.z > 1e-20)) return vec4(0.0, 0.0, 0.0, -1.0);
  return vec4(pix.xy / pix.z - prev_pix.xy / prev_pix.z, 0.0, 0.0);
}

#endif

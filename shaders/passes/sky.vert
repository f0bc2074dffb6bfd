#version 450
// One triangle covering the screen at the far plane (depth 1), with the world-space view ray of each
// corner: for a perspective (or orthographic) camera the ray far_point - near_point is an affine
// function of NDC xy (the inverse view-projection's w row does not depend on x and y), so the
// rasteriser's interpolation gives every pixel its ray, and the fragment stage does no matrix work.
#include "common/frame.glsl"
#include "common/motion.glsl"

layout(location = 0) out vec3 v_ray;
#if SURFACE_MOTION  // the ray's homogeneous pixel positions now and then (common/motion.glsl, sky_motion)
layout(location = 1) out vec3 v_pix;
layout(location = 2) out vec3 v_prev_pix;
#endif

#ifndef SKY_JITTERED
#define SKY_JITTERED 0
#endif

void main() {
  const vec2 ndc = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
#if SKY_JITTERED
  // The ray of the point the jittered camera sees at each pixel (core/scene/camera.h: a point at
  // unjittered pixel position u appears at u + jitter), as the surfaces' samples are: below the output
  // resolution a temporal upscaler places every sample where it was taken, the sky's included.
  const vec2 ndc_ray = ndc - 2.0 * sample_jitter_weight.xy * frame_resolution.zw;
#else
  const vec2 ndc_ray = ndc;  // the pixel centre's ray (the sky is smooth: one ray serves every sample)
#endif
  const vec4 far_point = frame_inv_view_proj * vec4(ndc_ray, 1.0, 1.0);
  const vec4 near_point = frame_inv_view_proj * vec4(ndc_ray, 0.0, 1.0);
  v_ray = far_point.xyz / far_point.w - near_point.xyz / near_point.w;
#if SURFACE_MOTION
  v_pix = clip_to_pixel_h(frame_view_proj * vec4(v_ray, 0.0));
  v_prev_pix = clip_to_pixel_h(frame_prev_view_proj * vec4(v_ray, 0.0));
#endif
  gl_Position = vec4(ndc, 1.0, 1.0);
}

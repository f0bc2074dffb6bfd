#version 450
// Transforms the mesh for any surface pass; hands object and world positions,
// the macro normal and tangent, and with SURFACE_MOTION what the motion vector
// needs (common/motion.glsl) to the fragment stage (common/surface_interface.glsl).
#include "common/frame.glsl"
#include "common/motion.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv;

layout(location = 0) out vec3 v_x_obj;
layout(location = 1) out vec3 v_x;
layout(location = 2) out vec3 v_n;
layout(location = 3) out vec4 v_t;
layout(location = 4) out vec2 v_uv;
#if SURFACE_MOTION
layout(location = 5) out vec3 v_pix;
layout(location = 6) out vec3 v_prev_pix;
layout(location = 7) out vec3 v_eye_offset;
layout(location = 8) out vec3 v_prev_eye_offset;
#endif

void main() {
  // The depth pre-pass and the shading pass run this shader in two pipelines
  // and must get bit-identical depth (the shading pass tests EQUAL): `precise`
  // forbids the compiler to contract or reorder the position arithmetic
  // differently in each. (glslang's `invariant gl_Position` decorates a block
  // member, which the SPIR-V validator rejects.)
  precise vec4 x = frame_model * vec4(in_position, 1.0);
  precise vec4 clip = sample_view_proj * x;
  v_x_obj = in_position;
  v_x = x.xyz;
  v_n = mat3(frame_normal_matrix) * in_normal;
  v_t = vec4(mat3(frame_model) * in_tangent.xyz, in_tangent.w);
  v_uv = in_uv;
#if SURFACE_MOTION
  vec3 prev_x = (frame_prev_model * vec4(in_position, 1.0)).xyz;
  v_pix = clip_to_pixel_h(frame_view_proj * x);
  v_prev_pix = clip_to_pixel_h(frame_prev_view_proj * vec4(prev_x, 1.0));
  v_eye_offset = x.xyz - frame_camera_pos.xyz;
  v_prev_eye_offset = prev_x - frame_prev_camera_pos.xyz;
#endif
  gl_Position = clip;
}

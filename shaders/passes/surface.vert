#version 450
// Transforms the mesh for any surface pass; hands object and world positions,
// the macro normal and tangent, and the previous frame's position (motion
// vectors) to the fragment stage (common/surface_interface.glsl).
#include "common/frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv;

layout(location = 0) out vec3 v_x_obj;
layout(location = 1) out vec3 v_x;
layout(location = 2) out vec3 v_n;
layout(location = 3) out vec4 v_t;
layout(location = 4) out vec2 v_uv;
layout(location = 5) out vec3 v_prev_x;  // same point, previous frame (motion vectors)

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
  v_prev_x = (frame_prev_model * vec4(in_position, 1.0)).xyz;
  gl_Position = clip;
}

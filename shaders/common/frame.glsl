// Per-frame uniforms (set 0, binding 0) and per-sample push constants shared
// by every surface pass. Mirrored by core::FrameUniforms / core::SamplePush
// (core/render/frame_uniforms.h); keep the two in the same order.
#ifndef GLINTLAB_FRAME_GLSL
#define GLINTLAB_FRAME_GLSL

layout(set = 0, binding = 0, std140) uniform FrameUBO {
  mat4 frame_model;            // object -> world
  mat4 frame_normal_matrix;    // inverse transpose of frame_model (upper 3x3 used)
  mat4 frame_prev_model;       // object -> world in the previous frame (object motion)
  mat4 frame_view_proj;        // this frame, unjittered (motion vectors)
  mat4 frame_prev_view_proj;   // previous frame, unjittered (motion vectors)
  mat4 frame_inv_view_proj;    // inverse of frame_view_proj (sky rays)
  vec4 frame_camera_pos;       // xyz world eye, w = time (s)
  vec4 frame_prev_camera_pos;  // xyz world eye in the previous frame
  vec4 frame_sun_dir;          // xyz unit vector towards the sun, w = angular radius (rad)
  vec4 frame_sun_L;            // rgb = L_i(x, w_i) (Kajs sec. 4.2.1), working space
  vec4 frame_resolution;       // width, height, 1/width, 1/height
  vec4 env_sh[9];              // SH irradiance E(n) coefficients, rgb (core/scene/spherical_harmonics.h)
  vec4 env_params;             // x = number of env_map mip levels, y = sky radiance scale
};

layout(push_constant) uniform SamplePush {
  mat4 sample_view_proj;       // this sample's jittered view-projection
  vec4 sample_jitter_weight;   // xy = jitter (px), z = weight (1/spp), w = sample index
};

#endif

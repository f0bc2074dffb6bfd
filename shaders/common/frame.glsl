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
  vec4 frame_ubo_sun_dir;      // frame_sun_dir below
  vec4 frame_ubo_sun_L;        // frame_sun_L below
  vec4 frame_resolution;       // width, height, 1/width, 1/height
  vec4 frame_ubo_env_sh[9];    // env_sh below
  vec4 env_params;             // x = number of env_map mip levels, y = sky radiance scale
};

// The frame's lighting, read as
//   frame_sun_dir  xyz unit vector towards the sun, w = angular radius (rad)
//   frame_sun_L    rgb = L_i(x, w_i) (Kajs sec. 4.2.1), working space
//   env_sh[9]      SH irradiance E(n) coefficients, rgb (core/scene/spherical_harmonics.h)
// from the uniform block, or, with FRAME_LIGHTING_WORDS (the 44 32-bit words of
// these three fields in block order; the surface pass defines it for programs
// that ask, core/material/program.h), as constants the compiler folds: a run's
// sun and sky do not change between frames, and on lavapipe every value a
// fragment shader reads from a uniform block costs a bounds-checked load per
// eight fragments. Private globals rather than consts: glslang does not fold
// uintBitsToFloat in a constant initialiser; the compilers after it do.
#ifdef FRAME_LIGHTING_WORDS
const uint frame_lighting_words[44] = uint[44](FRAME_LIGHTING_WORDS);
#define FRAME_LIGHTING_V(i)                                                                            \
  vec4(uintBitsToFloat(frame_lighting_words[i]), uintBitsToFloat(frame_lighting_words[i + 1]),        \
       uintBitsToFloat(frame_lighting_words[i + 2]), uintBitsToFloat(frame_lighting_words[i + 3]))
vec4 frame_sun_dir = FRAME_LIGHTING_V(0);
vec4 frame_sun_L = FRAME_LIGHTING_V(4);
vec4 env_sh[9] = vec4[9](FRAME_LIGHTING_V(8), FRAME_LIGHTING_V(12), FRAME_LIGHTING_V(16), FRAME_LIGHTING_V(20),
                         FRAME_LIGHTING_V(24), FRAME_LIGHTING_V(28), FRAME_LIGHTING_V(32), FRAME_LIGHTING_V(36),
                         FRAME_LIGHTING_V(40));
#else
#define frame_sun_dir frame_ubo_sun_dir
#define frame_sun_L frame_ubo_sun_L
#define env_sh frame_ubo_env_sh
#endif

layout(push_constant) uniform SamplePush {
  mat4 sample_view_proj;       // this sample's jittered view-projection
  vec4 sample_jitter_weight;   // xy = jitter (px), z = weight (1/spp), w = sample index
};

#endif

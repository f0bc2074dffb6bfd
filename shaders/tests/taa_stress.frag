#version 450
// Surface program of the TAA stress cases (experiments/stress/cases_taa.cpp):
// shades nothing physical; the colour and the motion that the TAA resolve
// reads are set per frame through the frame uniforms (uploaded every frame),
// so a case can feed the resolve a history of huge values, motion vectors
// pointing off-screen or not finite, and so on:
//   frame_sun_L.rgb   colour scale C
//   frame_sun_dir.x   pattern: 0 constant C; 1 C h (h a per-pixel hash in [0, 1)^3);
//                     2 C where the hash is below frame_sun_dir.y, C / 64 elsewhere (sparse bright pixels);
//                     3 C (1 + frame_sun_dir.y (h - 1/2)) (a flat region with a small relative spread)
//   frame_sun_dir.z   hash seed (a new pattern each frame)
//   env_sh[0]         xy: the motion vector of every pixel (pixels) when z > 0.5, and then the
//                     distances now and last frame are both w (a disocclusion everywhere in a
//                     frame whose w differs from the last frame's, none otherwise);
//                     z <= 0.5: the true motion of the surface (common/motion.glsl)
//   env_sh[1], [2]    a moving square over a background, when env_sh[1].w > 0.5 (it overrides env_sh[0]):
//                     the pixels x, y with env_sh[1].xy <= (x, y) < env_sh[1].xy + env_sh[1].z are the
//                     square, moving env_sh[2].xy pixels a frame at distance env_sh[2].z; the others a
//                     still background at distance env_sh[2].w (tests/experiments/taa.cpp counts the
//                     pixels whose history restarts against the square's positions)
// With SURFACE_GLINT the glint layer (passes/sand.frag's layout) is the bright pixels of pattern 2
// (share 1) and 0 elsewhere: the sparse glints the glint-aware options act on.
#include "common/frame.glsl"
#include "common/surface_interface.glsl"
#include "common/pcg3d.glsl"
#include "common/motion.glsl"

layout(location = 0) out vec4 out_color;
#if SURFACE_MOTION
layout(location = 1) out vec4 out_motion;
#endif
#if SURFACE_GLINT
layout(location = 2) out vec4 out_glint;
#endif

void main() {
  uvec2 px = uvec2(gl_FragCoord.xy);
  vec3 h = pcg3d_unit(pcg3d(uvec3(px, floatBitsToUint(frame_sun_dir.z))));
  vec3 C = frame_sun_L.rgb;
  vec3 c = C;
  if (frame_sun_dir.x > 2.5) c = C * (1.0 + frame_sun_dir.y * (h - 0.5));
  else if (frame_sun_dir.x > 1.5) c = h.x < frame_sun_dir.y ? C : C * (1.0 / 64.0);
  else if (frame_sun_dir.x > 0.5) c = C * h;
  bool glint = frame_sun_dir.x > 1.5 && frame_sun_dir.x < 2.5 && h.x < frame_sun_dir.y;
  float w = sample_jitter_weight.z;
  out_color = vec4(c * w, w);
#if SURFACE_MOTION
  vec4 m = surface_motion(v_pix, v_prev_pix, v_eye_offset, v_prev_eye_offset);
  if (env_sh[0].z > 0.5) m = vec4(env_sh[0].xy, env_sh[0].w, env_sh[0].w);
  if (env_sh[1].w > 0.5) {
    vec2 o = vec2(px) - env_sh[1].xy;
    bool square = all(greaterThanEqual(o, vec2(0.0))) && all(lessThan(o, vec2(env_sh[1].z)));
    m = square ? vec4(env_sh[2].xy, env_sh[2].z, env_sh[2].z) : vec4(0.0, 0.0, env_sh[2].w, env_sh[2].w);
  }
  out_motion = m;
#endif
#if SURFACE_GLINT
  out_glint = glint ? vec4(c * w, w) : vec4(0.0);
#endif
}

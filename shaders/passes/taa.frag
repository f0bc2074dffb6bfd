#version 450
// The TAA pass's host (core/render/taa_pass.h): binds what the resolve uses, implements the accessors of
// taa/interface.glsl, includes the resolve file (TAA_RESOLVE_FILE, an include alias) and writes its
// TaaResult: taa.color (rgb = color, a = the current frame's coverage), taa.history and, where the file
// reads them back, taa.state, taa.state2 and taa.history2. A full-screen fragment pass
// (passes/fullscreen.vert): one fragment per pixel (why a fragment pass: core/render/taa_pass.cpp).
// Inputs use texelFetch only (exact, no filtering hardware needed).

#ifndef TAA_QUAD_SHARE
#define TAA_QUAD_SHARE 0
#endif
#ifndef TAA_RENDER_SCALED
#define TAA_RENDER_SCALED 1  // the host sets it (core/render/taa_pass.cpp); 1 serves any scale
#endif
#if TAA_QUAD_SHARE
#extension GL_KHR_shader_subgroup_quad : require
#endif
#ifndef TAA_USES_MOTION
#define TAA_USES_MOTION 0
#endif
#ifndef TAA_USES_GLINT
#define TAA_USES_GLINT 0
#endif
#ifndef TAA_USES_STATE
#define TAA_USES_STATE 0
#endif
#ifndef TAA_USES_STATE2
#define TAA_USES_STATE2 0
#endif
#ifndef TAA_USES_HISTORY2
#define TAA_USES_HISTORY2 0
#endif
#ifndef TAA_PARAMETER_VALUES
#define TAA_PARAMETER_VALUES
#endif

#include "taa/interface.glsl"

layout(set = 0, binding = 0) uniform sampler2D taa_color_tex;     // this frame, jittered, RGBA32F
layout(set = 0, binding = 1) uniform sampler2D taa_motion_tex;    // common/motion.glsl layout
layout(set = 0, binding = 2) uniform sampler2D taa_history_tex;   // last frame's TaaResult.history
layout(set = 0, binding = 3) uniform sampler2D taa_state_tex;     // ... .state
layout(set = 0, binding = 4) uniform sampler2D taa_state2_tex;    // ... .state2
layout(set = 0, binding = 5) uniform sampler2D taa_history2_tex;  // ... .history2
layout(set = 0, binding = 6) uniform sampler2D taa_glint_tex;     // the surface pass's glint layer

// Outputs: taa.color, taa.history, then the kept targets the resolve uses, in this order.
layout(location = 0) out vec4 taa_out_color;
layout(location = 1) out vec4 taa_out_history;
#define TAA_LOCATION_STATE 2
#if TAA_USES_STATE
layout(location = TAA_LOCATION_STATE) out vec4 taa_out_state;
#define TAA_LOCATION_STATE2 (TAA_LOCATION_STATE + 1)
#else
#define TAA_LOCATION_STATE2 TAA_LOCATION_STATE
#endif
#if TAA_USES_STATE2
layout(location = TAA_LOCATION_STATE2) out vec4 taa_out_state2;
#define TAA_LOCATION_HISTORY2 (TAA_LOCATION_STATE2 + 1)
#else
#define TAA_LOCATION_HISTORY2 TAA_LOCATION_STATE2
#endif
#if TAA_USES_HISTORY2
layout(location = TAA_LOCATION_HISTORY2) out vec4 taa_out_history2;
#endif

layout(push_constant) uniform TaaPush {
  vec4 taa_size_frame;   // width, height, history valid (0/1), frame
  vec4 taa_jitters;      // jitter, jitter_prev (output pixels)
  vec4 taa_render;       // render width, height; render size / output size (x, y)
  vec4 taa_values[4];    // the parameters, in declaration order
};

ivec2 taa_g_size;
ivec2 taa_g_pixel;
ivec2 taa_g_rsize;   // the render resolution of the inputs (colour, motion, glint layer)
vec2 taa_g_scale;    // render size / output size, in (0, 1]

float taa_parameter_value(int i) { return taa_values[i / 4][i % 4]; }

ivec2 taa_size() { return taa_g_size; }

vec4 taa_texel(sampler2D t, ivec2 q) { return texelFetch(t, clamp(q, ivec2(0), taa_g_size - 1), 0); }

// A continuous position safe to convert: not finite -> (0, 0); clamped to a pixel beyond the image.
vec2 taa_safe_pos(vec2 pos) {
  if (any(isnan(pos)) || any(isinf(pos))) return vec2(0.0);
  return clamp(pos, vec2(-1.0), vec2(taa_g_size) + 1.0);
}

vec4 taa_nearest(sampler2D t, vec2 pos) {
  return texelFetch(t, ivec2(clamp(floor(taa_safe_pos(pos)), vec2(0.0), vec2(taa_g_size - 1))), 0);
}

// The filtered value at continuous position pos (texel centres at +0.5): i0 = floor(pos - 0.5), f the
// fraction of pos - 0.5 past i0, and the 2x2 texels i0 + (0|1, 0|1); Catmull-Rom adds the ring around
// them. Falcor samples Catmull-Rom in 9 bilinear taps (the two middle weights of each axis merged into
// one hardware-filtered lookup, exact because both are >= 0); where every tap is a texelFetch those 9
// lookups are 36 fetches, so here the 16 texels are weighted directly (the same filter).
vec3 taa_catmull_rom_row(sampler2D t, ivec2 p, vec3 inner0, vec3 inner1, vec4 wx) {
  return wx.x * taa_texel(t, p + ivec2(-1, 0)).rgb + wx.y * inner0 + wx.z * inner1 + wx.w * taa_texel(t, p + ivec2(2, 0)).rgb;
}

vec3 taa_filtered(sampler2D t, vec2 pos, int filter_kind) {
  if (filter_kind == TAA_NEAREST) return taa_nearest(t, pos).rgb;
  vec2 qq = taa_safe_pos(pos) - 0.5;
  ivec2 i0 = ivec2(floor(qq));  // within [-2, size + 1]: no out-of-range conversion
  vec2 f = qq - floor(qq);
  vec3 a = taa_texel(t, i0).rgb, b = taa_texel(t, i0 + ivec2(1, 0)).rgb;
  vec3 c = taa_texel(t, i0 + ivec2(0, 1)).rgb, d = taa_texel(t, i0 + ivec2(1, 1)).rgb;
  if (filter_kind != TAA_CATMULL_ROM) return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
  vec2 f2 = f * f, f3 = f2 * f;
  vec2 w0 = f2 - 0.5 * (f3 + f);
  vec2 w1 = 1.5 * f3 - 2.5 * f2 + 1.0;
  vec2 w3 = 0.5 * (f3 - f2);
  vec2 w2 = 1.0 - w0 - w1 - w3;
  vec4 wx = vec4(w0.x, w1.x, w2.x, w3.x);
  ivec2 up = i0 - ivec2(0, 1), down = i0 + ivec2(0, 2);
  return w0.y * taa_catmull_rom_row(t, up, taa_texel(t, up).rgb, taa_texel(t, up + ivec2(1, 0)).rgb, wx) +
         w1.y * taa_catmull_rom_row(t, i0, a, b, wx) +
         w2.y * taa_catmull_rom_row(t, i0 + ivec2(0, 1), c, d, wx) +
         w3.y * taa_catmull_rom_row(t, down, taa_texel(t, down).rgb, taa_texel(t, down + ivec2(1, 0)).rgb, wx);
}

// This frame's jitter in render pixels (the push constants hold it in output pixels).
vec2 taa_jitter_render() { return taa_jitters.xy * taa_g_scale; }
// A render-resolution input at a texel, clamped to the render image.
vec4 taa_rtexel(sampler2D t, ivec2 q) { return texelFetch(t, clamp(q, ivec2(0), taa_g_rsize - 1), 0); }
ivec2 taa_render_size() { return taa_g_rsize; }
vec2 taa_render_scale() { return taa_g_scale; }
// The render texel whose area holds output position pos (at scale 1: the pixel itself).
ivec2 taa_render_texel(vec2 pos) {
  return ivec2(clamp(floor(taa_safe_pos(pos) * taa_g_scale), vec2(0.0), vec2(taa_g_rsize - 1)));
}
// The render texel under the centre of output pixel q.
ivec2 taa_under(ivec2 q) { return taa_render_texel(vec2(q) + 0.5); }
// Where the sample of render texel i was taken, in output pixels: the camera of this frame sees at a
// texel centre c the point whose unjittered position is c - jitter (core/scene/camera.h).
vec2 taa_render_sample(ivec2 texel) { return (vec2(texel) + 0.5 - taa_jitter_render()) / taa_g_scale; }
vec3 taa_render_color(ivec2 texel) { return taa_rtexel(taa_color_tex, texel).rgb; }
vec3 taa_current(ivec2 offset) { return taa_rtexel(taa_color_tex, taa_under(taa_g_pixel + offset)).rgb; }
vec3 taa_history(vec2 pos, int filter_kind) { return taa_filtered(taa_history_tex, pos, filter_kind); }
bool taa_in_frame(vec2 pos) {
  return all(greaterThanEqual(pos, vec2(0.0))) && all(lessThanEqual(pos, vec2(taa_g_size))) &&
         !any(isnan(pos)) && !any(isinf(pos));
}
#if TAA_USES_MOTION
// Motion in render pixels inside, in output pixels here (at scale 1 the same bits).
vec2 taa_render_motion(ivec2 texel) { return taa_rtexel(taa_motion_tex, texel).xy / taa_g_scale; }
float taa_render_distance(ivec2 texel) { return taa_rtexel(taa_motion_tex, texel).z; }
float taa_render_distance_prev(ivec2 texel) { return taa_rtexel(taa_motion_tex, texel).w; }
vec2 taa_motion(ivec2 offset) { return taa_render_motion(taa_under(taa_g_pixel + offset)); }
float taa_distance(ivec2 offset) { return taa_rtexel(taa_motion_tex, taa_under(taa_g_pixel + offset)).z; }
float taa_distance_prev(ivec2 offset) { return taa_rtexel(taa_motion_tex, taa_under(taa_g_pixel + offset)).w; }
#endif
#if TAA_USES_STATE
vec4 taa_state(vec2 pos) { return taa_nearest(taa_state_tex, pos); }
#endif
#if TAA_USES_STATE2
vec4 taa_state2(vec2 pos) { return taa_nearest(taa_state2_tex, pos); }
#endif
#if TAA_USES_HISTORY2
vec3 taa_history2(vec2 pos, int filter_kind) { return taa_filtered(taa_history2_tex, pos, filter_kind); }
#endif
#if TAA_USES_GLINT
vec4 taa_render_glint(ivec2 texel) { return taa_rtexel(taa_glint_tex, texel); }
vec4 taa_glint(ivec2 offset) { return taa_rtexel(taa_glint_tex, taa_under(taa_g_pixel + offset)); }
#endif

#include "TAA_RESOLVE_FILE"

void main() {
  taa_g_size = ivec2(taa_size_frame.xy);
  taa_g_pixel = ivec2(gl_FragCoord.xy);  // the viewport is the image
  taa_g_rsize = ivec2(taa_render.xy);
  taa_g_scale = taa_render.zw;
  TaaPixel p;
  p.pixel = taa_g_pixel;
  p.history_valid = taa_size_frame.z > 0.5;
  p.jitter = taa_jitters.xy;
  p.jitter_prev = taa_jitters.zw;
  p.frame = uint(taa_size_frame.w);
  TAA_PARAMETER_VALUES
  TaaResult r = taa_resolve(p);
  taa_out_color = vec4(r.color, taa_rtexel(taa_color_tex, taa_under(taa_g_pixel)).a);
  taa_out_history = vec4(r.history, 0.0);
#if TAA_USES_STATE
  taa_out_state = r.state;
#endif
#if TAA_USES_STATE2
  taa_out_state2 = r.state2;
#endif
#if TAA_USES_HISTORY2
  taa_out_history2 = vec4(r.history2, 0.0);
#endif
}

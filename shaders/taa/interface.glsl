// The temporal resolve interface. A resolve is one file (the built-in ones are the other files of this
// folder; a user's comes from the experiment file, "taa": {"file": ...}) that defines
//
//   TaaResult taa_resolve(TaaPixel p);
//
// and declares itself in comment lines (core/render/taa_resolve.h parses them):
//   // taa_resolve checks=finite,deterministic,converges,ghosting,cut,pan,flicker [fails=CHECK,...]
//   // taa_parameter NAME default=V range=LO,HI [requires=BOOL]   a float field p.NAME, set at run time
//   // taa_parameter NAME default=true|false [requires=BOOL]      a bool field p.NAME
//   // taa_option NAME=a|b|c default=a [requires=BOOL]            compile time: #if TAA_NAME == TAA_NAME_b
// The preprocessor also sees TAA_ON_NAME for every parameter (1 where its value is non-zero), so that
// code a zero parameter switches off can be compiled out, and with it what it reads. `requires=B`: the
// experiment file may set it only where the bool parameter B is true.
//
// Units: pixels of the output image, continuous coordinates with pixel centres at +0.5 (pixel p covers
// [p, p + 1)). The pass runs taa_resolve once per output pixel, every frame. The frame may be rendered
// below the output resolution (a variant's "render_scale" s): its colour, motion and glint layer are
// then render texels, each 1/s output pixels wide; every accessor but the taa_render_* ones reads the
// render texel under the output pixel's centre and gives motion and jitter in output pixels, so a
// resolve written for s = 1 runs unchanged (and at s = 1 every render texel is its pixel).
//
// TaaPixel p:
//   ivec2 pixel         the output pixel
//   bool history_valid  false on the first frame, after a reset and after a camera cut: every
//                       taa_history / taa_state read is then meaningless
//   vec2 jitter         this frame's sub-pixel jitter (output pixels): the camera sees at a texel centre
//                       c the point whose unjittered position is c - jitter (core/scene/camera.h)
//   vec2 jitter_prev    the jitter of the frame the history holds (= jitter when there is none)
//   uint frame          the frame's index in the camera path
//   and every declared parameter, p.NAME
//
// TaaResult (start from taa_result(color), which sets every field):
//   vec3 color     what is displayed and measured
//   vec3 history   kept for the next frame's taa_history (taa_result: = color)
//   vec4 state     kept for the next frame's taa_state (taa_result: 0)
//   vec4 state2    kept for the next frame's taa_state2 (taa_result: 0)
//   vec3 history2  kept for the next frame's taa_history2 (taa_result: 0): a second filtered history,
//                  e.g. a layer resolved apart
//
// Accessors (each target or input is bound only where the file, as its options compile it, uses it):
//   vec3  taa_current(ivec2 offset)      this frame's jittered colour at pixel + offset (clamped to the image)
//   vec2  taa_motion(ivec2 offset)       glintlab's motion vector there, pixels: the history of the point at
//                                        c = pixel + 0.5 is at c - taa_motion(ivec2(0))
//   float taa_distance(ivec2 offset)     the distance of the surface seen there to the eye (0: sky)
//   float taa_distance_prev(ivec2 offset) its distance in the previous frame (-1: behind that camera)
//   vec3  taa_history(vec2 pos, int filter_kind)   last frame's TaaResult.history at pos, filtered by
//                                        TAA_NEAREST, TAA_BILINEAR or TAA_CATMULL_ROM (16 texels; it rings
//                                        below 0 next to bright texels: clamp as the resolve needs)
//   vec3  taa_history2(vec2 pos, int filter_kind)  the same of TaaResult.history2
//   vec4  taa_state(vec2 pos), taa_state2(vec2 pos)  last frame's TaaResult.state / state2, nearest texel
//   bool  taa_in_frame(vec2 pos)         pos is finite and within [0, width] x [0, height]
//   vec4  taa_glint(ivec2 offset)        the surface pass's glint layer: rgb = the glint term's part of
//                                        the colour, a = its share of the luma (sand/sand.glsl)
//   ivec2 taa_size()                     the output image size
// Upscaling (render texels; the same as the above at s = 1):
//   ivec2 taa_render_size(), vec2 taa_render_scale()   the render resolution, render size / output size
//   ivec2 taa_render_texel(vec2 pos)     the render texel whose area holds output position pos
//   vec2  taa_render_sample(ivec2 texel) where that texel's sample was taken this frame, output pixels
//   vec3  taa_render_color(ivec2 texel), vec2 taa_render_motion(ivec2 texel) (output pixels),
//   float taa_render_distance(ivec2 texel), float taa_render_distance_prev(ivec2 texel),
//   vec4 taa_render_glint(ivec2 texel)
// Reads outside the image are clamped to its edge; positions that are not finite read texel (0, 0).
// Host capability: TAA_QUAD_SHARE is 1 where every 2x2 quad of fragments lies whole in the image and the
// device has quad subgroup operations in fragment shaders (GL_KHR_shader_subgroup_quad is enabled then).
// TAA_RENDER_SCALED is 1 where the inputs are below the output resolution and 0 at it (what
// taa_render_scale() says at run time, known when the pass is compiled): `#if TAA_RENDER_SCALED` leaves
// the other case out (a GPU without divergence skips an untaken branch; llvmpipe runs both sides).
//
// A resolve may not declare resources, outputs or work-group memory, nor discard: it reads what the
// accessors give.
#ifndef GLINTLAB_TAA_INTERFACE_GLSL
#define GLINTLAB_TAA_INTERFACE_GLSL

#define TAA_NEAREST 0
#define TAA_BILINEAR 1
#define TAA_CATMULL_ROM 2

#ifndef TAA_PARAMETER_FIELDS
#define TAA_PARAMETER_FIELDS
#endif

struct TaaPixel {
  ivec2 pixel;
  bool history_valid;
  vec2 jitter;
  vec2 jitter_prev;
  uint frame;
  TAA_PARAMETER_FIELDS
};

struct TaaResult {
  vec3 color;
  vec3 history;
  vec4 state;
  vec4 state2;
  vec3 history2;
};

TaaResult taa_result(vec3 color) { return TaaResult(color, color, vec4(0.0), vec4(0.0), vec3(0.0)); }

vec3 taa_current(ivec2 offset);
vec2 taa_motion(ivec2 offset);
float taa_distance(ivec2 offset);
float taa_distance_prev(ivec2 offset);
vec3 taa_history(vec2 pos, int filter_kind);
vec3 taa_history2(vec2 pos, int filter_kind);
vec4 taa_state(vec2 pos);
vec4 taa_state2(vec2 pos);
bool taa_in_frame(vec2 pos);
vec4 taa_glint(ivec2 offset);
ivec2 taa_size();
ivec2 taa_render_size();
vec2 taa_render_scale();
ivec2 taa_render_texel(vec2 pos);
vec2 taa_render_sample(ivec2 texel);
vec3 taa_render_color(ivec2 texel);
vec2 taa_render_motion(ivec2 texel);
float taa_render_distance(ivec2 texel);
float taa_render_distance_prev(ivec2 texel);
vec4 taa_render_glint(ivec2 texel);

#endif

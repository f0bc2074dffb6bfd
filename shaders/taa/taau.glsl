// Temporal upsampling in the Falcor family (Karis 2014, "High Quality Temporal Supersampling", the
// TAAU of Unreal Engine 4): Falcor's resolve (falcor.glsl, every parameter and option, `accumulate`
// included) whose current frame is not the render texel under the output pixel but a reconstruction
// from the render texels around the pixel's centre.
//
// taa_resolve extends=falcor checks=finite,deterministic,ghosting,cut,pan,flicker fails=converges
//
// The current frame at an output pixel, at render scale s < 1: the render samples that fell inside the
// pixel this frame (its box, the truth's filter), their mean and their count W; where none did, a
// reconstruction from the 3x3 render texels around the one under the pixel's centre, a Gaussian in
// output pixels of standard deviation upsample_sigma (0.47: Karis' fit exp(-2.29 x^2) of the
// Blackman-Harris window of his current-frame filter) over the distance from each texel's sample this
// frame (taa_render_sample: the texel centre moved by the jitter) to the pixel's centre, and W = 0.
// taa_parameter upsample_sigma default=0.47 range=0.2,2
//
// Then falcor's resolve, with
//   the box   = the 3x3 render texels around the one under the pixel (Karis' neighbourhood of the
//               samples themselves, not of the reconstruction);
//   motion    = that of those render texels (falcor's choice among them: `velocity`);
//   with `accumulate`, this frame counts W in n (not 1) and weighs max(alpha' W, W / n): the history
//   accumulates the samples that fell inside the pixel, frame after frame, and converges to their mean,
//   the box-filtered image; a frame with no sample inside leaves it as it is.
// At s = 1 the current is the pixel's own sample, the box and motion its 3x3 and W = 1: the frames
// falcor renders with the same choices (taau adds nothing where there is nothing to upsample).

// Whether falcor reads the glint layer (its FALCOR_GLINT, defined when taa/falcor.glsl is included below).
#define TAAU_GLINT (TAA_ON_reactive || TAA_ON_glint_layer || TAA_ON_glint_lock)

struct TaauCurrent {
  vec3 rgb;
  vec4 glint;
  float weight;
  ivec2 texel;  // the render texel under the pixel's centre
#if TAA_RENDER_SCALED
  // The 3x3 render texels around `texel` (k = 3 (dy + 1) + dx + 1; reads past the edge clamped, as the
  // accessors give them): fetched once for the reconstruction, read again as falcor's neighbourhood
  // (one fetch fewer for each of eight neighbours: 15 % of the resolve on llvmpipe).
  vec3 nb[9];
#if TAAU_GLINT
  vec4 gnb[9];
#endif
#endif
};
TaauCurrent taau_g;

void taau_begin(TaaPixel px) {
  vec2 centre = vec2(px.pixel) + 0.5;
  taau_g.texel = taa_render_texel(centre);
#if !TAA_RENDER_SCALED
  taau_g.rgb = taa_current(ivec2(0));
#if TAAU_GLINT
  taau_g.glint = taa_glint(ivec2(0));
#endif
  taau_g.weight = 1.0;
#else
  float inv_two_var = 0.5 / (px.upsample_sigma * px.upsample_sigma);
  vec3 sum = vec3(0.0), inside = vec3(0.0);
  vec4 gsum = vec4(0.0), ginside = vec4(0.0);
  float wsum = 0.0, count = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 t = taau_g.texel + ivec2(dx, dy);
      vec3 c = taa_render_color(t);
      taau_g.nb[(dy + 1) * 3 + dx + 1] = c;
#if TAAU_GLINT
      vec4 g = taa_render_glint(t);
      taau_g.gnb[(dy + 1) * 3 + dx + 1] = g;
#endif
      if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, taa_render_size()))) continue;
      vec2 x = taa_render_sample(t), d = x - centre;
      float w = exp(-min(dot(d, d) * inv_two_var, 80.0));  // no underflow to denormals
      sum += w * c;
      wsum += w;
      bool in_pixel = all(greaterThanEqual(x, vec2(px.pixel))) && all(lessThan(x, vec2(px.pixel) + 1.0));
      if (in_pixel) {
        inside += c;
        count += 1.0;
      }
#if TAAU_GLINT
      gsum += w * g;
      if (in_pixel) ginside += g;
#endif
    }
  // The texel under the centre is always among them, so wsum > 0 unless every weight underflowed:
  // then that texel alone.
  if (count > 0.0) {
    taau_g.rgb = inside / count;
    taau_g.glint = ginside / count;
  } else if (wsum > 0.0) {
    taau_g.rgb = sum / wsum;
    taau_g.glint = gsum / wsum;
  } else {
    taau_g.rgb = taau_g.nb[4];
#if TAAU_GLINT
    taau_g.glint = taau_g.gnb[4];
#endif
  }
  taau_g.weight = count;
#endif
}

// The neighbourhood falcor reads (o in [-1, 1]^2): the render texels around the one under the pixel,
// as taau_begin fetched them (at scale 1 the pixel's own neighbours, which are those texels).
#if TAA_RENDER_SCALED
vec3 taau_neighbour_rgb(ivec2 o) { return taau_g.nb[(o.y + 1) * 3 + o.x + 1]; }
#if TAAU_GLINT
vec4 taau_neighbour_glint(ivec2 o) { return taau_g.gnb[(o.y + 1) * 3 + o.x + 1]; }
#endif
vec4 taau_neighbour_motion(ivec2 o) {
  ivec2 t = clamp(taau_g.texel + o, ivec2(0), taa_render_size() - 1);
  return vec4(taa_render_motion(t), taa_render_distance(t), taa_render_distance_prev(t));
}
#else
vec3 taau_neighbour_rgb(ivec2 o) { return taa_current(o); }
#if TAAU_GLINT
vec4 taau_neighbour_glint(ivec2 o) { return taa_glint(o); }
#endif
vec4 taau_neighbour_motion(ivec2 o) { return vec4(taa_motion(o), taa_distance(o), taa_distance_prev(o)); }
#endif

#define FALCOR_BEGIN(px) taau_begin(px);
#define FALCOR_CURRENT_RGB() taau_g.rgb
#define FALCOR_CURRENT_GLINT() taau_g.glint
#define FALCOR_NEIGHBOUR_RGB(o) taau_neighbour_rgb(o)
#define FALCOR_NEIGHBOUR_GLINT(o) taau_neighbour_glint(o)
#define FALCOR_NEIGHBOUR_MOTION(o) taau_neighbour_motion(o)
#define FALCOR_SAMPLE_WEIGHT() taau_g.weight

#include "taa/falcor.glsl"

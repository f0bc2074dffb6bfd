#version 450
// TAA resolve: this frame's jittered colour blended with the reprojected
// history. Every design choice is a compile-time option (core/render/taa_settings.h
// names them and cites their sources); the defaults are Falcor's TAA pass.
//
// Per pixel p (texel centre c = p + 0.5):
//   1. v = motion vector chosen by TAA_VELOCITY; the history is at q = c - v.
//   2. History is invalid (the pixel restarts from the current colour) in the
//      first frame after a reset or camera cut, when q is off-screen, or when the
//      resampled history is not finite; with TAA_DISOCCLUSION also where the
//      surface the history holds is not the one seen now (same_surface below).
//   3. Samples are mapped for HDR (TAA_HDR), then to the box space (TAA_SPACE);
//      the history is rectified against the 3x3 neighbourhood (TAA_CLAMP).
//   4. out = mix(history, current, alpha'), alpha' from TAA_FEEDBACK (and the
//      anti-flicker guard), mapped back to linear radiance, clamped to >= 0.
// The glint-aware options (core/render/taa_settings.h; all off by default, and
// then none of their code is compiled) read the surface pass's glint layer G
// (rgb = the glint term's part of the pixel's radiance, a = its share s of the
// luma, sand/sand.glsl sand_glint_share):
//   TAA_ACCUMULATE   alpha' = max(alpha', 1/n), n = frames accumulated at the
//                    pixel since its history last restarted (taa.extra.a,
//                    reprojected with the nearest texel).
//   TAA_REACTIVE     r = reactive s: h = mix(h, raw history, r) (the
//                    rectification relaxed: a glint is an outlier of its 3x3
//                    box, so the box cannot tell a valid glint history from a
//                    ghost) and alpha' = mix(alpha', 1, r) (the history weight
//                    lowered by 1 - r, so what is kept unrectified is kept
//                    briefly and cannot trail).
//   TAA_GLINT_LOCK   where s > 1/2 and the raw history's luma is at least half
//                    the current one, h = raw history (no rectification).
//   TAA_GLINT_LAYER  colour - G through steps 1-4 (and into taa.history); G
//                    apart: G_out = mix(G_hist, G, glint_alpha) with G_hist
//                    the same resample of taa.extra.rgb at q, under the same
//                    validity, rectified by TAA_GLINT_CLAMP (none, or the
//                    min/max of the 3x3 current G); out = colour' + G_out.
// Inputs use texelFetch only (exact, no filtering hardware needed).
// A full-screen fragment pass (passes/fullscreen.vert): one fragment per pixel
// writes the resolved colour, the history and (anti_flicker) the lumas (why a
// fragment pass: core/render/taa_pass.cpp).

#ifndef TAA_QUAD_SHARE
#define TAA_QUAD_SHARE 0
#endif
#if TAA_QUAD_SHARE
#extension GL_KHR_shader_subgroup_quad : require
#endif

layout(set = 0, binding = 0) uniform sampler2D color_tex;     // this frame, jittered, RGBA32F
layout(set = 0, binding = 1) uniform sampler2D motion_tex;    // common/motion.glsl layout
layout(set = 0, binding = 2) uniform sampler2D history_tex;   // last frame's resolve: rgb, a = nearest distance
layout(set = 0, binding = 3) uniform sampler2D luma_tex;      // anti-flicker: last lumas
layout(set = 0, binding = 4) uniform sampler2D glint_tex;     // the surface pass's glint layer (TAA_GLINT)
layout(set = 0, binding = 5) uniform sampler2D extra_tex;     // taa.extra of last frame (TAA_EXTRA)
layout(location = 0) out vec4 out_color;    // taa.color
layout(location = 1) out vec4 out_history;  // taa.history (this frame's slot)
#if TAA_ANTI_FLICKER
layout(location = 2) out vec4 out_luma;     // taa.luma (this frame's slot)
#define TAA_EXTRA_LOCATION 3
#else
#define TAA_EXTRA_LOCATION 2
#endif
#ifndef TAA_EXTRA
#define TAA_EXTRA 0
#endif
#if TAA_EXTRA
layout(location = TAA_EXTRA_LOCATION) out vec4 out_extra;  // taa.extra: rgb glint history, a = n
#endif

layout(push_constant) uniform Push {
  vec4 size_alpha_gamma;  // width, height, alpha, gamma
  vec4 history_jitter;    // history valid (0/1), disocclusion tolerance, jitter of frame t-1 minus frame t (px)
  vec4 glint_weights;     // reactive, glint_alpha
};

#define CLAMP_NONE 0
#define CLAMP_MINMAX 1
#define CLAMP_CLIP 2
#define CLAMP_VARIANCE 3
#define FILTER_BILINEAR 0
#define FILTER_CATMULL_ROM 1
#define VELOCITY_CENTER 0
#define VELOCITY_CLOSEST_DEPTH 1
#define VELOCITY_LONGEST 2
#define FEEDBACK_FIXED 0
#define FEEDBACK_LUMA 1
#define FEEDBACK_KARIS 2
#define HDR_NONE 0
#define HDR_INVERSE_LUMA 1
#define HDR_TONEMAP 2

#ifndef TAA_CLAMP
#define TAA_CLAMP CLAMP_VARIANCE
#endif
#ifndef TAA_SPACE
#define TAA_SPACE 1
#endif
#ifndef TAA_FILTER
#define TAA_FILTER FILTER_CATMULL_ROM
#endif
#ifndef TAA_VELOCITY
#define TAA_VELOCITY VELOCITY_LONGEST
#endif
#ifndef TAA_FEEDBACK
#define TAA_FEEDBACK FEEDBACK_KARIS
#endif
#ifndef TAA_HDR
#define TAA_HDR HDR_NONE
#endif
#ifndef TAA_ANTI_FLICKER
#define TAA_ANTI_FLICKER 0
#endif
#ifndef TAA_DERING
#define TAA_DERING 0
#endif
#ifndef TAA_GLINT
#define TAA_GLINT 0
#endif
#ifndef TAA_ACCUMULATE
#define TAA_ACCUMULATE 0
#endif
#ifndef TAA_REACTIVE
#define TAA_REACTIVE 0
#endif
#ifndef TAA_GLINT_LAYER
#define TAA_GLINT_LAYER 0
#endif
#ifndef TAA_GLINT_CLAMP
#define TAA_GLINT_CLAMP 0
#endif
#ifndef TAA_GLINT_LOCK
#define TAA_GLINT_LOCK 0
#endif
#ifndef TAA_DISOCCLUSION
#define TAA_DISOCCLUSION 0
#endif

ivec2 g_size;

float luma(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }  // Rec. 709 luma of linear rgb

// HDR mapping (Karis 2014; FSR2) and its inverse; both keep colours >= 0 finite.
vec3 hdr_forward(vec3 c) {
#if TAA_HDR == HDR_INVERSE_LUMA
  return c / (1.0 + max(luma(c), 0.0));
#elif TAA_HDR == HDR_TONEMAP
  return c / (max(max(c.r, c.g), max(c.b, 0.0)) + 1.0);
#else
  return c;
#endif
}
vec3 hdr_inverse(vec3 c) {
#if TAA_HDR == HDR_INVERSE_LUMA
  return c / max(1.0 - luma(c), 1e-6);
#elif TAA_HDR == HDR_TONEMAP
  return c / max(1.0 - max(max(c.r, c.g), c.b), 1e-6);
#else
  return c;
#endif
}

// Box space: rgb, or YCoCg (Y = r/4 + g/2 + b/4; its first channel is luma-like).
vec3 to_space(vec3 c) {
#if TAA_SPACE == 1
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b, -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
#else
  return c;
#endif
}
vec3 from_space(vec3 y) {
#if TAA_SPACE == 1
  return vec3(y.x + y.y - y.z, y.x + y.z, y.x - y.y - y.z);
#else
  return y;
#endif
}
// The luma of a box-space colour.
float space_luma(vec3 y) {
#if TAA_SPACE == 1
  return y.x;
#else
  return luma(y);
#endif
}

vec4 fetch(sampler2D t, ivec2 p) { return texelFetch(t, clamp(p, ivec2(0), g_size - 1), 0); }

// The colour steps 1-4 resolve: the frame's, or with the layers separated, the frame's without its glints.
vec3 resolved_rgb(ivec2 q) {
#if TAA_GLINT_LAYER
  return fetch(color_tex, q).rgb - fetch(glint_tex, q).rgb;
#else
  return fetch(color_tex, q).rgb;
#endif
}

// A colour as the neighbourhood box sees it: HDR-mapped, in box space.
vec3 box_colour(vec3 c) { return to_space(hdr_forward(max(c, vec3(0.0)))); }

#if TAA_QUAD_SHARE
// The 3x3 neighbourhood of every pixel of a 2x2 quad lies in the quad's 4x4
// block of texels: each pixel fetches the 2x2 of it on its own side (itself and
// its neighbours away from the quad's centre, o = (+-1, +-1)) and takes the
// five on the other side from the quad's other pixels, whose own fetches they
// are (a quad swap: the same texel, the same arithmetic, so the same bits).
// 4 fetches of colour and 4 of motion a pixel instead of 9 + 9; on llvmpipe a
// fetch costs about 3 % of the resolve. Needs whole quads: the pass sets
// TAA_QUAD_SHARE only for even image sizes (every quad of the full-screen
// triangle then lies inside the image) and devices with quad operations in
// fragment shaders. T is vec3 (colours) or vec4 (motion); p the pixel.
#define QUAD_NEIGHBOURHOOD(T, p, centre, fetch_box, o, N)                                   \
  {                                                                                         \
    T x_ = fetch_box(p + ivec2(o.x, 0)), y_ = fetch_box(p + ivec2(0, o.y)),                 \
      xy_ = fetch_box(p + o);                                                               \
    /* first N[sy + 1][sx + 1] = the texel at (sx o.x, sy o.y) from this pixel */          \
    N[1][1] = centre; N[1][2] = x_; N[2][1] = y_; N[2][2] = xy_;                            \
    N[1][0] = subgroupQuadSwapHorizontal(centre); N[2][0] = subgroupQuadSwapHorizontal(y_); \
    N[0][1] = subgroupQuadSwapVertical(centre); N[0][2] = subgroupQuadSwapVertical(x_);     \
    N[0][0] = subgroupQuadSwapDiagonal(centre);                                             \
    /* to N[dy + 1][dx + 1], the texel at (dx, dy): mirrored where o points left or up */   \
    for (int r_ = 0; r_ < 3; ++r_) {                                                        \
      T a_ = N[r_][0], b_ = N[r_][2];                                                       \
      N[r_][0] = o.x > 0 ? a_ : b_;                                                         \
      N[r_][2] = o.x > 0 ? b_ : a_;                                                         \
    }                                                                                       \
    for (int c_ = 0; c_ < 3; ++c_) {                                                        \
      T a_ = N[0][c_], b_ = N[2][c_];                                                       \
      N[0][c_] = o.y > 0 ? a_ : b_;                                                         \
      N[2][c_] = o.y > 0 ? b_ : a_;                                                         \
    }                                                                                       \
  }
vec3 fetch_box_colour(ivec2 q) { return box_colour(resolved_rgb(q)); }
vec4 fetch_motion(ivec2 q) { return fetch(motion_tex, q); }
#endif

// The history around continuous pixel position q (texel centres at +0.5):
// i0 = floor(q - 0.5), f = the fraction of q - 0.5 past i0, and the 2x2
// texels i0 + (0|1, 0|1) (rgb, a = the distance kept with the history), which
// both filters and the disocclusion test use.
struct Taps {
  ivec2 i0;
  vec2 f;
  vec4 a, b, c, d;  // (0, 0), (1, 0), (0, 1), (1, 1)
};
Taps taps_2x2(sampler2D t, vec2 q) {
  vec2 qq = q - 0.5;
  Taps k;
  k.i0 = ivec2(floor(qq));  // q is within [0, size] here: no out-of-range conversion
  k.f = qq - floor(qq);
  k.a = fetch(t, k.i0);
  k.b = fetch(t, k.i0 + ivec2(1, 0));
  k.c = fetch(t, k.i0 + ivec2(0, 1));
  k.d = fetch(t, k.i0 + ivec2(1, 1));
  return k;
}

vec3 bilinear(Taps k) { return mix(mix(k.a.rgb, k.b.rgb, k.f.x), mix(k.c.rgb, k.d.rgb, k.f.x), k.f.y); }

// One row of the 4x4: its outer texels fetched, its inner two given; wx the
// four horizontal weights.
vec3 catmull_rom_row(sampler2D t, ivec2 p, vec3 inner0, vec3 inner1, vec4 wx) {
  return wx.x * fetch(t, p + ivec2(-1, 0)).rgb + wx.y * inner0 + wx.z * inner1 + wx.w * fetch(t, p + ivec2(2, 0)).rgb;
}

// Catmull-Rom over the 4x4 texels i0 - 1 .. i0 + 2, the filter of Falcor's
// TAA. Falcor samples it in 9 bilinear taps (the two middle weights of each
// axis merged into one hardware-filtered lookup, exact because both are >= 0);
// where every tap is a texelFetch those 9 lookups are 36 fetches, so here the
// 16 texels are weighted directly (the same filter; sums rounded in another
// order). The inner 2x2 are k's texels.
vec3 catmull_rom(sampler2D t, Taps k) {
  vec2 f = k.f, f2 = f * f, f3 = f2 * f;
  vec2 w0 = f2 - 0.5 * (f3 + f);
  vec2 w1 = 1.5 * f3 - 2.5 * f2 + 1.0;
  vec2 w3 = 0.5 * (f3 - f2);
  vec2 w2 = 1.0 - w0 - w1 - w3;
  vec4 wx = vec4(w0.x, w1.x, w2.x, w3.x);
  ivec2 up = k.i0 - ivec2(0, 1), down = k.i0 + ivec2(0, 2);
  vec3 r = w0.y * catmull_rom_row(t, up, fetch(t, up).rgb, fetch(t, up + ivec2(1, 0)).rgb, wx) +
           w1.y * catmull_rom_row(t, k.i0, k.a.rgb, k.b.rgb, wx) +
           w2.y * catmull_rom_row(t, k.i0 + ivec2(0, 1), k.c.rgb, k.d.rgb, wx) +
           w3.y * catmull_rom_row(t, down, fetch(t, down).rgb, fetch(t, down + ivec2(1, 0)).rgb, wx);
#if TAA_DERING
  // Deringing (FSR2): keep the result within the range of the 2x2 texels
  // around q, so a bright glint's negative lobes cannot darken its
  // neighbours (core/render/taa_settings.h, `dering`).
  r = clamp(r, min(min(k.a.rgb, k.b.rgb), min(k.c.rgb, k.d.rgb)), max(max(k.a.rgb, k.b.rgb), max(k.c.rgb, k.d.rgb)));
#endif
  return max(r, vec3(0.0));  // the negative lobes can ring below zero
}

// INSIDE's clip: move h toward the box centre until it is inside the box.
vec3 clip_to_box(vec3 h, vec3 lo, vec3 hi) {
  vec3 centre = 0.5 * (hi + lo), ext = 0.5 * (hi - lo) + 1e-7;
  vec3 d = h - centre;
  vec3 t = abs(d / ext);
  float m = max(t.x, max(t.y, t.z));
  return m > 1.0 ? centre + d / m : h;
}

bool finite3(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

#if TAA_DISOCCLUSION
// The disocclusion test: does the history hold the surface seen now? The history keeps, in its
// alpha, the distance of the nearest surface of its pixel's 3x3 (0: all sky), and the test takes the
// nearest surface of the 3x3 now. With the nearest of the neighbourhood (FSR2's dilated depth), an
// edge pixel's distance is the near side's in every frame, whichever side its jittered sample hit,
// so a ridge or silhouette keeps its history and converges like supersampling. The nearest pixel's
// own motion and previous distance say where that surface was and how far (FSR2's reconstructed
// previous depth).
//
// The history's distances are point samples at last frame's jittered positions. The test reads them
// where the point was among those samples: q_n (the pixel centre moved back by the nearest's motion)
// plus the change of jitter j_{t-1} - j_t (the camera of frame t sees at pixel centre c the point
// whose unjittered position is c - j_t, core/scene/camera.h; texel i of the history sampled
// i + 1/2 - j_{t-1}). Between samples on one surface the distance lies between theirs, however fast
// it changes (toward a horizon it changes by 5-100 % from one pixel to the next): the point's
// previous distance must lie within the range of the bilinear taps around that position (those of
// weight > 0), widened by the relative tolerance. The sky counts as infinitely far: a tap of sky
// leaves the range open above, and a pixel with no surface in its 3x3 needs a tap of sky.
// near: the motion texel of the nearest surface of the 3x3 (z = 0 where there is none); u: q_n plus
// the jitter change (continuous pixel coordinates).
bool same_surface(vec4 near, vec2 u, float tol) {
  // Off the image by more than a pixel (or not finite): the surface was not seen.
  if (!(all(greaterThanEqual(u, vec2(-1.0))) && all(lessThanEqual(u, vec2(g_size) + 1.0)))) return false;
  Taps k = taps_2x2(history_tex, clamp(u, vec2(0.5), vec2(g_size) - 0.5));
  vec4 held = vec4(k.a.a, k.b.a, k.c.a, k.d.a);
  bvec4 tap = bvec4(true, k.f.x > 0.0, k.f.y > 0.0, k.f.x > 0.0 && k.f.y > 0.0);  // bilinear weight > 0
  float lo = 3.4e38, hi = 0.0;
  bool sky = false;
  for (int i = 0; i < 4; ++i)
    if (tap[i]) {
      if (held[i] > 0.0) {
        lo = min(lo, held[i]);
        hi = max(hi, held[i]);
      } else {
        sky = true;
      }
    }
  if (!(near.z > 0.0)) return sky;   // no surface now: the sky was there
  if (!(near.w > 0.0)) return false; // behind the previous camera
  float w = near.w, slack = tol * w;
  return w >= lo - slack && (sky || w <= hi + slack);
}
#endif

// ---- steps 1 and 3: the current 3x3 neighbourhood
struct Neighbourhood {
  vec3 cur;          // the centre, HDR-mapped, in box space
  vec3 lo, hi;       // the min/max box of the 3x3
  vec3 mean, sigma;  // their mean and standard deviation (the variance clamp)
  vec4 mc;           // the centre's motion texel
  vec2 v;            // the motion TAA_VELOCITY chose
  vec4 near;         // the motion texel of the nearest surface of the 3x3 (TAA_DISOCCLUSION; z = 0: none)
};

// Mean and standard deviation of the neighbourhood (the variance clamp), in two passes about the mean,
// on samples scaled by a power of two that brings the largest to [1/2, 1] (to [1, 4] beyond 2^126).
// The one-pass form m2/9 - mean^2 cancels to fp32 rounding noise in flat regions (a box 1e-3 of the
// mean wide where it should be 1e-5: taa.variance-flat-regions, 6.2e-4 relative error against the
// fp64 resolve) and overflows beyond 1.8e19 (sigma NaN, a collapsed box on lavapipe:
// taa.huge-current, error x261).
void moments(vec3 nb[9], vec3 lo, vec3 hi, out vec3 mean_out, out vec3 sigma_out) {
  float big = max(max(max(abs(lo.x), abs(lo.y)), abs(lo.z)), max(max(abs(hi.x), abs(hi.y)), abs(hi.z)));
  // 2^-e, e in [-126, 126], built from its bits (exp2(-126) may come out
  // denormal and be flushed to 0): the scale and its inverse are normal fp32
  int e = 0;
  if (big > 0.0 && !isinf(big)) frexp(big, e);
  float scale = uintBitsToFloat(uint(127 - clamp(e, -126, 126)) << 23);
  // `precise`: the compiler may not factor the scale out of the sums
  // (a s + b s -> (a + b) s, which NIR does to inexact arithmetic).
  precise vec3 mean = vec3(0.0);
  for (int k = 0; k < 9; ++k) mean += nb[k] * scale;
  mean /= 9.0;
  precise vec3 var = vec3(0.0);
  for (int k = 0; k < 9; ++k) {
    precise vec3 d = nb[k] * scale - mean;
    var += d * d;
  }
  precise vec3 sigma = sqrt(var / 9.0) / scale;
  mean /= scale;
  mean_out = mean;
  sigma_out = sigma;
}

// The 3x3 around p: its box, its moments, the motion to follow and the nearest surface.
Neighbourhood neighbourhood(ivec2 p, vec3 centre_rgb) {
  Neighbourhood nh;
  vec3 cur = box_colour(centre_rgb);
  vec3 lo = cur, hi = cur;
  vec3 nb[9];
  vec4 mc = fetch(motion_tex, p);
  vec2 v = mc.xy;
  float best_d = mc.z > 0.0 ? mc.z : 3.4e38, best_len = dot(mc.xy, mc.xy);
  nb[4] = cur;  // the centre: its colour and motion are fetched above (on llvmpipe a fetch is ~3 % of the resolve)
  vec4 near = mc;  // the nearest surface of the 3x3 (the centre first: ties keep it)
  if (!(near.z > 0.0)) near = vec4(0.0);
#if TAA_QUAD_SHARE
  ivec2 out_dir = 2 * (p & 1) - 1;  // away from the centre of this pixel's quad
  vec3 qc[3][3];
  vec4 qm[3][3];
  QUAD_NEIGHBOURHOOD(vec3, p, cur, fetch_box_colour, out_dir, qc)
  QUAD_NEIGHBOURHOOD(vec4, p, mc, fetch_motion, out_dir, qm)
#endif
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;  // the initial values above: the same box, and no longer motion
#if TAA_QUAD_SHARE
      vec3 s = qc[dy + 1][dx + 1];
      vec4 mo = qm[dy + 1][dx + 1];
#else
      ivec2 o = p + ivec2(dx, dy);
      vec3 s = box_colour(resolved_rgb(o));
      vec4 mo = fetch(motion_tex, o);
#endif
      lo = min(lo, s);
      hi = max(hi, s);
      nb[(dy + 1) * 3 + dx + 1] = s;
#if TAA_VELOCITY == VELOCITY_CLOSEST_DEPTH
      float d = mo.z > 0.0 ? mo.z : 3.4e38;  // the sky is farthest
      if (d < best_d) { best_d = d; v = mo.xy; }
#elif TAA_VELOCITY == VELOCITY_LONGEST
      float l = dot(mo.xy, mo.xy);
      if (l > best_len) { best_len = l; v = mo.xy; }
#endif
#if TAA_DISOCCLUSION
      if (mo.z > 0.0 && (!(near.z > 0.0) || mo.z < near.z)) near = mo;
#endif
    }
  moments(nb, lo, hi, nh.mean, nh.sigma);
  nh.cur = cur;
  nh.lo = lo;
  nh.hi = hi;
  nh.mc = mc;
  nh.v = v;
  nh.near = near;
  return nh;
}

// ---- step 3: the history rectified against the box (TAA_CLAMP); the variance clamp's box becomes the
// box the feedback reads.
vec3 rectify(vec3 raw, inout Neighbourhood nh, float gamma) {
  vec3 h = raw;
#if TAA_CLAMP == CLAMP_MINMAX
  h = clamp(raw, nh.lo, nh.hi);
#elif TAA_CLAMP == CLAMP_CLIP
  h = clip_to_box(raw, nh.lo, nh.hi);
#elif TAA_CLAMP == CLAMP_VARIANCE
  vec3 vlo = nh.mean - gamma * nh.sigma, vhi = nh.mean + gamma * nh.sigma;
  nh.lo = vlo;
  nh.hi = vhi;
  h = clamp(raw, vlo, vhi);
#endif
  return h;
}

// ---- step 4: the weight of the current frame (TAA_FEEDBACK).
float feedback(vec3 cur, vec3 h, vec3 lo, vec3 hi, float alpha) {
#if TAA_FEEDBACK == FEEDBACK_LUMA
  float L0 = space_luma(cur), L1 = space_luma(h);
  float k = 1.0 - abs(L0 - L1) / max(max(L0, L1), 0.2);
  return 1.0 - mix(0.88, 0.97, k * k);
#elif TAA_FEEDBACK == FEEDBACK_KARIS
  float hl = space_luma(h), blo = space_luma(lo), bhi = space_luma(hi);
  float d = min(abs(hl - blo), abs(bhi - hl)), range = max(bhi - blo, 0.0);
  return d + range > 0.0 ? clamp(alpha * d / (d + range), 0.0, 1.0) : alpha;
#else
  return alpha;
#endif
}

#if TAA_ANTI_FLICKER
// Luma instability (FSR2; UE5 TSR ShadingRejection.Flickering): the last three lumas of this surface
// point and the current one; where successive changes alternate in sign and are large against the
// luma, the pixel oscillates and keeps more of its unrectified history. Returns the lumas to keep.
vec4 anti_flicker(vec2 q, vec3 cur, vec3 raw, inout vec3 h, inout float a) {
  vec4 lh = texelFetch(luma_tex, ivec2(clamp(floor(q), vec2(0.0), vec2(g_size - 1))), 0);
  float Lc = space_luma(cur);
  float d1 = lh.y - lh.x, d2 = lh.z - lh.y, d3 = Lc - lh.z;
  float big = 0.1 * max(max(lh.x, lh.y), max(lh.z, Lc)) + 1e-6;
  float alternations = (d1 * d2 < 0.0 && min(abs(d1), abs(d2)) > big ? 1.0 : 0.0) +
                       (d2 * d3 < 0.0 && min(abs(d2), abs(d3)) > big ? 1.0 : 0.0);
  float s = lh.w >= 3.0 ? 0.5 * alternations : 0.0;  // needs three remembered lumas
  h = mix(h, raw, s);
  a *= 1.0 - 0.5 * s;
  return vec4(lh.y, lh.z, Lc, min(lh.w + 1.0, 3.0));
}
#endif

#if TAA_GLINT_LAYER
// The glint layer under its own rule, with the base's validity (q, disocclusion) and filter; n the
// frames accumulated (TAA_ACCUMULATE).
vec3 resolve_glint_layer(ivec2 p, vec2 q, bool valid, vec3 g_cur, float n) {
  vec3 g_out = g_cur;
  if (valid) {
    Taps kg = taps_2x2(extra_tex, q);
#if TAA_FILTER == FILTER_CATMULL_ROM
    vec3 g_hist = catmull_rom(extra_tex, kg);
#else
    vec3 g_hist = max(bilinear(kg), vec3(0.0));
#endif
#if TAA_GLINT_CLAMP == 1
    vec3 g_lo = g_cur, g_hi = g_cur;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        vec3 gs = fetch(glint_tex, p + ivec2(dx, dy)).rgb;
        g_lo = min(g_lo, gs);
        g_hi = max(g_hi, gs);
      }
    g_hist = clamp(g_hist, g_lo, g_hi);
#endif
    float ag = glint_weights.y;
#if TAA_ACCUMULATE
    ag = max(ag, 1.0 / n);
#endif
    if (finite3(g_hist)) g_out = mix(g_hist, g_cur, ag);
  }
  return g_out;
}
#endif

void main() {
  g_size = ivec2(size_alpha_gamma.xy);
  ivec2 p = ivec2(gl_FragCoord.xy);  // the pixel: the viewport is the image
  float alpha = size_alpha_gamma.z, gamma = size_alpha_gamma.w;
  bool valid = history_jitter.x > 0.5;

  // ---- current neighbourhood (HDR-mapped, in box space) and motion
  vec4 centre_px = fetch(color_tex, p);
#if TAA_GLINT
  vec4 glint_px = fetch(glint_tex, p);
  float share = clamp(glint_px.a, 0.0, 1.0);  // NaN -> 0: no glint-aware change where the layer is undefined
#endif
#if TAA_GLINT_LAYER
  vec3 centre_rgb = centre_px.rgb - glint_px.rgb;
#else
  vec3 centre_rgb = centre_px.rgb;
#endif
  Neighbourhood nh = neighbourhood(p, centre_rgb);
  vec3 cur = nh.cur;

  // ---- step 2: reprojection and validity
  vec2 q = vec2(p) + 0.5 - nh.v;
  bool on_screen = all(greaterThanEqual(q, vec2(0.0))) && all(lessThanEqual(q, vec2(g_size))) && finite3(vec3(q, 0.0));
  if (!on_screen) valid = false;
#if TAA_DISOCCLUSION
  if (valid) valid = same_surface(nh.near, vec2(p) + 0.5 - nh.near.xy + history_jitter.zw, history_jitter.y);
#endif
  vec3 hist_lin = vec3(0.0);
  if (valid) {
    Taps k = taps_2x2(history_tex, q);
#if TAA_FILTER == FILTER_CATMULL_ROM
    hist_lin = catmull_rom(history_tex, k);
#else
    hist_lin = bilinear(k);
#endif
    valid = finite3(hist_lin);
  }

#if TAA_EXTRA
  // The frames accumulated at the reprojected point (nearest texel), this one included.
  float n = valid ? min(texelFetch(extra_tex, ivec2(clamp(floor(q), vec2(0.0), vec2(g_size - 1))), 0).a, 1e6) + 1.0
                  : 1.0;
  if (!(n >= 1.0)) n = 1.0;  // NaN in the history: restart the count
#endif
  // ---- steps 3 and 4: rectify and blend
  vec3 result = cur;
  vec4 lumas = vec4(0.0);
  if (valid) {
    vec3 raw = box_colour(hist_lin);
    vec3 h = rectify(raw, nh, gamma);
    float a = feedback(cur, h, nh.lo, nh.hi, alpha);
#if TAA_ANTI_FLICKER
    lumas = anti_flicker(q, cur, raw, h, a);
#endif
#if TAA_ACCUMULATE
    a = max(a, 1.0 / n);
#endif
#if TAA_GLINT_LOCK
    if (share > 0.5 && space_luma(raw) >= 0.5 * space_luma(cur)) h = raw;
#endif
#if TAA_REACTIVE
    float r = glint_weights.x * share;
    h = mix(h, raw, r);
    a = mix(a, 1.0, r);
#endif
    result = mix(h, cur, a);
  }
#if TAA_ANTI_FLICKER
  if (!valid) lumas = vec4(0.0, 0.0, space_luma(cur), 1.0);
#endif

  vec3 lin = max(hdr_inverse(max(from_space(result), vec3(0.0))), vec3(0.0));
  if (!finite3(lin)) lin = max(centre_rgb, vec3(0.0));
  // A current sample that is NaN or infinite is a defect of the frame: passed through as it is, so the
  // frame's scan counts it (the clamps above would turn it into 0 and hide it); the history restarts
  // from it being non-finite.
  if (!finite3(centre_px.rgb)) lin = centre_px.rgb;
#if TAA_GLINT_LAYER
  vec3 g_out = resolve_glint_layer(p, q, valid, glint_px.rgb, n);
  vec3 base_lin = lin;
  lin = base_lin + g_out;
  if (!finite3(lin)) lin = max(centre_px.rgb, vec3(0.0));
  if (!finite3(centre_px.rgb)) lin = centre_px.rgb;
  vec3 history_rgb = base_lin;
#else
  vec3 history_rgb = lin;
#endif
  out_color = vec4(lin, centre_px.a);
#if TAA_DISOCCLUSION
  out_history = vec4(history_rgb, nh.near.z);
#else
  out_history = vec4(history_rgb, nh.mc.z);
#endif
#if TAA_EXTRA
#if TAA_GLINT_LAYER
  out_extra = vec4(finite3(g_out) ? g_out : vec3(0.0), n);
#else
  out_extra = vec4(0.0, 0.0, 0.0, n);
#endif
#endif
#if TAA_ANTI_FLICKER
  out_luma = lumas;
#endif
}

// Falcor's TAA (RenderPasses/Antialiasing/TAA) with every design choice of the TAA literature as a
// parameter or option, and glintlab's glint-aware options. The defaults are Falcor's pass: alpha 0.1,
// clamp to mean +- 1.0 sigma over 3x3 in YCoCg, Catmull-Rom history, the longest motion vector in 3x3,
// Karis' alpha' = alpha d / (d + box range) near the box edge, no HDR weighting, no depth test (the
// jitter, Halton(2,3) x16 by default, is the variant's: "taa": {"jitter": ...}).
//
// taa_resolve checks=finite,deterministic,ghosting,cut,pan,flicker fails=converges
// It fails `converges` by design: Karis' feedback gives the history all the weight where it lies on
// the edge of the box, and the variance box of one jittered sample per pixel rejects the history at
// high-contrast edges, so a static view stays near one sample's error there (taa-test: CIEDE2000 7.4x
// that of 8x8 supersampling after 64 frames; with `accumulate` and `clamp` none it converges).
//
// History rectification: none (ghosts; converges to the mean under a static camera), minmax (the 3x3
// min/max box, UE4's "YCoCg min/max box"), clip (toward the box centre, INSIDE / Playdead), variance
// (mean +- gamma sigma over 3x3, Salvi 2016; Falcor gamma 1.0, UE4 1.25).
// taa_option clamp=none|minmax|clip|variance default=variance
// taa_parameter gamma default=1 range=0,100
// The weight of the current frame, (0, 1].
// taa_parameter alpha default=0.1 range=0.0001,1
// The colour space of the neighbourhood box (YCoCg: Y = r/4 + g/2 + b/4).
// taa_option space=rgb|ycocg default=ycocg
// How the history is resampled at the reprojected position: 4 taps, or Falcor's Catmull-Rom.
// taa_option history_filter=bilinear|catmull_rom default=catmull_rom
// Clamp the Catmull-Rom history to the range of the 2x2 texels around the reprojected point (FSR2's
// deringing of its Lanczos history). Without it the filter's negative lobes ring next to a bright HDR
// glint: the history falls to 0 (it is floored there), the variance box of a glinting neighbourhood is
// too wide to lift it, and black pixels appear beside glints (seen in the default experiment, whose TAA
// variants turn it on). Off by default so that the defaults stay Falcor's exactly. No effect with the
// bilinear filter, which cannot overshoot.
// taa_parameter dering default=false
// Which motion vector reprojects the pixel: its own, that of the nearest surface in 3x3 (INSIDE), the
// longest in 3x3 (Falcor).
// taa_option velocity=center|closest_depth|longest default=longest
// The weight of the current frame in the blend: alpha; INSIDE / Lottes' history weight
// lerp(0.88, 0.97, (1 - |L0 - L1| / max(L0, L1, 0.2))^2); Falcor's alpha' = alpha d / (d + box range),
// d the luma distance of the history to the nearer box edge.
// taa_option feedback=fixed|luma|karis default=karis
// HDR handling, applied before the box statistics and the blend and inverted after: none; c / (1 + L)
// (Karis 2014, "High-quality temporal supersampling"); c / (max(r, g, b) + 1) (FSR2).
// taa_option hdr=none|inverse_luma|tonemap default=none
// A luma-oscillation guard (FSR2 "luma instability", UE5 TSR "ShadingRejection.Flickering"): pixels
// whose luma alternated in sign over the last frames keep more of their unrectified history.
// taa_parameter anti_flicker default=false
// The disocclusion test (not in Falcor's pass, which relies on the rectification alone): the history
// restarts where the nearest surface of the pixel's 3x3 was not where the history holds it
// (same_surface below: FSR2's dilated depth and reconstructed previous depth), beyond a relative
// distance mismatch of disocclusion_tolerance past the local slope.
// taa_parameter disocclusion default=false
// taa_parameter disocclusion_tolerance default=0.05 range=0.0001,10 requires=disocclusion
//
// The glint-aware options read the surface pass's glint layer G (rgb = the glint term's part of the
// pixel's radiance, a = its share s of the luma); all off by default, and then none of their code is
// compiled and the glint layer is not rendered:
// Accumulation schedule: alpha' = max(alpha', 1/n), n = frames accumulated at the pixel since its history
// last restarted (kept in the state, read at the nearest texel), so a static view averages its first
// 1/alpha frames with equal weights, as supersampling does (Yang et al. 2009, "Amortized supersampling").
// taa_parameter accumulate default=false
// Reactive mask from the material (FSR2's reactive mask, computed rather than authored): r = reactive s;
// h = mix(h, raw history, r) (the rectification relaxed: a glint is an outlier of its 3x3 box, so the
// box cannot tell a valid glint history from a ghost) and alpha' = mix(alpha', 1, r) (the history weight
// lowered by 1 - r, so what is kept unrectified is kept briefly and cannot trail).
// taa_parameter reactive default=0 range=0,1
// Layer separation: colour - G goes through the resolve (its box statistics then see no glints); G apart:
// G_out = mix(G_hist, G, glint_alpha) (with accumulate: max(glint_alpha, 1/n)), G_hist the same resample
// of the glint history under the same validity, rectified by glint_clamp (none, or the min/max of the 3x3
// current G); out = colour' + G_out.
// taa_parameter glint_layer default=false
// taa_parameter glint_alpha default=0.5 range=0.0001,1 requires=glint_layer
// taa_option glint_clamp=none|minmax default=none requires=glint_layer
// Glint locks (after FSR2's locks on thin features): where s > 1/2 and the raw history's luma is at least
// half the current one (the glint persisted along the motion), the history is not rectified.
// taa_parameter glint_lock default=false
//
// Per pixel p (centre c = p + 0.5):
//   1. v = the motion vector `velocity` chooses; the history is at q = c - v.
//   2. History is invalid (the pixel restarts from the current colour) without history, when q is
//      off-screen, when the resampled history is not finite and, with `disocclusion`, where the surface
//      the history holds is not the one seen now.
//   3. Samples are mapped for HDR, then to the box space; the history is rectified against the 3x3.
//   4. out = mix(history, current, alpha'), mapped back to linear radiance, clamped to >= 0.
// Kept: history = the resolved colour (without its glints with glint_layer); state = (the distance of
// the nearest surface of the 3x3, n, 0, 0); state2 = the last lumas (anti_flicker); history2 = the glint
// layer's history (glint_layer).

#define FALCOR_GLINT (TAA_ON_reactive || TAA_ON_glint_layer || TAA_ON_glint_lock)
#define FALCOR_STATE (TAA_ON_disocclusion || TAA_ON_accumulate)

// Hooks for a resolve that extends this one (taa_resolve extends=falcor; taau.glsl): it defines them
// before including this file. FALCOR_BEGIN(px) runs first in taa_resolve; the current colour and
// glint layer at the pixel, those of neighbour o (the 3x3 box, the motion to follow), and the weight
// this frame's sample adds to the count n of `accumulate` (1: one sample at the pixel).
#ifndef FALCOR_BEGIN
#define FALCOR_BEGIN(px)
#endif
#ifndef FALCOR_CURRENT_RGB
#define FALCOR_CURRENT_RGB() taa_current(ivec2(0))
#endif
#ifndef FALCOR_CURRENT_GLINT
#define FALCOR_CURRENT_GLINT() taa_glint(ivec2(0))
#endif
#ifndef FALCOR_NEIGHBOUR_RGB
#define FALCOR_NEIGHBOUR_RGB(o) taa_current(o)
#endif
#ifndef FALCOR_NEIGHBOUR_GLINT
#define FALCOR_NEIGHBOUR_GLINT(o) taa_glint(o)
#endif
#ifndef FALCOR_NEIGHBOUR_MOTION
#define FALCOR_NEIGHBOUR_MOTION(o) vec4(taa_motion(o), taa_distance(o), taa_distance_prev(o))
#endif
#ifndef FALCOR_SAMPLE_WEIGHT
#define FALCOR_SAMPLE_WEIGHT() 1.0
#endif

float luma(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }  // Rec. 709 luma of linear rgb

// HDR mapping (Karis 2014; FSR2) and its inverse; both keep colours >= 0 finite.
vec3 hdr_forward(vec3 c) {
#if TAA_hdr == TAA_hdr_inverse_luma
  return c / (1.0 + max(luma(c), 0.0));
#elif TAA_hdr == TAA_hdr_tonemap
  return c / (max(max(c.r, c.g), max(c.b, 0.0)) + 1.0);
#else
  return c;
#endif
}
vec3 hdr_inverse(vec3 c) {
#if TAA_hdr == TAA_hdr_inverse_luma
  return c / max(1.0 - luma(c), 1e-6);
#elif TAA_hdr == TAA_hdr_tonemap
  return c / max(1.0 - max(max(c.r, c.g), c.b), 1e-6);
#else
  return c;
#endif
}

// Box space: rgb, or YCoCg (its first channel is luma-like).
vec3 to_space(vec3 c) {
#if TAA_space == TAA_space_ycocg
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b, -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
#else
  return c;
#endif
}
vec3 from_space(vec3 y) {
#if TAA_space == TAA_space_ycocg
  return vec3(y.x + y.y - y.z, y.x + y.z, y.x - y.y - y.z);
#else
  return y;
#endif
}
// The luma of a box-space colour.
float space_luma(vec3 y) {
#if TAA_space == TAA_space_ycocg
  return y.x;
#else
  return luma(y);
#endif
}

// The colour steps 1-4 resolve: the frame's, or with the layers separated, the frame's without its glints.
vec3 resolved_rgb(ivec2 o) {
#if TAA_ON_glint_layer
  return FALCOR_NEIGHBOUR_RGB(o) - FALCOR_NEIGHBOUR_GLINT(o).rgb;
#else
  return FALCOR_NEIGHBOUR_RGB(o);
#endif
}

// A colour as the neighbourhood box sees it: HDR-mapped, in box space.
vec3 box_colour(vec3 c) { return to_space(hdr_forward(max(c, vec3(0.0)))); }

vec4 motion_texel(ivec2 o) { return FALCOR_NEIGHBOUR_MOTION(o); }

#if TAA_QUAD_SHARE
// The 3x3 neighbourhood of every pixel of a 2x2 quad lies in the quad's 4x4 block of texels: each pixel
// fetches the 2x2 of it on its own side (itself and its neighbours away from the quad's centre,
// o = (+-1, +-1)) and takes the five on the other side from the quad's other pixels, whose own fetches
// they are (a quad swap: the same texel, the same arithmetic, so the same bits). 4 fetches of colour and
// 4 of motion a pixel instead of 9 + 9; on llvmpipe a fetch costs about 3 % of the resolve. The host sets
// TAA_QUAD_SHARE only where every quad is whole. T is vec3 (colours) or vec4 (motion).
#define QUAD_NEIGHBOURHOOD(T, centre, fetch_box, o, N)                                      \
  {                                                                                         \
    T x_ = fetch_box(ivec2(o.x, 0)), y_ = fetch_box(ivec2(0, o.y)), xy_ = fetch_box(o);     \
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
vec3 fetch_box_colour(ivec2 o) { return box_colour(resolved_rgb(o)); }
#endif

// The history of `history2` or not, at q, by the `history_filter`; Catmull-Rom deringed to the range of
// the 2x2 texels around q (with `dering`) and floored at 0 (its negative lobes can ring below zero).
vec3 resample(vec2 q, bool second) {
#if TAA_history_filter == TAA_history_filter_catmull_rom
#if TAA_ON_glint_layer
  vec3 r = second ? taa_history2(q, TAA_CATMULL_ROM) : taa_history(q, TAA_CATMULL_ROM);
#else
  vec3 r = taa_history(q, TAA_CATMULL_ROM);
#endif
#if TAA_ON_dering
  vec2 c0 = floor(q - 0.5) + 0.5;
  vec3 a, b, c, d;
#if TAA_ON_glint_layer
  if (second) {
    a = taa_history2(c0, TAA_NEAREST);
    b = taa_history2(c0 + vec2(1.0, 0.0), TAA_NEAREST);
    c = taa_history2(c0 + vec2(0.0, 1.0), TAA_NEAREST);
    d = taa_history2(c0 + vec2(1.0, 1.0), TAA_NEAREST);
  } else
#endif
  {
    a = taa_history(c0, TAA_NEAREST);
    b = taa_history(c0 + vec2(1.0, 0.0), TAA_NEAREST);
    c = taa_history(c0 + vec2(0.0, 1.0), TAA_NEAREST);
    d = taa_history(c0 + vec2(1.0, 1.0), TAA_NEAREST);
  }
  r = clamp(r, min(min(a, b), min(c, d)), max(max(a, b), max(c, d)));
#endif
  return max(r, vec3(0.0));
#else
#if TAA_ON_glint_layer
  return second ? max(taa_history2(q, TAA_BILINEAR), vec3(0.0)) : taa_history(q, TAA_BILINEAR);
#else
  return taa_history(q, TAA_BILINEAR);
#endif
#endif
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

#if TAA_ON_disocclusion
// The disocclusion test: does the history hold the surface seen now? The state keeps the distance of
// the nearest surface of its pixel's 3x3 (0: all sky), and the test takes the nearest surface of the 3x3
// now. With the nearest of the neighbourhood (FSR2's dilated depth), an edge pixel's distance is the near
// side's in every frame, whichever side its jittered sample hit, so a ridge or silhouette keeps its
// history and converges like supersampling. The nearest pixel's own motion and previous distance say
// where that surface was and how far (FSR2's reconstructed previous depth).
//
// The kept distances are point samples at last frame's jittered positions. The test reads them where
// the point was among those samples: q_n (the pixel centre moved back by the nearest's motion) plus the
// change of jitter j_{t-1} - j_t (the camera of frame t sees at pixel centre c the point whose unjittered
// position is c - j_t, core/scene/camera.h; texel i of the history sampled i + 1/2 - j_{t-1}). Between
// samples on one surface the distance lies between theirs, however fast it changes (toward a horizon it
// changes by 5-100 % from one pixel to the next): the point's previous distance must lie within the range
// of the bilinear taps around that position (those of weight > 0), widened by the relative tolerance.
// The sky counts as infinitely far: a tap of sky leaves the range open above, and a pixel with no surface
// in its 3x3 needs a tap of sky. near: the motion texel of the nearest surface of the 3x3 (z = 0 where
// there is none); u: q_n plus the jitter change.
bool same_surface(vec4 near, vec2 u, float tol) {
  // Off the image by more than a pixel (or not finite): the surface was not seen.
  if (!(all(greaterThanEqual(u, vec2(-1.0))) && all(lessThanEqual(u, vec2(taa_size()) + 1.0)))) return false;
  vec2 qq = clamp(u, vec2(0.5), vec2(taa_size()) - 0.5) - 0.5;
  vec2 c0 = floor(qq) + 0.5, f = qq - floor(qq);
  vec4 held = vec4(taa_state(c0).x, taa_state(c0 + vec2(1.0, 0.0)).x, taa_state(c0 + vec2(0.0, 1.0)).x,
                   taa_state(c0 + vec2(1.0, 1.0)).x);
  bvec4 tap = bvec4(true, f.x > 0.0, f.y > 0.0, f.x > 0.0 && f.y > 0.0);  // bilinear weight > 0
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
  vec2 v;            // the motion `velocity` chose
  vec4 near;         // the motion texel of the nearest surface of the 3x3 (disocclusion; z = 0: none)
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

// The 3x3 around the pixel: its box, its moments, the motion to follow and the nearest surface.
Neighbourhood neighbourhood(ivec2 p, vec3 centre_rgb) {
  Neighbourhood nh;
  vec3 cur = box_colour(centre_rgb);
  vec3 lo = cur, hi = cur;
  vec3 nb[9];
  vec4 mc = motion_texel(ivec2(0));
  vec2 v = mc.xy;
  float best_d = mc.z > 0.0 ? mc.z : 3.4e38, best_len = dot(mc.xy, mc.xy);
  nb[4] = cur;  // the centre: its colour and motion are fetched above (on llvmpipe a fetch is ~3 % of the resolve)
  vec4 near = mc;  // the nearest surface of the 3x3 (the centre first: ties keep it)
  if (!(near.z > 0.0)) near = vec4(0.0);
#if TAA_QUAD_SHARE
  ivec2 out_dir = 2 * (p & 1) - 1;  // away from the centre of this pixel's quad
  vec3 qc[3][3];
  vec4 qm[3][3];
  QUAD_NEIGHBOURHOOD(vec3, cur, fetch_box_colour, out_dir, qc)
  QUAD_NEIGHBOURHOOD(vec4, mc, motion_texel, out_dir, qm)
#endif
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;  // the initial values above: the same box, and no longer motion
#if TAA_QUAD_SHARE
      vec3 s = qc[dy + 1][dx + 1];
      vec4 mo = qm[dy + 1][dx + 1];
#else
      ivec2 o = ivec2(dx, dy);
      vec3 s = box_colour(resolved_rgb(o));
      vec4 mo = motion_texel(o);
#endif
      lo = min(lo, s);
      hi = max(hi, s);
      nb[(dy + 1) * 3 + dx + 1] = s;
#if TAA_velocity == TAA_velocity_closest_depth
      float d = mo.z > 0.0 ? mo.z : 3.4e38;  // the sky is farthest
      if (d < best_d) { best_d = d; v = mo.xy; }
#elif TAA_velocity == TAA_velocity_longest
      float l = dot(mo.xy, mo.xy);
      if (l > best_len) { best_len = l; v = mo.xy; }
#endif
#if TAA_ON_disocclusion
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

// ---- step 3: the history rectified against the box; the variance clamp's box becomes the box the
// feedback reads.
vec3 rectify(vec3 raw, inout Neighbourhood nh, float gamma) {
  vec3 h = raw;
#if TAA_clamp == TAA_clamp_minmax
  h = clamp(raw, nh.lo, nh.hi);
#elif TAA_clamp == TAA_clamp_clip
  h = clip_to_box(raw, nh.lo, nh.hi);
#elif TAA_clamp == TAA_clamp_variance
  vec3 vlo = nh.mean - gamma * nh.sigma, vhi = nh.mean + gamma * nh.sigma;
  nh.lo = vlo;
  nh.hi = vhi;
  h = clamp(raw, vlo, vhi);
#endif
  return h;
}

// ---- step 4: the weight of the current frame.
float feedback(vec3 cur, vec3 h, vec3 lo, vec3 hi, float alpha) {
#if TAA_feedback == TAA_feedback_luma
  float L0 = space_luma(cur), L1 = space_luma(h);
  float k = 1.0 - abs(L0 - L1) / max(max(L0, L1), 0.2);
  return 1.0 - mix(0.88, 0.97, k * k);
#elif TAA_feedback == TAA_feedback_karis
  float hl = space_luma(h), blo = space_luma(lo), bhi = space_luma(hi);
  float d = min(abs(hl - blo), abs(bhi - hl)), range = max(bhi - blo, 0.0);
  return d + range > 0.0 ? clamp(alpha * d / (d + range), 0.0, 1.0) : alpha;
#else
  return alpha;
#endif
}

#if TAA_ON_anti_flicker
// Luma instability (FSR2; UE5 TSR ShadingRejection.Flickering): the last three lumas of this surface
// point and the current one; where successive changes alternate in sign and are large against the
// luma, the pixel oscillates and keeps more of its unrectified history. Returns the lumas to keep.
vec4 anti_flicker(vec2 q, vec3 cur, vec3 raw, inout vec3 h, inout float a) {
  vec4 lh = taa_state2(q);
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

#if TAA_ON_glint_layer
// The glint layer under its own rule, with the base's validity (q, disocclusion) and filter; n the
// frames accumulated (accumulate).
vec3 resolve_glint_layer(vec2 q, bool valid, vec3 g_cur, float n, float glint_alpha) {
  vec3 g_out = g_cur;
  if (valid) {
    vec3 g_hist = resample(q, true);
#if TAA_glint_clamp == TAA_glint_clamp_minmax
    vec3 g_lo = g_cur, g_hi = g_cur;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        vec3 gs = FALCOR_NEIGHBOUR_GLINT(ivec2(dx, dy)).rgb;
        g_lo = min(g_lo, gs);
        g_hi = max(g_hi, gs);
      }
    g_hist = clamp(g_hist, g_lo, g_hi);
#endif
    float ag = glint_alpha;
#if TAA_ON_accumulate
    ag = max(ag, FALCOR_SAMPLE_WEIGHT() / n);
#endif
    if (finite3(g_hist)) g_out = mix(g_hist, g_cur, ag);
  }
  return g_out;
}
#endif

TaaResult taa_resolve(TaaPixel px) {
  FALCOR_BEGIN(px)
  ivec2 p = px.pixel;
  bool valid = px.history_valid;

  // ---- current neighbourhood (HDR-mapped, in box space) and motion
  vec3 centre_px = FALCOR_CURRENT_RGB();
#if FALCOR_GLINT
  vec4 glint_px = FALCOR_CURRENT_GLINT();
  float share = clamp(glint_px.a, 0.0, 1.0);  // NaN -> 0: no glint-aware change where the layer is undefined
#endif
#if TAA_ON_glint_layer
  vec3 centre_rgb = centre_px - glint_px.rgb;
#else
  vec3 centre_rgb = centre_px;
#endif
  Neighbourhood nh = neighbourhood(p, centre_rgb);
  vec3 cur = nh.cur;

  // ---- step 2: reprojection and validity
  vec2 q = vec2(p) + 0.5 - nh.v;
  if (!taa_in_frame(q)) valid = false;
#if TAA_ON_disocclusion
  if (valid) valid = same_surface(nh.near, vec2(p) + 0.5 - nh.near.xy + (px.jitter_prev - px.jitter),
                                  px.disocclusion_tolerance);
#endif
  vec3 hist_lin = vec3(0.0);
  if (valid) {
    hist_lin = resample(q, false);
    valid = finite3(hist_lin);
  }

  float n = 1.0;
#if TAA_ON_accumulate
  // The frames accumulated at the reprojected point (nearest texel), this one included (each frame's
  // sample counts FALCOR_SAMPLE_WEIGHT: 1 here).
  float w_sample = FALCOR_SAMPLE_WEIGHT();
  n = w_sample;
  if (valid) n = min(taa_state(q).y, 1e6) + w_sample;
  if (!(n >= w_sample)) n = w_sample;  // NaN in the history: restart the count
#endif
  // ---- steps 3 and 4: rectify and blend
  vec3 result = cur;
  vec4 lumas = vec4(0.0);
  if (valid) {
    vec3 raw = box_colour(hist_lin);
    vec3 h = rectify(raw, nh, px.gamma);
    float a = feedback(cur, h, nh.lo, nh.hi, px.alpha);
#if TAA_ON_anti_flicker
    lumas = anti_flicker(q, cur, raw, h, a);
#endif
#if TAA_ON_accumulate
    // (a frame whose sample weight w is below 1 takes only that share of alpha' too, and one of weight 0,
    // which saw nothing of the pixel, leaves the history as it is)
    a = max(a * w_sample, w_sample / max(n, 1e-6));
#endif
#if TAA_ON_glint_lock
    if (share > 0.5 && space_luma(raw) >= 0.5 * space_luma(cur)) h = raw;
#endif
#if TAA_ON_reactive
    float r = px.reactive * share;
    h = mix(h, raw, r);
    a = mix(a, 1.0, r);
#endif
    result = mix(h, cur, a);
  }
#if TAA_ON_anti_flicker
  if (!valid) lumas = vec4(0.0, 0.0, space_luma(cur), 1.0);
#endif

  vec3 lin = max(hdr_inverse(max(from_space(result), vec3(0.0))), vec3(0.0));
  if (!finite3(lin)) lin = max(centre_rgb, vec3(0.0));
  // A current sample that is NaN or infinite is a defect of the frame: passed through as it is, so the
  // frame's scan counts it (the clamps above would turn it into 0 and hide it); the history restarts
  // from it being non-finite.
  if (!finite3(centre_px)) lin = centre_px;
  TaaResult res = taa_result(lin);
#if TAA_ON_glint_layer
  vec3 g_out = resolve_glint_layer(q, valid, glint_px.rgb, n, px.glint_alpha);
  res.color = lin + g_out;
  if (!finite3(res.color)) res.color = max(centre_px, vec3(0.0));
  if (!finite3(centre_px)) res.color = centre_px;
  res.history2 = finite3(g_out) ? g_out : vec3(0.0);
#endif
  res.state = vec4(nh.near.z, n, 0.0, 0.0);
  res.state2 = lumas;
  return res;
}

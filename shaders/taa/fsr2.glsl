// AMD FidelityFX Super Resolution 2, written from its public documentation ("The technique", FSR 2.3
// docs, sections cited as [Section]) in glintlab's own code, as one resolve run once per output pixel.
// Each documented stage is a step below; where one pass per output pixel cannot do what the
// documented pass does, the simplification is named (SIMPLIFICATION).
//
// taa_resolve checks=finite,deterministic,ghosting,cut,pan,flicker fails=converges
//
// [Depth clip]: the relative distance change beyond which a surface counts as disoccluded (FSR 2 uses
// the Akeley separation of its depth buffer; glintlab has distances).
// taa_parameter depth_separation default=0.05 range=0.001,1
// [Reproject & accumulate]: the most history weight a pixel accumulates, in samples ("FSR2 will
// typically blend the current frame with a relatively low linear interpolation factor").
// taa_parameter max_accumulation default=16 range=1,256
// [Create locks]: a render texel whose luma stands out of its 3x3 neighbourhood by this share of the
// neighbourhood's range is a thin feature and gets a lock.
// taa_parameter lock_threshold default=0.5 range=0,1
// [Reproject & accumulate], shading change: a lock whose luma moved by more than this share of the
// larger is dropped.
// taa_parameter lock_shading_change default=0.25 range=0,1
//
// SIMPLIFICATIONS, all named:
// - [Compute luminance pyramid]: no auto exposure (exposure 1: the local tonemap below keeps HDR
//   bounded without it); the shading change detection compares lumas of this frame and the lock's.
// - [Reconstruct & dilate]: FSR 2 scatters each depth along its dilated motion with atomics to
//   estimate the previous depth; a resolve run per output pixel cannot scatter, and glintlab's motion
//   target carries each surface point's exact distance in the previous frame
//   (taa_render_distance_prev), which is what that scatter estimates.
// - [Reproject & accumulate]: the history is resampled with the host's Catmull-Rom (16 texels)
//   rather than Lanczos-2 (the documentation notes the kernel "may vary by GPU product"); the
//   upsampling of the current frame is Lanczos-2 as documented.
// - The reactive and transparency & composition masks: FSR 2 generates them from the difference of
//   an opaque-only and a composited colour buffer; glintlab's scenes have no alpha-blended objects, so
//   the generated masks are zero everywhere and are not computed.
// - [Robust Contrast Adaptive Sharpening]: not applied. It sharpens the presentation buffer only (the
//   history FSR 2 keeps is the unsharpened output), and needs the neighbours' outputs: a second pass.
//
// Kept: history = the accumulated colour (linear); state = (accumulated weight, the nearest distance
// of the 3x3 render texels, lock lifetime, lock luma); state2 = the last three lumas and their count
// (luma instability).

float fsr2_luma(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// [Depth clip] "Adjusted color buffer ... a local, reversible operator ... stored in YCoCg".
vec3 fsr2_tonemap(vec3 c) { return c / (max(max(c.r, c.g), max(c.b, 0.0)) + 1.0); }
vec3 fsr2_inverse_tonemap(vec3 c) { return c / max(1.0 - max(max(c.r, c.g), c.b), 1e-6); }
vec3 fsr2_to_ycocg(vec3 c) {
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b, -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}
vec3 fsr2_from_ycocg(vec3 y) { return vec3(y.x + y.y - y.z, y.x + y.z, y.x - y.y - y.z); }
vec3 fsr2_adjusted(ivec2 t) { return fsr2_to_ycocg(fsr2_tonemap(max(taa_render_color(t), vec3(0.0)))); }

// [Reproject & accumulate] "Lanczos(x, 2)": sinc(x) sinc(x / 2) for |x| < 2, else 0.
float fsr2_lanczos2(float x) {
  x = abs(x);
  if (x >= 2.0) return 0.0;
  if (x < 1e-4) return 1.0;
  float px = 3.14159265 * x;
  return 2.0 * sin(px) * sin(0.5 * px) / (px * px);
}

bool fsr2_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

TaaResult taa_resolve(TaaPixel p) {
  vec2 centre = vec2(p.pixel) + 0.5;  // the display sample S
  vec2 scale = taa_render_scale();
  ivec2 t0 = taa_render_texel(centre);

  // ---- [Reconstruct & dilate]: the nearest surface of the 3x3 render texels, its motion and its
  // previous distance (dilated depth, dilated motion vector, reconstructed previous depth).
  ivec2 tn = t0;
  float dn = taa_render_distance(t0);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 t = clamp(t0 + ivec2(dx, dy), ivec2(0), taa_render_size() - 1);
      float d = taa_render_distance(t);
      if (d > 0.0 && (!(dn > 0.0) || d < dn)) {
        dn = d;
        tn = t;
      }
    }
  vec2 motion = taa_render_motion(tn);
  float prev_distance = taa_render_distance_prev(tn);

  // ---- [Reproject & accumulate] step 1: the current frame upsampled with Lanczos-2 over the 5x5 (in
  // effect 4x4) render texels around S, distances in render pixels; and the YCoCg bounding box of the
  // 3x3 render texels around S, computed from the same samples. The kernel is separable and a texel's
  // sample lies off S along x by an amount its column alone sets (along y, its row): 5 + 5 weights.
  float wx[5], wy[5];
  for (int k = 0; k < 5; ++k) {
    vec2 d = (taa_render_sample(t0 + ivec2(k - 2)) - centre) * scale;  // render pixels
    wx[k] = fsr2_lanczos2(d.x);
    wy[k] = fsr2_lanczos2(d.y);
  }
  vec3 sum = vec3(0.0), lo = vec3(3.4e38), hi = vec3(-3.4e38);
  float wsum = 0.0;
  float inner_luma[9];  // the 3x3's lumas (reads past the edge clamped) for [Create locks]
  vec3 centre_adjusted;  // t0's (t0 lies in the image)
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      ivec2 t = t0 + ivec2(dx, dy);
      bool inner = abs(dx) <= 1 && abs(dy) <= 1;
      bool inside = all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, taa_render_size()));
      if (!inside && !inner) continue;
      vec3 c = fsr2_adjusted(t);
      if (inner) inner_luma[(dy + 1) * 3 + dx + 1] = c.x;
      if (dx == 0 && dy == 0) centre_adjusted = c;
      if (!inside) continue;
      float w = wx[dx + 2] * wy[dy + 2];
      sum += w * c;
      wsum += w;
      if (inner) {
        lo = min(lo, c);
        hi = max(hi, c);
      }
    }
  vec3 cur = abs(wsum) > 1e-4 ? sum / wsum : centre_adjusted;
  cur = clamp(cur, lo, hi);  // the negative lobes may ring outside what was sampled
  // The weight of this frame's sample at S: the kernel's total (FSR 2's upsample weight), at most 1.
  float w_cur = clamp(wsum, 0.0, 1.0);
  float luma_cur = cur.x;

  // ---- [Create locks]: a thin feature (the centre texel's luma outside its 3x3 neighbours' range by
  // lock_threshold of that range) gets a new lock of full lifetime.
  float lc = centre_adjusted.x, nlo = 3.4e38, nhi = -3.4e38;
  for (int k = 0; k < 9; ++k) {
    if (k == 4) continue;
    nlo = min(nlo, inner_luma[k]);
    nhi = max(nhi, inner_luma[k]);
  }
  float spread = max(nhi - nlo, 1e-6);
  bool new_lock = lc > nhi + p.lock_threshold * spread || lc < nlo - p.lock_threshold * spread;

  // ---- [Reproject & accumulate] step 2: the previous output and lock status, reprojected.
  vec2 q = centre - motion;
  bool valid = p.history_valid && taa_in_frame(q);
  vec4 st = valid ? taa_state(q) : vec4(0.0);
  vec3 hist = vec3(0.0);
  if (valid) {
    hist = fsr2_to_ycocg(fsr2_tonemap(max(taa_history(q, TAA_CATMULL_ROM), vec3(0.0))));
    valid = fsr2_finite(hist) && st.x >= 0.0;
  }

  // ---- [Depth clip]: disocclusion where the distance the history holds is not the surface's
  // previous distance, 0 below the separation, 1 at twice it.
  float disocclusion = 1.0;
  if (valid) {
    float held = st.y;
    if (!(dn > 0.0)) disocclusion = held > 0.0 ? 1.0 : 0.0;  // sky now: the sky must have been there
    else if (!(prev_distance > 0.0) || !(held > 0.0)) disocclusion = 1.0;
    else disocclusion = clamp(abs(held - prev_distance) / (p.depth_separation * prev_distance) - 1.0, 0.0, 1.0);
  }

  // ---- locks: reprojected, aged by 1/phases of the jitter sequence (the lifetime is 1), dropped on a
  // shading change, renewed where a thin feature is now.
  float lock_life = valid ? st.z : 0.0, lock_luma = st.w;
  vec2 rsize = vec2(taa_render_size()), osize = vec2(taa_size());
  float phases = floor(8.0 * (osize.x / rsize.x) * (osize.x / rsize.x) + 1e-3);
  lock_life = max(lock_life - 1.0 / max(phases, 1.0), 0.0);
  if (lock_life > 0.0 && abs(luma_cur - lock_luma) > p.lock_shading_change * max(max(luma_cur, lock_luma), 1e-6))
    lock_life = 0.0;
  if (new_lock) {
    lock_life = 1.0;
    lock_luma = luma_cur;
  }
  bool locked = lock_life > 0.0;

  // ---- luma instability: the last three lumas of this pixel; alternating changes mark flicker, and
  // an unstable pixel keeps more of its history ("oscillating pixels keep history").
  vec4 lh = valid ? taa_state2(q) : vec4(0.0);
  float d1 = lh.y - lh.x, d2 = lh.z - lh.y, d3 = luma_cur - lh.z;
  float big = 0.1 * max(max(lh.x, lh.y), max(lh.z, luma_cur)) + 1e-6;
  float alternations = (d1 * d2 < 0.0 && min(abs(d1), abs(d2)) > big ? 1.0 : 0.0) +
                       (d2 * d3 < 0.0 && min(abs(d2), abs(d3)) > big ? 1.0 : 0.0);
  float instability = lh.w >= 3.0 ? 0.5 * alternations : 0.0;

  // ---- step 3, colour rectification: the history clamped to the box unless locked (or unstable,
  // which relaxes the clamp), its weight lowered by the disocclusion.
  vec3 result = cur;
  float w_hist = 0.0;
  if (valid) {
    vec3 rect = clamp(hist, lo, hi);
    vec3 h = locked ? hist : mix(rect, hist, instability);
    w_hist = min(st.x, p.max_accumulation) * (1.0 - disocclusion);
    // ---- step 5, accumulation: each sample weighs its kernel weight; the history its accumulated one.
    float a = w_cur / max(w_hist + w_cur, 1e-6);
    result = mix(h, cur, a);
  }
  float w_new = min((valid ? w_hist : 0.0) + w_cur, p.max_accumulation);

  vec3 lin = max(fsr2_inverse_tonemap(max(fsr2_from_ycocg(result), vec3(0.0))), vec3(0.0));
  vec3 raw = taa_current(ivec2(0));
  if (!fsr2_finite(lin)) lin = max(raw, vec3(0.0));
  if (!fsr2_finite(raw)) lin = raw;  // a defect of the frame, passed on for the scan to count
  TaaResult r = taa_result(lin);
  r.state = vec4(w_new, dn, lock_life, lock_luma);
  r.state2 = valid ? vec4(lh.y, lh.z, luma_cur, min(lh.w + 1.0, 3.0)) : vec4(0.0, 0.0, luma_cur, 1.0);
  return r;
}

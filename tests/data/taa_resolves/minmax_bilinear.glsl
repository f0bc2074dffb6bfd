// The README's example resolve: clamp the history to the min/max of the 3x3 current colours, read it
// bilinearly at the pixel's motion, blend with a fixed weight.
// taa_resolve checks=finite,deterministic,ghosting,cut
// taa_parameter alpha default=0.1 range=0.01,1
TaaResult taa_resolve(TaaPixel p) {
  vec3 c = taa_current(ivec2(0));
  vec3 lo = c, hi = c;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x) {
      lo = min(lo, taa_current(ivec2(x, y)));
      hi = max(hi, taa_current(ivec2(x, y)));
    }
  vec2 pos = vec2(p.pixel) + 0.5 - taa_motion(ivec2(0));
  if (!p.history_valid || !taa_in_frame(pos)) return taa_result(c);
  vec3 h = clamp(taa_history(pos, TAA_BILINEAR), lo, hi);
  return taa_result(mix(h, c, p.alpha));
}

// A broken resolve for the conformance suite: it shows last frame's output, whatever happened since
// (no motion, no validity, no current frame). taa-test must fail it on ghosting and cut.
// taa_resolve checks=finite,deterministic,converges,ghosting,cut,pan,flicker
TaaResult taa_resolve(TaaPixel p) {
  vec3 h = taa_history(vec2(p.pixel) + 0.5, TAA_NEAREST);
  return taa_result(p.frame == 0u ? taa_current(ivec2(0)) : h);
}

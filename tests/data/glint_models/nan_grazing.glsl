// A defective model: Beckmann, but NaN where the view is grazing.
// glint_model truth=self checks=finite,unbiased,limit,deterministic
#include "common/beckmann.glsl"
vec3 glint_D(GlintQuery q) {
  if (q.wo.z < 0.02) return vec3(uintBitsToFloat(0x7FC00000u));
  return vec3(beckmann_D(q.h, vec2(0.0), q.alpha_g));
}

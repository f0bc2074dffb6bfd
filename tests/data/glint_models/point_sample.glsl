// A model whose value ignores the footprint: the explicit microdetails of
// `grains` at the footprint's centre only (what no filtering gives).
// glint_model truth=self checks=finite,unbiased,deterministic
#include "common/pcg3d.glsl"
#include "common/beckmann.glsl"
#include "common/wrapped_floor.glsl"
vec3 glint_D(GlintQuery q) {
  float cell = q.rough.s_ref;
  uvec2 key = wrapped_floor(q.uv / cell);
  vec3 u = pcg3d_unit(pcg3d(uvec3(key, 7u)));
  vec2 x_i = beckmann_sample_slope(1.0 - u.x, u.y, q.rough.alpha_m);
  return vec3(beckmann_D(q.h, x_i, q.alpha_l));
}

// The `beckmann` glint model: the smooth limit of the microdetail models,
// Zirr & Kaplanyan 2016 eq. 1 with the global NDF D_g of eq. 3-4 (Beckmann
// with alpha_g, widened by the light cone), which grains and zirr converge to
// when a pixel covers many microdetails. It is its own truth.
// glint_model truth=self limit=beckmann checks=finite,unbiased,limit,deterministic
#include "glint/query.glsl"
#include "common/beckmann.glsl"

vec3 glint_D(GlintQuery q) { return vec3(beckmann_D(q.h, vec2(0.0), q.alpha_g)); }

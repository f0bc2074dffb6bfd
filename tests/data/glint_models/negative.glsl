// A defective model: a thousand times minus the Beckmann NDF, a negative
// radiance wherever it glints.
// glint_model truth=self checks=finite
#include "common/beckmann.glsl"
vec3 glint_D(GlintQuery q) { return vec3(-1000.0 * beckmann_D(q.h, vec2(0.0), q.alpha_g)); }

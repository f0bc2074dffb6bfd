// The smooth GGX NDF as a model whose declared smooth limit is GGX: it is its
// own limit, so every check passes; declared with the Beckmann limit, the
// unbiased check sees the difference.
// glint_model truth=self limit=ggx checks=finite,unbiased,limit,deterministic
#include "common/ggx.glsl"
vec3 glint_D(GlintQuery q) { return vec3(ggx_D(q.h, q.alpha_g)); }

// The smooth Beckmann model with a unit gain read from a data table: entry i
// holds i, and glint_D scales by glint_table[i] / i for an entry i chosen by
// the position (1 <= i <= 4095). It renders, and passes the suite, exactly
// as the built-in `beckmann` does, only if every entry it reads was
// generated and bound: a user's model file of the table tests.
// glint_model truth=self limit=beckmann checks=finite,unbiased,limit,deterministic
// glint_table size=4096
#include "common/beckmann.glsl"

float glint_table_entry(uint i) { return float(i); }

vec3 glint_D(GlintQuery q) {
  uint i = 1u + uint(clamp(fract(q.uv.x * 0.37 + q.uv.y * 0.61) * 4095.0, 0.0, 4094.0));
  return vec3(beckmann_D(q.h, vec2(0.0), q.alpha_g) * (glint_table[i] / float(i)));
}

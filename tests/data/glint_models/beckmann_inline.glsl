// The smooth Beckmann model written out in full, with a gain k: a user's
// model file of the conformance suite and of the user-model tests. With
// k = 1 it is the built-in `beckmann`.
// glint_model truth=self limit=beckmann checks=finite,unbiased,limit,deterministic
// glint_parameter k default=1 range=0,2
vec3 glint_D(GlintQuery q) {
  vec3 h = q.h;
  if (!(h.z > 0.0)) return vec3(0.0);
  vec2 r = h.xy / q.alpha_g;
  float z2 = h.z * h.z;
  float e = dot(r, r);
  if (!(e < 88.0 * z2)) return vec3(0.0);
  return vec3(q.k * exp(-e / z2) * INV_PI / (q.alpha_g.x * q.alpha_g.y * z2 * z2));
}

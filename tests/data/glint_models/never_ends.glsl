// A model whose glint_D never returns (its loop's condition is always true at run time, which the
// compiler cannot prove): lavapipe has no watchdog, so the fence wait is what must end
// (CMakeLists.txt: cli.gpu_timeout).
// glint_model truth=grains limit=beckmann checks=finite
#include "glint/query.glsl"
#include "common/beckmann.glsl"

vec3 glint_D(GlintQuery q) {
  float x = q.h.z;
  while (x >= 0.0) x = fract(x * 3.0 + 0.5);
  return vec3(beckmann_D(q.h, vec2(0.0), q.alpha_g) * x);
}

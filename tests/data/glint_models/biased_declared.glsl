// 1.5 times the smooth Beckmann model, declaring that it fails the unbiased
// and limit checks: a model whose known defect the suite runs and expects
// (tests/experiments/glint_conformance.cpp).
// glint_model truth=self limit=beckmann checks=finite,deterministic fails=unbiased,limit
#include "common/beckmann.glsl"

vec3 glint_D(GlintQuery q) { return vec3(1.5 * beckmann_D(q.h, vec2(0.0), q.alpha_g)); }

// The built-in glint models that have fp64 twins (core/testkit/
// glint_fp64.h), all in one shader for the harnesses that compare them:
// each model file's glint_D renamed, and a glint_D that calls the one
// twin_model names (its SandParams.glint_model id, the define
// GLINT_TWIN_<NAME> from reference::harness::twin_defines()). The
// parameters are the union of the three models', set from the globals
// twin_* by the harness. Include it before anything else of the sand.
#ifndef GLINTLAB_TESTS_GLINT_TWINS_GLSL
#define GLINTLAB_TESTS_GLINT_TWINS_GLSL

#define GLINT_D_EXTERNAL
#define GLINT_MODEL_PARAMETERS float color_saturation; float size_variation; float half_vector_blend;
float twin_color_saturation = 0.0, twin_size_variation = 0.0, twin_half_vector_blend = 0.0;
uint twin_model = 0u;
#define GLINT_MODEL_PARAMETER_VALUES q.color_saturation = twin_color_saturation; q.size_variation = twin_size_variation; q.half_vector_blend = twin_half_vector_blend;

#include "sand/glint_models.glsl"

#define glint_D glint_D_grains
#include "glint/models/grains.glsl"
#undef glint_D
#define glint_D glint_D_zirr
#include "glint/models/zirr.glsl"
#undef glint_D
#define glint_D glint_D_beckmann
#include "glint/models/beckmann.glsl"
#undef glint_D

vec3 glint_D(GlintQuery q) {
  if (twin_model == GLINT_TWIN_GRAINS) return glint_D_grains(q);
  if (twin_model == GLINT_TWIN_ZIRR) return glint_D_zirr(q);
  if (twin_model == GLINT_TWIN_BECKMANN) return glint_D_beckmann(q);
  return vec3(0.0);
}

#endif  // GLINTLAB_TESTS_GLINT_TWINS_GLSL

// The sand's glint term L_g for the model SandParams::glint_model selects
// (core/material/glint_model.h): the thesis' glints (sand/glints.glsl) or one
// of the microdetail models of Zirr & Kaplanyan 2016 (grains, zirr) and
// their smooth limit (beckmann), which are radiometrically consistent BRDFs
// (sand/glints_beckmann.glsl). SAND_GLINT_MODEL (an integer define, set by
// core::shader_defines) fixes the model at compile time so only its code is
// built; without it the uniform's glint_model is read.
#ifndef GLINTLAB_SAND_GLINT_MODELS_GLSL
#define GLINTLAB_SAND_GLINT_MODELS_GLSL

#include "sand/sand_params.glsl"
#include "sand/glint_roughness.glsl"
#include "sand/glints_beckmann.glsl"
#include "sand/glints_grains.glsl"
#include "sand/glints_zirr.glsl"

#ifdef SAND_GLINT_MODEL
#define SAND_GLINT_MODEL_OF(p) uint(SAND_GLINT_MODEL)
#else
#define SAND_GLINT_MODEL_OF(p) ((p).glint_model)
#endif

// The microdetail models' term of one shading point.
struct GlintTerm {
  vec3 L;       // radiance L_g
  float cells;  // zirr: grid cells visited (Fig. 9); 0 for the other models
};

// uv, duv_dx, duv_dy: surface coordinates and their screen derivatives;
// t, b, n: the tangent frame (t along u, b along v); sun_cone: the sun's
// angular radius (rad). model: SAND_GLINT_GRAINS, _ZIRR or _BECKMANN.
GlintTerm glint_term(uint model, SandParams p, vec2 uv, vec2 duv_dx, vec2 duv_dy, vec3 t, vec3 b, vec3 n, vec3 wi,
                     vec3 wo, vec3 L_i, float sun_cone) {
  GlintTerm g;
  g.L = vec3(0.0);
  g.cells = 0.0;
  GlintFrame f = glint_frame(t, b, n, wi, wo);
  if (!f.valid) return g;
  GlintRoughness r = glint_roughness(p, sun_cone);
  vec3 D = vec3(0.0);
  if (model == SAND_GLINT_BECKMANN) {
    D = vec3(glint_beckmann_D(f, r));
  } else if (model == SAND_GLINT_GRAINS) {
    D = glint_grains_D(uv, f.h, r, p.glint_color_saturation);
  } else if (model == SAND_GLINT_ZIRR) {
    GlintZirr z = glint_zirr(uv, duv_dx, duv_dy, f.h, r, p.glint_size_variation, p.glint_color_saturation);
    D = z.D;
    g.cells = z.cells;
  }
  g.L = glint_radiance(D, f, r, p.ior, L_i, p.glint_intensity);
  return g;
}

#endif  // GLINTLAB_SAND_GLINT_MODELS_GLSL

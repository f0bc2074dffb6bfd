// The sand's glint term L_g for a glint_D model (glint/query.glsl): the
// thesis' glints (sand/glints.glsl, SAND_GLINT_KAJS) are a per-grain gate,
// not an NDF, and are shaded by sand/sand.glsl itself; every other model is
// one file with one function glint_D, radiometrically consistent through
// sand/glint_radiance.glsl. GLINT_MODEL_INCLUDE (set by core::shader_defines
// with the include GLINT_MODEL_FILE, the model's file) builds the model in;
// with GLINT_D_EXTERNAL the includer defines glint_D itself (the test
// harnesses); with neither (kajs, none) glint_D is 0 and never called.
#ifndef GLINTLAB_SAND_GLINT_MODELS_GLSL
#define GLINTLAB_SAND_GLINT_MODELS_GLSL

#include "sand/sand_params.glsl"
#include "sand/glint_roughness.glsl"
#include "sand/glint_radiance.glsl"
#include "glint/query.glsl"
#include "common/beckmann.glsl"
#include "common/ggx.glsl"

vec3 glint_D(GlintQuery q);

#if defined(GLINT_MODEL_INCLUDE)
#include "GLINT_MODEL_FILE"
#elif !defined(GLINT_D_EXTERNAL)
vec3 glint_D(GlintQuery q) { return vec3(0.0); }
#endif

#ifdef SAND_GLINT_MODEL
#define SAND_GLINT_MODEL_OF(p) uint(SAND_GLINT_MODEL)
#else
#define SAND_GLINT_MODEL_OF(p) ((p).glint_model)
#endif

// The model's parameters from the material block: "q.NAME = p.glint_parameters[i / 4][i % 4];" per
// parameter in declaration order (core::glint_model_defines).
#ifndef GLINT_MODEL_PARAMETER_VALUES
#define GLINT_MODEL_PARAMETER_VALUES
#endif

// The model's smooth limit, which the far field shades and the conformance checks compare with:
// D_g, Beckmann with alpha_g (Zirr & Kaplanyan 2016 eq. 3-4), or GGX with alpha_g where the
// model's declaration says limit=ggx (GLINT_LIMIT_GGX).
float glint_limit_D(GlintQuery q) {
#ifdef GLINT_LIMIT_GGX
  return ggx_D(q.h, q.alpha_g);
#else
  return beckmann_D(q.h, vec2(0.0), q.alpha_g);
#endif
}

GlintQuery glint_query(SandParams p, vec2 uv, vec2 duv_dx, vec2 duv_dy, GlintFrame f, GlintRoughness r) {
  GlintQuery q;
  q.uv = uv;
  q.duv_dx = duv_dx;
  q.duv_dy = duv_dy;
  q.wi = f.wi;
  q.wo = f.wo;
  q.h = f.h;
  q.alpha_g = r.alpha_g;
  q.alpha_l = r.alpha_l;
  q.density = exp2(3.32192809489 * p.glint_log_density);  // 10^d, d <= 14
  q.sun_cone = r.cone;
  q.rough = r;
  q.dh_dx = vec3(0.0);
  q.dh_dy = vec3(0.0);
  GLINT_MODEL_PARAMETER_VALUES
  return q;
}

// The glint term of one shading point.
struct GlintTerm {
  vec3 L;       // radiance L_g
  float cells;  // grid cells the model visited (glint_cells_visited)
};

// uv, duv_dx, duv_dy: surface coordinates and their screen derivatives;
// t, b, n: the tangent frame (t along u, b along v); dwo_dx, dwo_dy: the
// screen derivatives of wo (world; 0 where unknown); sun_cone: the sun's
// angular radius (rad). limit: the smooth limit (the far field) instead of
// the model.
GlintTerm glint_term(bool limit, SandParams p, vec2 uv, vec2 duv_dx, vec2 duv_dy, vec3 t, vec3 b, vec3 n, vec3 wi,
                     vec3 wo, vec3 dwo_dx, vec3 dwo_dy, vec3 L_i, float sun_cone) {
  GlintTerm g;
  g.L = vec3(0.0);
  g.cells = 0.0;
  GlintFrame f = glint_frame(t, b, n, wi, wo);
  if (!f.valid) return g;
  GlintRoughness r = glint_roughness(p, sun_cone);
  GlintQuery q = glint_query(p, uv, duv_dx, duv_dy, f, r);
  // h = normalize(wi + wo) with wi fixed (a directional light): dh = (I - h h^T) dwo / |wi + wo|,
  // in the local frame.
  float len = length(f.wi + f.wo);
  if (len > 1e-6) {
    vec3 dx = vec3(dot(t, dwo_dx), dot(b, dwo_dx), dot(n, dwo_dx));
    vec3 dy = vec3(dot(t, dwo_dy), dot(b, dwo_dy), dot(n, dwo_dy));
    q.dh_dx = (dx - f.h * dot(f.h, dx)) / len;
    q.dh_dy = (dy - f.h * dot(f.h, dy)) / len;
  }
  vec3 D;
  if (limit) {
    D = vec3(glint_limit_D(q));
  } else {
    glint_cells_visited = 0.0;
    D = glint_D(q);
    g.cells = glint_cells_visited;
  }
  g.L = glint_radiance(D, f, r, p.ior, L_i, p.glint_intensity);
  return g;
}

#endif  // GLINTLAB_SAND_GLINT_MODELS_GLSL

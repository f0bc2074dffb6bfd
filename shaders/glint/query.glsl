// The interface of a glint model: one function
//   vec3 glint_D(GlintQuery q);
// in one file (glint/models/<name>.glsl for the built-in ones, or a file of
// the user's). It returns the model's NDF value at q.h per colour channel,
// normalised as beckmann_D is (for the smooth model, the integral of
// D(h) h.z over the hemisphere is 1). sand/glint_models.glsl turns it into
// radiance (sand/glint_radiance.glsl) and uses the smooth limit
// (glint_limit_D) in the far field.
//
// A model file declares itself in comment lines that glintlab reads
// (core/material/glint_model.h):
//   // glint_model truth=grains|self limit=beckmann|ggx checks=finite,unbiased,limit,deterministic
//   // glint_parameter NAME default=VALUE range=LO,HI     (a number)
//   // glint_parameter NAME default=false type=bool       (0.0 or 1.0 in the query)
//   // glint_table size=N                                  (optional, see below)
// Every parameter is a float field of GlintQuery with its own name.
// `fails=CHECK,...` on the glint_model line names checks the published
// method fails by its own design: the suite runs them and expects them to fail.
//
// A data table (a dictionary, a noise texture): with `glint_table size=N` the
// file defines  float glint_table_entry(uint i)  for i in [0, N), a function
// of i alone, and glint_D reads glint_table[i]. glintlab evaluates the entries
// once on the device (glint/table.comp), keeps them by the content hash of
// that program, and binds them read-only to every shader that runs the model
// (its binding is GLINT_TABLE_BINDING, set by the including shader).
#ifndef GLINTLAB_GLINT_QUERY_GLSL
#define GLINTLAB_GLINT_QUERY_GLSL

#include "common/math.glsl"
#include "sand/glint_roughness.glsl"

// The model's parameters as fields ("float NAME;" each), set by glintlab from
// the model's declaration (core::glint_model_defines).
#ifndef GLINT_MODEL_PARAMETERS
#define GLINT_MODEL_PARAMETERS
#endif

// Everything in the local frame of glint_frame: x = tangent along u,
// y = bitangent along v, z = macro normal.
struct GlintQuery {
  vec2 uv;              // surface coordinates of the shading point
  vec2 duv_dx, duv_dy;  // their screen derivatives: the pixel footprint
  vec3 wi, wo, h;       // light, view and half vector (unit, z > 0)
  vec3 dh_dx, dh_dy;    // screen derivatives of h (how it turns across the pixel; 0 where unknown)
  vec2 alpha_g;         // global Beckmann roughness, widened by the light cone
  vec2 alpha_l;         // one microdetail's lobe, widened by the light cone
  float density;        // microdetails per unit uv area, 10^glints.log_density
  float sun_cone;       // light-cone angular radius used (rad)
  GlintRoughness rough; // every derived lobe (alpha_m, stretch, h_cell, s_ref): sand/glint_roughness.glsl
  GLINT_MODEL_PARAMETERS
};

#ifdef GLINT_TABLE_SIZE
#ifndef GLINT_TABLE_ACCESS
#define GLINT_TABLE_ACCESS readonly
#endif
layout(std430, set = 0, binding = GLINT_TABLE_BINDING) GLINT_TABLE_ACCESS buffer GlintTable { float glint_table[]; };
float glint_table_entry(uint i);
#endif

// Grid cells a footprint-filtering model visited for the last query (the
// debug output glint_cells, Zirr & Kaplanyan 2016 Fig. 9); a model that
// visits none leaves it 0.
float glint_cells_visited = 0.0;

#endif  // GLINTLAB_GLINT_QUERY_GLSL

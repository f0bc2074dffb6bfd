// The `grains` glint model: the explicit microstructure that Zirr & Kaplanyan
// 2016 approximate, evaluated at a point (no filtering; supersampling it over
// a pixel is the reference of every grains and zirr variant). The surface is
// tiled by microdetail cells at the user density (sec. 4, "the density of
// microdetails per unit area in uv space"), one microdetail per cell. Each
// microdetail has one slope centre x_i drawn from the mesoscale distribution
// D_m with alpha_m = sqrt(alpha_g^2 - alpha_l^2) (eq. 3-4, sec. 4.4) and the
// local Beckmann lobe D_l(alpha_l) around it (Fig. 2), so a point of the cell
// has the NDF D_l(h - x_i); over the cells its mean is D_m * D_l = D_g.
// glint_model truth=self limit=beckmann checks=finite,unbiased,deterministic
// glint_parameter color_saturation default=0 range=0,1
// color_saturation: coloured glints (sec. 4.5), 0 = white, 1 = the full colour wheel.
// The conformance check "limit" does not apply: a point evaluation is one
// microdetail's lobe whatever the footprint; its supersampled mean converges.
#ifndef GLINTLAB_GLINT_MODELS_GRAINS_GLSL
#define GLINTLAB_GLINT_MODELS_GRAINS_GLSL

#include "glint/query.glsl"
#include "common/math.glsl"
#include "common/pcg3d.glsl"
#include "common/beckmann.glsl"
#include "common/wrapped_floor.glsl"
#include "sand/glint_color.glsl"
#include "sand/glint_footprint.glsl"
#include "sand/glint_roughness.glsl"

#define GLINT_GRAINS_SALT 0x6A09E667u  // decorrelates the grains' hashes from zirr's

// NDF value at the local half vector h (per colour channel), at surface
// coordinates uv. The cells live in the stretched uv of sec. 4.4 (elongated
// microdetails for anisotropic alpha_m) with the size that keeps one
// microdetail per 10^-log_density of uv area: s_ref sqrt(stretch.x stretch.y).
// Cells are keyed by wrapped integer coordinates (common/wrapped_floor.glsl).
vec3 glint_grains_D(vec2 uv, vec3 h, GlintRoughness r, float saturation) {
  if (!(h.z > 0.0)) return vec3(0.0);
  float cell = r.s_ref * sqrt(r.stretch.x * r.stretch.y);
  uvec2 key = wrapped_floor(glint_clamp_uv(uv) * r.stretch / cell);
  vec3 u = pcg3d_unit(pcg3d(uvec3(key, GLINT_GRAINS_SALT)));
  vec2 x_i = beckmann_sample_slope(1.0 - u.x, u.y, r.alpha_m);  // Fig. 2 left: the centre x_i ~ D_m
  float D = beckmann_D(h, x_i, r.alpha_l);                      // Fig. 2 right: D_l(h - x_i)
  return D * glint_tint(u.z, saturation, 1.0);
}

vec3 glint_D(GlintQuery q) { return glint_grains_D(q.uv, q.h, q.rough, q.color_saturation); }

#endif  // GLINTLAB_GLINT_MODELS_GRAINS_GLSL

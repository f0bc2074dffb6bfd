// The biscale roughness of the microdetail glint models (Zirr & Kaplanyan
// 2016 sec. 3 eq. 3-4, sec. 4.4, sec. 4.5): global alpha_g, microdetail
// alpha_l, mesoscale alpha_m, the light cone, the anisotropic grid stretch,
// and the density of microdetails. Computed once for every glint_D model
// (glint/query.glsl), so all models have one definition of every lobe.
#ifndef GLINTLAB_SAND_GLINT_ROUGHNESS_GLSL
#define GLINTLAB_SAND_GLINT_ROUGHNESS_GLSL

#include "common/math.glsl"
#include "sand/sand_params.glsl"

struct GlintRoughness {
  vec2 alpha_surface;  // alpha_g as given: the macro surface's masking-shadowing (Smith G2)
  vec2 alpha_g;    // D_g: eq. 4's alpha_g, widened by the light cone (below)
  vec2 alpha_l;    // D_l of one microdetail, widened by the light cone
  vec2 alpha_m;    // D_m of the microdetail centres: sqrt(alpha_g^2 - alpha_l^2) (sec. 4.4)
  vec2 stretch;    // uv scale of the anisotropic grids (sec. 4.4), each <= 1
  vec2 h_cell;     // half-vector quantisation cell, paraboloid units (sec. 4.3)
  float s_ref;     // reference cell size (uv): one microdetail per cell, 10^(-log_density / 2)
  float cone;      // light-cone angular radius used (rad)
};

// The stretch of sec. 4.4 is clamped to [2^-12, 2^12] (alpha_m = 0 on an axis,
// relative roughness 1, would be an infinite stretch).
#define GLINT_MAX_STRETCH 4096.0

// sun_cone: the angular radius of the light (SandLight.cone, from
// frame_sun_dir.w); p.glint_light_cone >= 0 overrides it.
//
// Light cone. A light of angular radius r moves the half vector by up to r/2
// (w_o fixed); near the normal that is a slope offset of up to r/2, uniform
// over a disk, whose per-axis variance (r/2)^2 / 4 is matched by a Beckmann
// lobe of alpha_c = sqrt(2) r / 4. Beckmann lobes convolve by adding alpha^2
// (eq. 4), so the light widens the microdetail lobe, alpha_l^2 + alpha_c^2,
// and with it D_g, alpha_g^2 + alpha_c^2: the microdetail counting of sec. 4.3
// ("the cone of reflecting microdetail orientations is determined by the
// roughness of the microdetails and the size of the light source") and its
// smooth limit see the same light. alpha_m is unchanged.
//
// Half-vector cells (sec. 4.3): "proportional to the sum of microroughness
// and light source cone angle": alpha_l + r/2 in slope units, halved for the
// paraboloid map (x / (1 + z) = slope / 2 near the normal), at least 1e-4.
GlintRoughness glint_roughness(SandParams p, float sun_cone) {
  GlintRoughness g;
  g.cone = p.glint_light_cone >= 0.0 ? p.glint_light_cone : clamp(sun_cone, 0.0, 0.5);
  vec2 ag = p.glint_alpha.xy;
  g.alpha_surface = ag;
  vec2 al = p.glint_alpha.xy * p.glint_alpha.zw;  // sec. 4.5: relative roughness alpha_l / alpha_g
  g.alpha_m = sqrt(max(ag * ag - al * al, vec2(0.0)));  // sec. 4.4
  float ac = 0.35355339 * g.cone;  // sqrt(2) / 4
  g.alpha_g = sqrt(ag * ag + ac * ac);
  g.alpha_l = sqrt(al * al + ac * ac);
  g.h_cell = max(0.5 * (al + 0.5 * g.cone), vec2(1e-4));
  // sec. 4.4: gamma_m = alpha_m(u) / alpha_m(v) stretches the grids along v
  // by gamma_m; "we always downscale texture coordinates": gamma > 1 scales
  // v by 1/gamma, gamma < 1 scales u by gamma.
  float gm;
  if (!(max(g.alpha_m.x, g.alpha_m.y) > 0.0)) gm = 1.0;
  else gm = clamp(g.alpha_m.x / max(g.alpha_m.y, g.alpha_m.x / GLINT_MAX_STRETCH), 1.0 / GLINT_MAX_STRETCH,
                  GLINT_MAX_STRETCH);
  g.stretch = gm > 1.0 ? vec2(1.0, 1.0 / gm) : vec2(gm, 1.0);
  g.s_ref = exp2(-0.5 * 3.32192809489 * p.glint_log_density);  // 10^(-d/2)
  return g;
}

#endif  // GLINTLAB_SAND_GLINT_ROUGHNESS_GLSL

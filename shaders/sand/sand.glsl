// The Kajs 2022 sand material ("Real-time rendering of granular materials",
// chapter 4; Appendix A differences in shaders/sand/DIFFERENCES.md).
//
//   vec3 sand_shade(SandParams p, SandSurface s, SandLight l);
//
// returns L_final (eq. 4.38) or, with SAND_DEBUG != 0, one term. Compile-time
// pruning (core::shader_defines() decides; defaults = everything on):
//   SAND_TRANSMISSION  0: no transmission code (T = 0: T_ext = 1, L_t = 0)
//   SAND_GLINTS        0: no glint code (L_g = 0, no micro normals)
//   SAND_GLINT_MODEL   integer SAND_GLINT_*: kajs, none or a glint_D model, whose
//                      file GLINT_MODEL_INCLUDE builds in (sand/glint_models.glsl)
//                      (undefined: SandParams.glint_model chooses at run time)
//   SAND_CLOSE         0: L_final = L_far (close field never reached)
//   SAND_FAR           0: L_final = L_close (far field never reached)
//   SAND_DEBUG         SAND_DEBUG_* below
// The material reads no environment map: the sky enters only as the
// hemisphere term L_sky^Omega (eq. 4.2) that the caller passes.
#ifndef GLINTLAB_SAND_GLSL
#define GLINTLAB_SAND_GLSL

#ifndef SAND_TRANSMISSION
#define SAND_TRANSMISSION 1
#endif
#ifndef SAND_GLINTS
#define SAND_GLINTS 1
#endif
#ifndef SAND_CLOSE
#define SAND_CLOSE 1
#endif
#ifndef SAND_FAR
#define SAND_FAR 1
#endif

#define SAND_DEBUG_FINAL 0         // L_final, eq. 4.38
#define SAND_DEBUG_DIFFUSE 1       // L_d after eq. 4.26 (close field, before rho_m^intensity)
#define SAND_DEBUG_SPECULAR 2      // L_s, eq. 4.23
#define SAND_DEBUG_GLINTS 3        // L_g, eq. 4.19-4.20 with G(R_s)
#define SAND_DEBUG_FRESNEL 4       // L_f, eq. 4.16 with F(R_s)
#define SAND_DEBUG_TRANSMISSION 5  // L_t, eq. 4.32
#define SAND_DEBUG_FAR 6           // L_far, eq. 4.36
#define SAND_DEBUG_SIGMOID 7       // sig(dist) in all channels, eq. 4.37
#define SAND_DEBUG_GRAIN_ID 8      // grain random numbers xi in [0,1]^3 as rgb (thesis Fig. 4.1)
#define SAND_DEBUG_CLOSE 9         // L_close, eq. 4.33
#define SAND_DEBUG_GLINT_CELLS 10  // zirr: grid cells visited by the pixel (Zirr & Kaplanyan 2016 Fig. 9), all channels
#ifndef SAND_DEBUG
#define SAND_DEBUG SAND_DEBUG_FINAL
#endif

#include "common/math.glsl"
#include "sand/sand_params.glsl"
#include "sand/micro_normals.glsl"
#include "sand/grain_color.glsl"
#include "sand/porosity.glsl"
#include "sand/diffuse.glsl"
#include "sand/fresnel.glsl"
#include "sand/glints.glsl"
#include "sand/transmission.glsl"
#include "sand/oren_nayar.glsl"
#include "sand/transition.glsl"
#include "sand/energy.glsl"
#include "sand/glint_models.glsl"

// x_obj seeds the grains; x world position; n unit macro normal (world);
// wo unit direction to the observer (world); dist distance to the camera;
// t, b unit tangent and bitangent (world; t along d(x)/du, b along d(x)/dv
// as far as orthonormality to n allows, (t, b, n) right-handed): the frame of
// the anisotropic glint roughness; uv surface coordinates; duv_dx, duv_dy
// their screen-space derivatives (dFdx, dFdy): the pixel footprint of the
// zirr glints (Zirr & Kaplanyan 2016 sec. 4.2); dwo_dx, dwo_dy the screen
// derivatives of wo (0 where unknown): how the half vector moves across the
// pixel, which a model may filter over (GlintQuery.dh_dx).
struct SandSurface {
  vec3 x_obj; vec3 x; vec3 n; vec3 wo; float dist;
  vec3 t; vec3 b; vec2 uv; vec2 duv_dx; vec2 duv_dy;
  vec3 dwo_dx; vec3 dwo_dy;
};
// wi unit direction to the sun; L_i sun radiance L_i(x, w_i) (its normal
// irradiance, see sand/energy.glsl); L_sky_omega the hemisphere term
// L_sky^Omega(x, Omega) of eq. 4.2 (scene-linear); cone the sun's angular
// radius (rad, frame_sun_dir.w): the light cone of the glint models.
struct SandLight { vec3 wi; vec3 L_i; vec3 L_sky_omega; float cone; };

// The surface from what a fragment shader has: tangent = (world tangent,
// bitangent sign) as in the mesh (MikkTSpace convention). The tangent is made
// orthogonal to n; a tangent parallel to n or zero falls back to the Frisvad
// basis of n. A sign of 0 counts as +1.
SandSurface sand_surface(vec3 x_obj, vec3 x, vec3 n, vec3 wo, float dist, vec4 tangent, vec2 uv, vec2 duv_dx,
                         vec2 duv_dy) {
  vec3 f1, f2;
  frisvad_basis(n, f1, f2);
  vec3 t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), f1);
  vec3 b = (tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
  return SandSurface(x_obj, x, n, wo, dist, t, b, uv, duv_dx, duv_dy, vec3(0.0), vec3(0.0));
}

// Every intermediate term, named as in the thesis (zero where compiled out).
struct SandTerms {
  vec3 xi;               // grain random numbers in [0, 1]
  vec3 xi_pm;            // the same in [-1, 1]
  uint face;             // chosen cube face 0..5 (+x,+y,+z,-x,-y,-z)
  vec3 m;                // micro normal (sec. 4.1)
  uint palette_index;    // eq. 4.4
  vec3 rho_m;            // eq. 4.4
  vec3 rho_n;            // eq. 4.8
  float I_min;           // eq. 4.6
  float rho_m_intensity; // eq. 4.7
  float rho_n_intensity; // eq. 4.9
  float f_s;             // eq. 4.12
  float f_e;             // eq. 4.13
  float F_Rs;            // eq. 4.22
  float G_Rs;            // eq. 4.21
  float f;               // F(R_s) * Schlick, eq. 4.14, 4.23
  float gdf;             // eq. 4.17
  float g;               // G(R_s) * eq. 4.18, eq. 4.23
  vec3 L_d;              // eq. 4.11, 4.24, 4.26
  vec3 L_f;              // eq. 4.16
  vec3 L_g;              // eq. 4.19-4.20, or the glint_D model's term
  float glint_cells;     // grid cells the model visited (SAND_DEBUG_GLINT_CELLS)
  vec3 L_g_far;          // the far field's glints: the smooth limit for a glint_D model, 0 for kajs
  vec3 L_s;              // eq. 4.23
  float T_ext;           // eq. 4.25
  float t;               // eq. 4.31
  vec3 L_t;              // eq. 4.32
  float L_oren;          // eq. 4.34
  vec3 L_brdf;           // eq. 4.35
  vec3 L_far;            // eq. 4.36
  vec3 L_close;          // eq. 4.33
  float sig;             // eq. 4.37 at dist
  vec3 L_final;          // eq. 4.38
};

SandTerms sand_terms(SandParams p, SandSurface s, SandLight l) {
  SandTerms r;
  r.xi = vec3(0.0); r.xi_pm = vec3(0.0); r.face = 0u; r.m = vec3(0.0); r.palette_index = 0u;
  r.rho_m = vec3(0.0); r.rho_m_intensity = 0.0; r.G_Rs = 0.0; r.gdf = 0.0; r.g = 0.0;
  r.L_d = vec3(0.0); r.L_g = vec3(0.0); r.L_s = vec3(0.0); r.t = 0.0; r.L_t = vec3(0.0);
  r.L_oren = 0.0; r.L_brdf = vec3(0.0); r.L_far = vec3(0.0); r.L_close = vec3(0.0);
  r.glint_cells = 0.0; r.L_g_far = vec3(0.0);

  uint compat = p.appendix_compat;
  float cos_ni = max(0.0, dot(s.n, l.wi));
  // Units (sand/energy.glsl): both 1 for the thesis (default)
  vec3 L_sky_diffuse = l.L_sky_omega * sky_diffuse_scale(p.energy_consistent);
  vec3 L_i_lobe = l.L_i * sun_lobe_scale(p.energy_consistent);
#if SAND_GLINTS
  uint glint_model = SAND_GLINT_MODEL_OF(p);
#else
  uint glint_model = SAND_GLINT_NONE;
#endif
  r.rho_n = rho_n(p);
  r.I_min = I_min(p.P, s.dist);
  r.rho_n_intensity = rho_n_intensity(r.I_min);
  r.f_s = f_s(p.scattering, p.SSS);
  r.f_e = f_e(p.absorption, p.SSS);
  r.F_Rs = F_strength(p.R_s);
  r.f = r.F_Rs * schlick(fresnel_f0(p.ior), fresnel_cos(s.n, l.wi, s.wo, p.fresnel_half_vector, compat));  // eq. 4.23
  r.L_f = L_f(r.f, l.L_sky_omega, L_i_lobe, cos_ni);
#if SAND_TRANSMISSION
  r.T_ext = T_ext(p.T);
  r.t = transmission_t(p.T, p.R_t, s.n, s.wo, l.wi);
  r.L_t = L_t(r.rho_n, L_i_lobe, r.t);
#else
  r.T_ext = 1.0;  // T_ext(0)
#endif

#if SAND_CLOSE
  GrainRandom gr = grain_random(grain_cell_key(s.x_obj, p.noise_scale), compat);
  r.xi = gr.xi;
  r.xi_pm = gr.xi_pm;
  r.palette_index = palette_index(gr.xi);
  r.rho_m = rho_m(p, r.palette_index);
  r.rho_m_intensity = rho_m_intensity(r.I_min, (compat & SAND_COMPAT_INTENSITY_XI1) != 0u ? gr.xi.x : gr.xi.z);
  r.L_d = L_d(r.rho_m, r.f_s, r.f_e, l.L_i, L_sky_diffuse, cos_ni);
  r.L_d *= 1.0 - r.f;  // eq. 4.24
  r.L_d *= r.T_ext;    // eq. 4.26
#if SAND_GLINTS
  if (glint_model == SAND_GLINT_KAJS) {
    r.m = micro_normal(gr.xi.xy, s.wo, r.face);
    r.gdf = GDF((compat & SAND_COMPAT_GATE_XI1) != 0u ? gr.xi_pm.x : gr.xi_pm.z, p.sigma_g);
    r.G_Rs = G_strength(p.R_s);
    r.g = r.G_Rs * g_glint(r.gdf, s.wo, l.wi, r.m, cos_ni);  // eq. 4.23
    float lobe = sun_lobe_scale(p.energy_consistent);
    r.L_g = L_g(r.g, l.L_i * lobe, l.L_sky_omega * lobe, p.I_glints.rgb, compat);
  } else if (glint_model != SAND_GLINT_NONE) {
    GlintTerm g = glint_term(false, p, s.uv, s.duv_dx, s.duv_dy, s.t, s.b, s.n, l.wi, s.wo, s.dwo_dx, s.dwo_dy, l.L_i,
                             l.cone);
    r.L_g = g.L;
    r.glint_cells = g.cells;
  }
#endif
  r.L_s = r.L_f + r.L_g;  // eq. 4.23
  r.L_close = L_close(r.L_d, r.L_s, r.L_t, r.rho_m_intensity);
#endif

#if SAND_FAR
  r.L_oren = L_oren(s.n, l.wi, s.wo, p.sigma_on, compat);
  r.L_brdf = L_brdf(r.rho_n, r.f_s, r.f_e, r.L_oren, cos_ni, l.L_i, L_sky_diffuse, 1.0 - r.f, r.T_ext);
#if SAND_GLINTS
  // The far field is the footprint average of the close field: a glint_D
  // model averages to its smooth limit there (the thesis' far field has no
  // glints, eq. 4.36).
  if (glint_model != SAND_GLINT_KAJS && glint_model != SAND_GLINT_NONE)
    r.L_g_far =
        glint_term(true, p, s.uv, s.duv_dx, s.duv_dy, s.t, s.b, s.n, l.wi, s.wo, s.dwo_dx, s.dwo_dy, l.L_i, l.cone).L;
#endif
  r.L_far = L_far(r.L_brdf, r.L_f + r.L_g_far, r.L_t, r.rho_n_intensity);
#endif

#if SAND_CLOSE && SAND_FAR
  r.sig = sig(s.dist, p.sig_a, p.sig_b);
#elif SAND_FAR
  r.sig = 1.0;
#else
  r.sig = 0.0;
#endif
  r.L_final = L_final(r.L_close, r.L_far, r.sig);
  return r;
}

// The glint term's part of L_final: eq. 4.38 and 4.33 are linear in L_s = L_f + L_g and eq. 4.36 in
// its far-field glints, so L_final = G + (the same with L_g = L_g_far = 0), where
//   G = (1 - sig) rho_m^intensity L_g + sig rho_n^intensity L_g_far.
vec3 sand_glint_radiance(SandTerms r) {
  return (1.0 - r.sig) * r.rho_m_intensity * r.L_g + r.sig * r.rho_n_intensity * r.L_g_far;
}
// The share of L_final's Rec. 709 luma that is G's, in [0, 1]; 0 where L_final is black (or the ratio
// is not finite). What the glint-aware TAA options read (passes/taa.frag).
float sand_glint_share(vec3 G, vec3 L_final_) {
  const vec3 w = vec3(0.2126, 0.7152, 0.0722);
  float lf = dot(L_final_, w), lg = dot(G, w);
  float s = lf > 0.0 ? lg / lf : 0.0;
  return s >= 0.0 ? min(s, 1.0) : 0.0;
}

// What sand_shade() returns, from the terms (SAND_DEBUG).
vec3 sand_output(SandTerms r) {
#if SAND_DEBUG == SAND_DEBUG_DIFFUSE
  return r.L_d;
#elif SAND_DEBUG == SAND_DEBUG_SPECULAR
  return r.L_s;
#elif SAND_DEBUG == SAND_DEBUG_GLINTS
  return r.L_g;
#elif SAND_DEBUG == SAND_DEBUG_FRESNEL
  return r.L_f;
#elif SAND_DEBUG == SAND_DEBUG_TRANSMISSION
  return r.L_t;
#elif SAND_DEBUG == SAND_DEBUG_FAR
  return r.L_far;
#elif SAND_DEBUG == SAND_DEBUG_SIGMOID
  return vec3(r.sig);
#elif SAND_DEBUG == SAND_DEBUG_GRAIN_ID
  return r.xi;
#elif SAND_DEBUG == SAND_DEBUG_CLOSE
  return r.L_close;
#elif SAND_DEBUG == SAND_DEBUG_GLINT_CELLS
  return vec3(r.glint_cells);
#else
  return r.L_final;
#endif
}

vec3 sand_shade(SandParams p, SandSurface s, SandLight l) { return sand_output(sand_terms(p, s, l)); }

#endif  // GLINTLAB_SAND_GLSL

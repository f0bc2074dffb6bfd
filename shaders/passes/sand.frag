#version 450
// The sand material as a surface pass: gathers the macro surface, the sun and
// the sky's hemisphere term (Kajs eq. 4.2, from SH irradiance) and calls
// sand_shade(). Writes the weighted sample for accumulation; alpha = coverage;
// with SURFACE_MOTION, also the motion vector of the surface point.
#include "common/frame.glsl"
#include "sand/sand_params.glsl"
#ifdef SAND_PARAMS_WORDS
// The material block as constants (core/material/program.h, material_constants_define): its std140
// words, mapped onto the fields of sand/sand_params.glsl at their std140 offsets (a test renders both
// ways and compares). A private global rather than a const: glslang does not fold uintBitsToFloat in
// a constant initialiser, but every compiler after it folds it and all that follows from it.
const uint sand_words[72] = uint[72](SAND_PARAMS_WORDS);
#define SAND_WORD_F(i) uintBitsToFloat(sand_words[i])
#define SAND_WORD_V(i) vec4(SAND_WORD_F(i), SAND_WORD_F(i + 1), SAND_WORD_F(i + 2), SAND_WORD_F(i + 3))
SandParams sand_params = SandParams(
    vec4[8](SAND_WORD_V(0), SAND_WORD_V(4), SAND_WORD_V(8), SAND_WORD_V(12), SAND_WORD_V(16), SAND_WORD_V(20),
            SAND_WORD_V(24), SAND_WORD_V(28)),                                // palette
    SAND_WORD_V(32),                                                          // I_glints
    SAND_WORD_F(36), SAND_WORD_F(37), SAND_WORD_F(38), SAND_WORD_F(39),      // SSS, R_s, T, R_t
    SAND_WORD_F(40), SAND_WORD_F(41), SAND_WORD_F(42), SAND_WORD_F(43),      // sigma_g, P, noise_scale, ior
    SAND_WORD_F(44), SAND_WORD_F(45), SAND_WORD_F(46), SAND_WORD_F(47),      // scattering, absorption, sigma_on, sig_a
    SAND_WORD_F(48), SAND_WORD_F(49), SAND_WORD_F(50), SAND_WORD_F(51),      // sig_b, glint_intensity, _light_cone, pad
    sand_words[52], sand_words[53], sand_words[54], sand_words[55],          // appendix_compat, fresnel_half_vector, glint_model, energy_consistent
    SAND_WORD_V(56),                                                          // glint_alpha
    SAND_WORD_F(60), SAND_WORD_F(61), SAND_WORD_F(62), SAND_WORD_F(63),      // glint_log_density, specular_aa_sigma2, _kappa, pad
    vec4[2](SAND_WORD_V(64), SAND_WORD_V(68)));                               // glint_parameters
#else
layout(set = 0, binding = 1, std140) uniform MaterialUBO { SandParams sand_params; };
#endif
layout(set = 0, binding = 2) uniform sampler2D env_map;
#define GLINT_TABLE_BINDING 3  // the glint model's data table, when it declares one (glint/query.glsl)
#include "common/environment.glsl"
#include "sand/sand.glsl"
#ifndef SAND_SPECULAR_AA
#define SAND_SPECULAR_AA 0
#endif
#if SAND_SPECULAR_AA
#include "sand/specular_aa.glsl"
#endif

#ifndef COLOR_HALF
#define COLOR_HALF 0  // the surface pass sets it when the colour target is RGBA16F
#endif
#include "common/surface_interface.glsl"
#include "common/motion.glsl"

layout(location = 0) out vec4 out_color;
#if SURFACE_MOTION
layout(location = 1) out vec4 out_motion;  // common/motion.glsl
#endif
#ifndef SURFACE_FOOTPRINT_SCALE
#define SURFACE_FOOTPRINT_SCALE 1.0
#endif
#ifndef SURFACE_GLINT
#define SURFACE_GLINT 0
#endif
#if SURFACE_GLINT
// The glint layer (core/render/surface_pass.h, option glint): rgb = the glint term's part of the
// sample's radiance (sand_glint_radiance), a = its share of the luma, both weighted like the colour.
layout(location = 2) out vec4 out_glint;
#endif

void main() {
  vec3 to_eye = frame_camera_pos.xyz - v_x;
  float dist = length(to_eye);
  vec3 wo = dist > 0.0 ? to_eye / dist : vec3(0.0, 1.0, 0.0);
  // Interpolated normals can shrink; a degenerate one falls back to the
  // direction of the viewer. Seen from behind, the surface's other side faces us.
  float nl = length(v_n);
  vec3 n = nl > 1e-20 ? v_n / nl : wo;
  if (!gl_FrontFacing) n = -n;

  // A sample of a supersampled frame stands for 1/N of the pixel (N = 1/weight
  // stratified samples): its footprint is the pixel's uv extent times 1/sqrt(N),
  // so a filtered glint model integrates its own stratum, not the whole pixel.
  // SURFACE_FOOTPRINT_SCALE (core/render/surface_pass.h): s for a display-pixel footprint below the
  // output resolution.
  float footprint = sqrt(sample_jitter_weight.z) * SURFACE_FOOTPRINT_SCALE;
  SandSurface s = sand_surface(v_x_obj, v_x, n, wo, dist, v_t, v_uv, dFdx(v_uv) * footprint, dFdy(v_uv) * footprint);
  s.dwo_dx = dFdx(wo) * footprint;
  s.dwo_dy = dFdy(wo) * footprint;
  SandLight l = SandLight(frame_sun_dir.xyz, frame_sun_L.rgb, env_irradiance(n), frame_sun_dir.w);
  // Not clamped: every frame is scanned for NaN/Inf/negative values, and a
  // clamp here would hide a defect of the material.
#if SAND_SPECULAR_AA
  // The derivatives of specular AA (sand/specular_aa.glsl), taken here in uniform control flow and,
  // like the uv footprint, for the sample's stratum of the pixel.
  vec3 h = safe_normalize(l.wi + wo, n);
  vec3 h_t = vec3(dot(h, s.t), dot(h, s.b), dot(h, n));
#if SAND_SPECULAR_AA == SPECULAR_AA_KAPLANYAN2016
  vec2 h_domain = h_t.xy / max(h_t.z, 1e-4);  // the slope domain (h below the surface: the lobe sees 0)
#else
  vec2 h_domain = h_t.xy;  // the projected space (tokuyoshi2019 reads the normal only)
#endif
  SpecularAAInput aa = SpecularAAInput(dFdx(n) * footprint, dFdy(n) * footprint, dFdx(h_domain) * footprint,
                                       dFdy(h_domain) * footprint);
  SandParams shaded = sand_params;
  shaded.glint_alpha =
      specular_aa_glint_alpha(shaded.glint_alpha, aa, shaded.specular_aa_sigma2, shaded.specular_aa_kappa);
  SandTerms terms = sand_terms(shaded, s, l);
#else
  SandTerms terms = sand_terms(sand_params, s, l);
#endif
  vec3 L = sand_output(terms);
  float w = sample_jitter_weight.z;
  out_color = vec4(L * w, w);
#if SURFACE_GLINT
  vec3 G = sand_glint_radiance(terms);
  out_glint = vec4(G * w, sand_glint_share(G, terms.L_final) * w);
#endif
#if COLOR_HALF
  // An RGBA16F target holds at most 65504: what lies above is written as the
  // largest half (Vulkan leaves the conversion of larger values to the driver:
  // lavapipe saturates, others may write inf). NaN stays NaN, so a defect of
  // the material is still seen.
  out_color.rgb = mix(min(out_color.rgb, vec3(65504.0)), out_color.rgb, isnan(out_color.rgb));
#endif
#if SURFACE_MOTION
  out_motion = surface_motion(v_pix, v_prev_pix, v_eye_offset, v_prev_eye_offset);
#endif
}

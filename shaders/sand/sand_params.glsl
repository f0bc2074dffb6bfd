// Parameters of the Kajs 2022 sand material, std140 layout (vec4 array and
// groups of four scalars). Mirrored by glintlab::core::SandParamsGPU
// (core/material/sand_material.h), which static_asserts the same offsets.
#ifndef GLINTLAB_SAND_PARAMS_GLSL
#define GLINTLAB_SAND_PARAMS_GLSL

// appendix_compat bits: Appendix A behaviour where it differs from chapter 4
// (see shaders/sand/DIFFERENCES.md). 0 = chapter 4 everywhere.
#define SAND_COMPAT_RAND_NORMALIZED 1u   // xi = normalize(int3(pcg3d)) (unit vector) instead of independent uniforms
#define SAND_COMPAT_INTENSITY_XI1 2u     // rho_m^intensity from xi_1 (rand.x) instead of xi_3 (eq. 4.7)
#define SAND_COMPAT_GATE_XI1 4u          // Gaussian glint gate on xi_1 (rand.x) instead of xi_3
#define SAND_COMPAT_GLINT_SKY 8u         // glint colour (L_sky + L_i) I_glints instead of L_i I_glints (eq. 4.19)
#define SAND_COMPAT_FRESNEL_ABS 16u      // Schlick on |w_h . w_o| instead of max(0, w_h . w_o)
#define SAND_COMPAT_OREN_NAYAR_WORLD 32u // Oren-Nayar angles in the world z frame, tan(beta) saturated

// fresnel_half_vector values (eq. 4.14)
#define SAND_FRESNEL_MACRO_NORMAL 0u     // w_h = halfway of w_i and its mirror about n (= n)
#define SAND_FRESNEL_LIGHT_VIEW 1u       // w_h = normalize(w_i + w_o)

// glint_model values (core/material/glint_model.h)
#define SAND_GLINT_NONE 0u
#define SAND_GLINT_KAJS 1u      // Kajs 2022 eq. 4.17-4.23 (sand/glints.glsl)
// >= 2: a glint_D model (glint/query.glsl), 2 + its index in the registry

struct SandParams {
  vec4 palette[8];    // rgb: C[0..7] grain colours (eq. 4.4), renderer's scene-linear space
  vec4 I_glints;      // rgb: glint gain I_glints (eq. 4.20)
  float SSS;          // subsurface scattering radius multiplier (eq. 4.12-4.13)
  float R_s;          // specular roughness (eq. 4.21-4.22)
  float T;            // transmission (eq. 4.25, 4.31)
  float R_t;          // transmission roughness (eq. 4.29-4.30)
  float sigma_g;      // glint Gaussian sigma (eq. 4.17)
  float P;            // porosity factor (eq. 4.6)
  float noise_scale;  // grains per object-space unit (pcg3d seed scale)
  float ior;          // grain IOR n_2 (eq. 4.15), n_1 = 1
  float scattering;   // eq. 4.12
  float absorption;   // eq. 4.13
  float sigma_on;     // Oren-Nayar sigma in radians (eq. 4.34)
  float sig_a;        // sigmoid stretch a (eq. 4.37)
  float sig_b;        // sigmoid shift b (eq. 4.37), camera-distance units
  float glint_intensity;       // overall glint gain of the glint_D models (Zirr & Kaplanyan 2016 sec. 4.5)
  float glint_light_cone;      // light-cone angular radius (rad); < 0: the sun's (SandLight.cone)
  float glint_pad0;
  uint appendix_compat;      // SAND_COMPAT_* bits
  uint fresnel_half_vector;  // SAND_FRESNEL_*
  uint glint_model;          // SAND_GLINT_*
  uint energy_consistent;    // 0: the thesis' factors; 1: radiometrically consistent (DIFFERENCES.md)
  vec4 glint_alpha;          // xy: global Beckmann roughness alpha_g (u, v); zw: relative roughness alpha_l / alpha_g (u, v)
  float glint_log_density;       // log10 of microdetails per unit uv area (sec. 4.5)
  float specular_aa_sigma2;      // sigma^2 and kappa of the specular_aa method (sand/specular_aa.glsl)
  float specular_aa_kappa;
  float glint_pad3;
  vec4 glint_parameters[2];      // the glint_D model's own parameters in declaration order (glint/query.glsl)
};

#endif  // GLINTLAB_SAND_PARAMS_GLSL

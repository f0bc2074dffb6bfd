#version 450
// GPU harness for the sand material terms (tests/core/material/sand_material.cpp):
// one input record of SAND_IN_STRIDE floats per item (surface, light and a
// full parameter set), one output record of SAND_OUT_STRIDE floats with
// every term of SandTerms, the sand_shade() result (under the SAND_* defines
// of the run) and the Frisvad basis of the macro normal. Inputs 0-63: the
// Kajs surface, light and parameters; 64-73: energy_consistent and the glint
// parameters of Zirr & Kaplanyan 2016; 74-86: tangent frame, uv, its
// derivatives and the sun's angular radius.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "tests/glint_twins.glsl"
#include "sand/sand.glsl"

#define SAND_IN_STRIDE 96u
#define SAND_OUT_STRIDE 76u

vec3 in3(uint b) { return vec3(inputs[b], inputs[b + 1u], inputs[b + 2u]); }
vec2 in2(uint b) { return vec2(inputs[b], inputs[b + 1u]); }
void out1(uint b, float v) { outputs[b] = v; }
void out3(uint b, vec3 v) { outputs[b] = v.x; outputs[b + 1u] = v.y; outputs[b + 2u] = v.z; }

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * SAND_IN_STRIDE;
  SandSurface s;
  s.x_obj = in3(i + 0u);
  s.x = s.x_obj;
  s.n = in3(i + 3u);
  s.wo = in3(i + 6u);
  s.dist = inputs[i + 9u];
  s.t = in3(i + 74u);
  s.b = in3(i + 77u);
  s.uv = in2(i + 80u);
  s.duv_dx = in2(i + 82u);
  s.duv_dy = in2(i + 84u);
  SandLight l;
  l.wi = in3(i + 10u);
  l.L_i = in3(i + 13u);
  l.L_sky_omega = in3(i + 16u);
  l.cone = inputs[i + 86u];
  SandParams p;
  p.SSS = inputs[i + 19u];
  p.R_s = inputs[i + 20u];
  p.T = inputs[i + 21u];
  p.R_t = inputs[i + 22u];
  p.sigma_g = inputs[i + 23u];
  p.P = inputs[i + 24u];
  p.noise_scale = inputs[i + 25u];
  p.ior = inputs[i + 26u];
  p.scattering = inputs[i + 27u];
  p.absorption = inputs[i + 28u];
  p.sigma_on = inputs[i + 29u];
  p.sig_a = inputs[i + 30u];
  p.sig_b = inputs[i + 31u];
  p.glint_pad0 = 0.0; p.specular_aa_sigma2 = 0.0; p.specular_aa_kappa = 0.0; p.glint_pad3 = 0.0;
  p.glint_parameters[0] = vec4(0.0); p.glint_parameters[1] = vec4(0.0);
  p.energy_consistent = uint(inputs[i + 64u]);
  p.glint_alpha = vec4(in2(i + 65u), in2(i + 67u));
  p.glint_log_density = inputs[i + 69u];
  twin_size_variation = inputs[i + 70u];
  p.glint_intensity = inputs[i + 71u];
  p.glint_light_cone = inputs[i + 72u];
  twin_color_saturation = inputs[i + 73u];
  p.appendix_compat = uint(inputs[i + 32u]);
  p.fresnel_half_vector = uint(inputs[i + 33u]);
  p.glint_model = uint(inputs[i + 34u]);
  twin_model = p.glint_model;
  p.I_glints = vec4(in3(i + 35u), 0.0);
  for (uint k = 0u; k < 8u; ++k) p.palette[k] = vec4(in3(i + 40u + 3u * k), 1.0);

  SandTerms r = sand_terms(p, s, l);
  uint o = id * SAND_OUT_STRIDE;
  out3(o + 0u, r.xi);
  out3(o + 3u, r.xi_pm);
  out1(o + 6u, float(r.face));
  out3(o + 7u, r.m);
  out1(o + 10u, float(r.palette_index));
  out3(o + 11u, r.rho_m);
  out3(o + 14u, r.rho_n);
  out1(o + 17u, r.I_min);
  out1(o + 18u, r.rho_m_intensity);
  out1(o + 19u, r.rho_n_intensity);
  out1(o + 20u, r.f_s);
  out1(o + 21u, r.f_e);
  out1(o + 22u, r.F_Rs);
  out1(o + 23u, r.G_Rs);
  out1(o + 24u, r.f);
  out1(o + 25u, r.gdf);
  out1(o + 26u, r.g);
  out3(o + 27u, r.L_d);
  out3(o + 30u, r.L_f);
  out3(o + 33u, r.L_g);
  out3(o + 36u, r.L_s);
  out1(o + 39u, r.T_ext);
  out1(o + 40u, r.t);
  out3(o + 41u, r.L_t);
  out1(o + 44u, r.L_oren);
  out3(o + 45u, r.L_brdf);
  out3(o + 48u, r.L_far);
  out3(o + 51u, r.L_close);
  out1(o + 54u, r.sig);
  out3(o + 55u, r.L_final);
  out3(o + 58u, sand_shade(p, s, l));
  vec3 b1, b2;
  frisvad_basis(s.n, b1, b2);
  out3(o + 61u, b1);
  out3(o + 64u, b2);
  out1(o + 67u, r.glint_cells);
  out3(o + 68u, r.L_g_far);
  out1(o + 71u, 0.0);
  vec3 G = sand_glint_radiance(r);
  out3(o + 72u, G);
  out1(o + 75u, sand_glint_share(G, r.L_final));
}

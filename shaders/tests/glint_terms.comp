#version 450
// GPU harness for the glint models of Zirr & Kaplanyan 2016 (tests/core/
// material/glint_models.cpp): every intermediate of sand/glint_models.glsl
// for one shading point. Input record (GLINT_IN floats):
//   0-1 uv, 2-3 duv_dx, 4-5 duv_dy, 6-8 t, 9-11 b, 12-14 n, 15-17 wi,
//   18-20 wo, 21-23 L_i, 24-27 glint_alpha, 28 log_density,
//   29 size_variation, 30 intensity, 31 light_cone, 32 color_saturation,
//   33 ior, 34 sun cone, 35 model (its SandParams.glint_model id), 36 half_vector_blend (0/1).
// Output record (GLINT_OUT floats):
//   0-2 frame wi, 3-5 wo, 6-8 h, 9 valid; 10-23 GlintRoughness (alpha_surface,
//   alpha_g, alpha_l, alpha_m, stretch, h_cell, s_ref, cone); 24 beckmann D,
//   25 Lambda(wi), 26 wo.z Lambda(wo), 27 G2, 28 G2/cos_o, 29 Schlick F;
//   30 pmf, 31 m0, 32-33 paraboloid h; 34-39 footprint (s_c, level_f, level0,
//   level1, weight0, weight1); 40-47, 48-55 the walks of both levels (c.x,
//   c.y, j, slope, t_lo, t_hi, first, columns); 56-58 zirr D, 59 cells;
//   60-62 grains D; 63-65 glint_term of the model: L, 66 its cells; 67-69
//   glint_radiance of D = 1.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "tests/glint_twins.glsl"

#define GLINT_IN 40u
#define GLINT_OUT 72u

vec3 in3(uint b) { return vec3(inputs[b], inputs[b + 1u], inputs[b + 2u]); }
vec2 in2(uint b) { return vec2(inputs[b], inputs[b + 1u]); }
void out3(uint b, vec3 v) { outputs[b] = v.x; outputs[b + 1u] = v.y; outputs[b + 2u] = v.z; }
void out2(uint b, vec2 v) { outputs[b] = v.x; outputs[b + 1u] = v.y; }

void out_walk(uint o, GlintWalk w) {
  out2(o, w.c);
  outputs[o + 2u] = float(w.j);
  outputs[o + 3u] = w.slope;
  outputs[o + 4u] = w.t_lo;
  outputs[o + 5u] = w.t_hi;
  outputs[o + 6u] = w.first;
  outputs[o + 7u] = float(w.columns);
}

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * GLINT_IN, o = id * GLINT_OUT;
  vec2 uv = in2(i), dx = in2(i + 2u), dy = in2(i + 4u);
  vec3 t = in3(i + 6u), b = in3(i + 9u), n = in3(i + 12u), wi = in3(i + 15u), wo = in3(i + 18u), L_i = in3(i + 21u);
  SandParams p;
  for (int k = 0; k < 8; ++k) p.palette[k] = vec4(1.0);
  p.I_glints = vec4(1.0);
  p.SSS = 0.0; p.R_s = 0.0; p.T = 0.0; p.R_t = 0.0; p.sigma_g = 1.0; p.P = 0.0; p.noise_scale = 1.0;
  p.scattering = 0.0; p.absorption = 0.0; p.sigma_on = 0.0; p.sig_a = 1.0; p.sig_b = 0.0;
  p.appendix_compat = 0u; p.fresnel_half_vector = 0u; p.energy_consistent = 0u;
  p.glint_pad0 = 0.0; p.specular_aa_sigma2 = 0.0; p.specular_aa_kappa = 0.0; p.glint_pad3 = 0.0;
  p.glint_parameters[0] = vec4(0.0); p.glint_parameters[1] = vec4(0.0);
  twin_half_vector_blend = inputs[i + 36u];
  p.glint_alpha = vec4(in2(i + 24u), in2(i + 26u));
  p.glint_log_density = inputs[i + 28u];
  twin_size_variation = inputs[i + 29u];
  p.glint_intensity = inputs[i + 30u];
  p.glint_light_cone = inputs[i + 31u];
  twin_color_saturation = inputs[i + 32u];
  p.ior = inputs[i + 33u];
  float sun_cone = inputs[i + 34u];
  twin_model = uint(inputs[i + 35u]);
  p.glint_model = twin_model;

  GlintFrame f = glint_frame(t, b, n, wi, wo);
  out3(o + 0u, f.wi);
  out3(o + 3u, f.wo);
  out3(o + 6u, f.h);
  outputs[o + 9u] = f.valid ? 1.0 : 0.0;
  GlintRoughness r = glint_roughness(p, sun_cone);
  out2(o + 10u, r.alpha_surface);
  out2(o + 12u, r.alpha_g);
  out2(o + 14u, r.alpha_l);
  out2(o + 16u, r.alpha_m);
  out2(o + 18u, r.stretch);
  out2(o + 20u, r.h_cell);
  outputs[o + 22u] = r.s_ref;
  outputs[o + 23u] = r.cone;
  outputs[o + 24u] = beckmann_D(f.h, vec2(0.0), r.alpha_g);
  outputs[o + 25u] = f.wi.z > 0.0 ? beckmann_lambda(f.wi, r.alpha_surface) : 0.0;
  outputs[o + 26u] = f.wo.z > 0.0 ? beckmann_z_lambda(f.wo, r.alpha_surface) : 0.0;
  outputs[o + 27u] = smith_G2(f.wi, f.wo, f.h, r.alpha_surface);
  outputs[o + 28u] = smith_G2_over_cos_o(f.wi, f.wo, f.h, r.alpha_surface);
  outputs[o + 29u] = schlick(fresnel_f0(p.ior), dot(f.h, f.wo));
  GlintZirrPixel px = glint_zirr_pixel(f.h, r);
  outputs[o + 30u] = px.pmf;
  outputs[o + 31u] = px.m0;
  out2(o + 32u, px.hp);
  GlintFootprint fp = glint_footprint(dx, dy, r.s_ref);
  outputs[o + 34u] = fp.s_c;
  outputs[o + 35u] = fp.level_f;
  outputs[o + 36u] = float(fp.level0);
  outputs[o + 37u] = float(fp.level1);
  outputs[o + 38u] = fp.weight0;
  outputs[o + 39u] = fp.weight1;
  vec2 st_uv = glint_clamp_uv(uv) * r.stretch;
  vec2 st_dx = glint_clamp_derivative(dx) * r.stretch, st_dy = glint_clamp_derivative(dy) * r.stretch;
  out_walk(o + 40u, glint_walk(st_uv, st_dx, st_dy, r.s_ref * exp2(float(fp.level0))));
  out_walk(o + 48u, glint_walk(st_uv, st_dx, st_dy, r.s_ref * exp2(float(fp.level1))));
  GlintZirr z = glint_zirr(uv, dx, dy, f.h, r, twin_size_variation, twin_color_saturation, twin_half_vector_blend > 0.5);
  out3(o + 56u, z.D);
  outputs[o + 59u] = z.cells;
  out3(o + 60u, glint_grains_D(uv, f.h, r, twin_color_saturation));
  GlintTerm g = glint_term(false, p, uv, dx, dy, t, b, n, wi, wo, vec3(0.0), vec3(0.0), L_i, sun_cone);
  out3(o + 63u, g.L);
  outputs[o + 66u] = g.cells;
  out3(o + 67u, glint_radiance(vec3(1.0), f, r, p.ior, vec3(1.0), 1.0));
  for (uint k = 70u; k < GLINT_OUT; ++k) outputs[o + k] = 0.0;
}

#version 450
// GPU harness of the stress suite (experiments/stress/cases_math.cpp): the
// shared helpers of shaders/common/ and the scalar terms of shaders/sand/ on
// extreme arguments. One record of STRESS_IN floats per item: [0] the
// operation, [1..] its arguments; one record of STRESS_OUT floats out.
//   0 sig(x, a, b), stable_logistic(z)          in 1 x, 2 a, 3 b, 4 z;        out 0 sig, 1 logistic
//   1 frisvad_basis(n)                          in 1-3 n;                     out 0-2 b1, 3-5 b2
//   2 safe_normalize(v)                         in 1-3 v;                     out 0-2
//   3 L_oren(n, wi, wo, sigma, compat)          in 1-3 n, 4-6 wi, 7-9 wo, 10 sigma, 11 compat;
//                                               out 0 L_oren, 1 L_oren max(0, n.w_i) (what L_brdf uses)
//   4 grain_cell_key(x, scale), grain_random    in 1-3 x_obj, 4 noise_scale, 5 compat;
//                                               out 0-5 key (hi16, lo16) x3, 6-8 xi
//   5 I_min(P, dist), rho_n_intensity           in 1 P, 2 dist;               out 0, 1
//   6 transmission_t(T, R_t, n, wo, wi)         in 1 T, 2 R_t, 3-5 n, 6-8 wo, 9-11 wi; out 0
//   7 GDF(x, sigma)                             in 1 x, 2 sigma;              out 0
//   8 safe_log1p(x), safe_pow(x, y)             in 1 x, 2 y;                  out 0, 1
//   9 micro_normal(xi, wo)                      in 1-2 xi, 3-5 wo;            out 0-2 m, 3 face
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "common/math.glsl"
#include "common/frisvad.glsl"
#include "sand/sand_params.glsl"
#include "sand/micro_normals.glsl"
#include "sand/porosity.glsl"
#include "sand/transmission.glsl"
#include "sand/oren_nayar.glsl"
#include "sand/glints.glsl"
#include "sand/transition.glsl"

#define STRESS_IN 16u
#define STRESS_OUT 16u

vec3 in3(uint b) { return vec3(inputs[b], inputs[b + 1u], inputs[b + 2u]); }
void out3(uint b, vec3 v) { outputs[b] = v.x; outputs[b + 1u] = v.y; outputs[b + 2u] = v.z; }
void put_uint(uint o, uint v) { outputs[o] = float(v >> 16u); outputs[o + 1u] = float(v & 0xFFFFu); }

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * STRESS_IN, o = id * STRESS_OUT;
  for (uint k = 0u; k < STRESS_OUT; ++k) outputs[o + k] = 0.0;
  uint op = uint(inputs[i]);
  if (op == 0u) {
    outputs[o] = sig(inputs[i + 1u], inputs[i + 2u], inputs[i + 3u]);
    outputs[o + 1u] = stable_logistic(inputs[i + 4u]);
  } else if (op == 1u) {
    vec3 b1, b2;
    frisvad_basis(in3(i + 1u), b1, b2);
    out3(o, b1);
    out3(o + 3u, b2);
  } else if (op == 2u) {
    out3(o, safe_normalize(in3(i + 1u)));
  } else if (op == 3u) {
    vec3 n = in3(i + 1u), wi = in3(i + 4u);
    float L = L_oren(n, wi, in3(i + 7u), inputs[i + 10u], uint(inputs[i + 11u]));
    outputs[o] = L;
    outputs[o + 1u] = L * max(0.0, dot(n, wi));
  } else if (op == 4u) {
    uvec3 key = grain_cell_key(in3(i + 1u), inputs[i + 4u]);
    put_uint(o, key.x);
    put_uint(o + 2u, key.y);
    put_uint(o + 4u, key.z);
    out3(o + 6u, grain_random(key, uint(inputs[i + 5u])).xi);
  } else if (op == 5u) {
    float Im = I_min(inputs[i + 1u], inputs[i + 2u]);
    outputs[o] = Im;
    outputs[o + 1u] = rho_n_intensity(Im);
  } else if (op == 6u) {
    outputs[o] = transmission_t(inputs[i + 1u], inputs[i + 2u], in3(i + 3u), in3(i + 6u), in3(i + 9u));
  } else if (op == 7u) {
    outputs[o] = GDF(inputs[i + 1u], inputs[i + 2u]);
  } else if (op == 8u) {
    outputs[o] = safe_log1p(inputs[i + 1u]);
    outputs[o + 1u] = safe_pow(inputs[i + 1u], inputs[i + 2u]);
  } else if (op == 9u) {
    uint face;
    out3(o, micro_normal(vec2(inputs[i + 1u], inputs[i + 2u]), in3(i + 3u), face));
    outputs[o + 3u] = float(face);
  }
}

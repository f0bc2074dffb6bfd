#version 450
// Pixel estimates of the glint models for the limit and coherence tests
// (tests/core/material/glint_models.cpp): per pixel, the zirr term at the
// pixel centre with the pixel's footprint, the grains term supersampled on a
// GRID x GRID stratified jittered pattern over the footprint parallelogram
// (what the renderer's reference does; the microfacet factor, the same for
// every sub-sample at fixed light and view, is applied to their mean NDF),
// and the beckmann term. Local frame
// t = x, b = y, n = z. Input record (GLINT_LIMIT_IN floats): 0-1 uv, 2-3
// duv_dx, 4-5 duv_dy, 6-8 wi, 9-11 wo, 12-15 glint_alpha, 16 log_density,
// 17 size_variation, 18 light_cone, 19 color_saturation, 20 ior,
// 21 half_vector_blend (0/1).
// Output record (GLINT_LIMIT_OUT floats): 0-2 zirr L, 3-5 grains mean L,
// 6-8 beckmann L, 9 zirr cells. L_i = 1, intensity 1.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "tests/glint_twins.glsl"

#ifndef GRID
#define GRID 16
#endif
#define GLINT_LIMIT_IN 24u
#define GLINT_LIMIT_OUT 12u

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * GLINT_LIMIT_IN, o = id * GLINT_LIMIT_OUT;
  vec2 uv = vec2(inputs[i], inputs[i + 1u]);
  vec2 dx = vec2(inputs[i + 2u], inputs[i + 3u]), dy = vec2(inputs[i + 4u], inputs[i + 5u]);
  vec3 wi = vec3(inputs[i + 6u], inputs[i + 7u], inputs[i + 8u]);
  vec3 wo = vec3(inputs[i + 9u], inputs[i + 10u], inputs[i + 11u]);
  SandParams p;
  p.glint_alpha = vec4(inputs[i + 12u], inputs[i + 13u], inputs[i + 14u], inputs[i + 15u]);
  p.glint_log_density = inputs[i + 16u];
  twin_size_variation = inputs[i + 17u];
  p.glint_light_cone = inputs[i + 18u];
  twin_color_saturation = inputs[i + 19u];
  p.ior = inputs[i + 20u];
  twin_half_vector_blend = inputs[i + 21u];
  twin_model = GLINT_TWIN_ZIRR;
  p.glint_intensity = 1.0;
  const vec3 t = vec3(1.0, 0.0, 0.0), b = vec3(0.0, 1.0, 0.0), n = vec3(0.0, 0.0, 1.0), L_i = vec3(1.0);
  GlintTerm z = glint_term(false, p, uv, dx, dy, t, b, n, wi, wo, vec3(0.0), vec3(0.0), L_i, 0.0);
  vec3 beck = glint_term(true, p, uv, dx, dy, t, b, n, wi, wo, vec3(0.0), vec3(0.0), L_i, 0.0).L;
  // grains: the light and view are fixed, so the microfacet factor is applied once to the
  // mean NDF of the sub-samples (glint_term does the same per sample)
  GlintFrame f = glint_frame(t, b, n, wi, wo);
  GlintRoughness r = glint_roughness(p, 0.0);
  vec3 D = vec3(0.0);
  for (int sy = 0; sy < GRID; ++sy)
    for (int sx = 0; sx < GRID; ++sx) {
      vec3 j = pcg3d_unit(pcg3d(uvec3(id, uint(sx), uint(sy) + 0x1000u)));
      vec2 off = (vec2(sx, sy) + j.xy) / float(GRID) - 0.5;
      D += glint_grains_D(uv + off.x * dx + off.y * dy, f.h, r, twin_color_saturation);
    }
  vec3 grains = f.valid ? glint_radiance(D / float(GRID * GRID), f, r, p.ior, L_i, 1.0) : vec3(0.0);
  for (int k = 0; k < 3; ++k) {
    outputs[o + uint(k)] = z.L[k];
    outputs[o + 3u + uint(k)] = grains[k];
    outputs[o + 6u + uint(k)] = beck[k];
  }
  outputs[o + 9u] = z.cells;
  outputs[o + 10u] = 0.0;
  outputs[o + 11u] = 0.0;
}

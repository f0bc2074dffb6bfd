#version 450
// The cells the zirr walk visits for one footprint (tests/core/material/
// glint_models.cpp, footprint tests). Input record (GLINT_CELLS_IN floats):
//   0-1 uv, 2-3 duv_dx, 4-5 duv_dy, 6-9 glint_alpha, 10 log_density.
// Output record (GLINT_CELLS_OUT floats): 0 number of cells listed (weight
// > 0, both levels, in walk order), 1-2 level0, level1, 3-4 their mip
// weights, 5 level_f, 6 s_c, 7 unused; from 8 on, 6 floats per cell:
// level, index u (hi16, lo16), index v (hi16, lo16), coverage weight.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#include "sand/glint_footprint.glsl"
#include "sand/glint_roughness.glsl"

#define GLINT_CELLS_IN 12u
#define GLINT_CELLS_OUT 1024u

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * GLINT_CELLS_IN, o = id * GLINT_CELLS_OUT;
  vec2 uv = vec2(inputs[i], inputs[i + 1u]);
  vec2 dx = vec2(inputs[i + 2u], inputs[i + 3u]), dy = vec2(inputs[i + 4u], inputs[i + 5u]);
  SandParams p;
  p.glint_alpha = vec4(inputs[i + 6u], inputs[i + 7u], inputs[i + 8u], inputs[i + 9u]);
  p.glint_log_density = inputs[i + 10u];
  p.glint_light_cone = 0.0;
  GlintRoughness r = glint_roughness(p, 0.0);
  GlintFootprint fp = glint_footprint(dx, dy, r.s_ref);
  vec2 st_uv = glint_clamp_uv(uv) * r.stretch;
  vec2 st_dx = glint_clamp_derivative(dx) * r.stretch, st_dy = glint_clamp_derivative(dy) * r.stretch;
  uint n = 0u;
  for (int g = 0; g < 2; ++g) {
    float mw = g == 0 ? fp.weight0 : fp.weight1;
    if (!(mw > 0.0)) continue;
    int level = g == 0 ? fp.level0 : fp.level1;
    GlintWalk w = glint_walk(st_uv, st_dx, st_dy, r.s_ref * exp2(float(level)));
    for (int col = 0; col < w.columns; ++col)
      for (int row = 0; row < 2; ++row) {
        GlintCell c = glint_walk_cell(w, col, row);
        if (!(c.weight > 0.0) || 8u + 6u * (n + 1u) > GLINT_CELLS_OUT) continue;
        uint b = o + 8u + 6u * n;
        outputs[b] = float(level);
        outputs[b + 1u] = float(c.index.x >> 16u);
        outputs[b + 2u] = float(c.index.x & 0xFFFFu);
        outputs[b + 3u] = float(c.index.y >> 16u);
        outputs[b + 4u] = float(c.index.y & 0xFFFFu);
        outputs[b + 5u] = c.weight;
        ++n;
      }
  }
  outputs[o] = float(n);
  outputs[o + 1u] = float(fp.level0);
  outputs[o + 2u] = float(fp.level1);
  outputs[o + 3u] = fp.weight0;
  outputs[o + 4u] = fp.weight1;
  outputs[o + 5u] = fp.level_f;
  outputs[o + 6u] = fp.s_c;
  outputs[o + 7u] = 0.0;
}

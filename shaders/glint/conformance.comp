#version 450
// The conformance suite's evaluations of one glint model (experiments/
// glint_test/): the model's glint_D through the query the renderer builds
// (sand/glint_models.glsl: glint_frame, glint_roughness, glint_query), built
// in by the model's defines (core::glint_model_defines), and the smooth limit.
// Input record (CONFORMANCE_IN floats): 0-1 uv, 2-3 duv_dx, 4-5 duv_dy,
// 6-8 wi, 9-11 wo (local frame: t = x, b = y, n = z), 12-15 glint_alpha
// (alpha_g u, v, relative roughness u, v), 16 log_density, 17 light_cone
// (rad, >= 0), 18-19 unused, 20-27 the model's parameters (declaration order).
// Output record (CONFORMANCE_OUT floats): 0-2 D, 3 the limit D_g, 4 valid
// (both directions above the surface), 5-7 unused.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

#define GLINT_TABLE_BINDING 2  // the model's data table, when it declares one (glint/query.glsl)
#include "sand/glint_models.glsl"

#define CONFORMANCE_IN 28u
#define CONFORMANCE_OUT 8u

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  uint i = id * CONFORMANCE_IN, o = id * CONFORMANCE_OUT;
  vec2 uv = vec2(inputs[i], inputs[i + 1u]);
  vec2 dx = vec2(inputs[i + 2u], inputs[i + 3u]), dy = vec2(inputs[i + 4u], inputs[i + 5u]);
  vec3 wi = vec3(inputs[i + 6u], inputs[i + 7u], inputs[i + 8u]);
  vec3 wo = vec3(inputs[i + 9u], inputs[i + 10u], inputs[i + 11u]);
  SandParams p;
  p.glint_alpha = vec4(inputs[i + 12u], inputs[i + 13u], inputs[i + 14u], inputs[i + 15u]);
  p.glint_log_density = inputs[i + 16u];
  p.glint_light_cone = inputs[i + 17u];
  p.glint_parameters[0] = vec4(inputs[i + 20u], inputs[i + 21u], inputs[i + 22u], inputs[i + 23u]);
  p.glint_parameters[1] = vec4(inputs[i + 24u], inputs[i + 25u], inputs[i + 26u], inputs[i + 27u]);
  GlintFrame f = glint_frame(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0), wi, wo);
  vec3 D = vec3(0.0);
  float limit = 0.0;
  if (f.valid) {
    GlintRoughness r = glint_roughness(p, 0.0);
    GlintQuery q = glint_query(p, uv, dx, dy, f, r);
    D = glint_D(q);
    limit = glint_limit_D(q);
  }
  outputs[o] = D.x;
  outputs[o + 1u] = D.y;
  outputs[o + 2u] = D.z;
  outputs[o + 3u] = limit;
  outputs[o + 4u] = f.valid ? 1.0 : 0.0;
  outputs[o + 5u] = 0.0;
  outputs[o + 6u] = 0.0;
  outputs[o + 7u] = 0.0;
}

// The records of the GPU harnesses that evaluate the shader math for
// comparison with the fp64 twins (shaders/tests/sand_terms.comp and
// shaders/tests/glint_terms.comp): one definition of each input layout, used
// by the tests (tests/core/material/) and by `glintlab stress`.
#pragma once

#include "core/testkit/glint_fp64.h"
#include "core/material/sand_material.h"
#include "core/vk/vk_context.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace glintlab::reference::harness {

inline float f32(double x) { return static_cast<float>(x); }
inline std::array<float, 3> f3(const glint::vec3& v) { return {f32(v.x), f32(v.y), f32(v.z)}; }
inline glint::vec3 d3(const std::array<float, 3>& v) { return glint::vec3(v[0], v[1], v[2]); }

// core::run_compute in dispatches of at most 2^21 items
// (maxComputeWorkGroupCount = 65535 groups of 64).
std::vector<float> run_chunked(core::VkContext& ctx, const std::string& shader, const std::vector<std::string>& defines,
                               const std::vector<float>& in, size_t in_stride, size_t out_stride, size_t items);

// The defines shaders/tests/glint_twins.glsl needs: GLINT_TWIN_<NAME> = the
// SandParams.glint_model id of each built-in model with an fp64 twin.
std::vector<std::string> twin_defines();

// ---- shaders/tests/sand_terms.comp: one shading point of the sand material
constexpr size_t kSandTermsIn = 96, kSandTermsOut = 76;
struct SandTermsInput {
  std::array<float, 3> x_obj, n, wo, wi, L_i, L_sky;
  float dist;
  core::SandParamsGPU p;
  std::array<float, 3> t{1, 0, 0}, b{0, 1, 0};  // tangent frame (glint models)
  std::array<float, 2> uv{0, 0}, duv_dx{0, 0}, duv_dy{0, 0};
  float cone = 0;  // the sun's angular radius
};
void write_sand_terms_input(const SandTermsInput& c, float* in);  // kSandTermsIn floats
// The fp64 twin's terms of the same shading point.
sand::Terms sand_terms_of(const SandTermsInput& c, const sand::Features& features = {});

// ---- shaders/tests/glint_terms.comp: every stage of the glint models
constexpr size_t kGlintTermsIn = 40, kGlintTermsOut = 72;
struct GlintTermsInput {
  glint::vec2 uv{0.5}, dx{0}, dy{0};
  glint::vec3 t{1, 0, 0}, b{0, 1, 0}, n{0, 0, 1}, wi{0, 0, 1}, wo{0, 0, 1}, L_i{1};
  glint::Params p{glint::vec2(0.3), glint::vec2(0.1), 7, 0, 1, -1, 0, 1.5};
  double sun_cone = 0.0046;
  uint32_t model = glint::kGlintZirr;
};
// Rounds every input to the fp32 value the GPU sees.
void round_to_f32(GlintTermsInput& c);
std::vector<float> run_glint_terms(core::VkContext& ctx, const std::vector<GlintTermsInput>& cases);
// The GPU's GlintRoughness from an output record (outputs 10-23), for the
// stages after it; the half-vector blend is the input's.
glint::Roughness gpu_roughness(const float* out, const GlintTermsInput& c);

// glint_term's radiance from the GPU's own D of the model (outputs 24, 56,
// 60), in fp64: L, its largest channel, and the absolute error Schlick's F
// carries (1e-6, relative to f0 -> 0 at ior 1) scaled into radiance.
struct GlintRadiance {
  glint::vec3 L;
  double L_max = 0;
  double G_over_4cos = 0;  // G2 / (4 cos_o): the microfacet factor's scale
  double fresnel_allowance = 0;  // 1.5e-6 G_over_4cos max|D| max(L_i) intensity
};
GlintRadiance glint_radiance_of(const float* out, const GlintTermsInput& c, const glint::Frame& f,
                                const glint::Roughness& rg);

}  // namespace glintlab::reference::harness

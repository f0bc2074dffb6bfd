#include "core/testkit/harness_io.h"

#include "core/vk/compute_harness.h"

#include <algorithm>
#include <cmath>

namespace glintlab::reference::harness {

std::vector<float> run_chunked(core::VkContext& ctx, const std::string& shader, const std::vector<std::string>& defines,
                               const std::vector<float>& in, size_t in_stride, size_t out_stride, size_t items) {
  const size_t chunk = size_t(1) << 21;
  std::vector<float> out(items * out_stride);
  for (size_t b = 0; b < items; b += chunk) {
    size_t n = std::min(chunk, items - b);
    std::vector<float> part(in.begin() + long(b * in_stride), in.begin() + long((b + n) * in_stride));
    auto o = core::run_compute(ctx, shader, defines, part, n * out_stride, uint32_t(n));
    std::copy(o.begin(), o.end(), out.begin() + long(b * out_stride));
  }
  return out;
}

std::vector<std::string> twin_defines() {
  return {"GLINT_TWIN_GRAINS=" + std::to_string(glint::gpu_of_twin(glint::kGlintGrains)) + "u",
          "GLINT_TWIN_ZIRR=" + std::to_string(glint::gpu_of_twin(glint::kGlintZirr)) + "u",
          "GLINT_TWIN_BECKMANN=" + std::to_string(glint::gpu_of_twin(glint::kGlintBeckmann)) + "u"};
}

void write_sand_terms_input(const SandTermsInput& c, float* in) {
  auto put3 = [&](size_t o, const std::array<float, 3>& v) {
    for (int i = 0; i < 3; ++i) in[o + i] = v[i];
  };
  put3(0, c.x_obj);
  put3(3, c.n);
  put3(6, c.wo);
  in[9] = c.dist;
  put3(10, c.wi);
  put3(13, c.L_i);
  put3(16, c.L_sky);
  const auto& p = c.p;
  const float sc[13] = {p.SSS, p.R_s, p.T, p.R_t, p.sigma_g, p.P, p.noise_scale, p.ior, p.scattering, p.absorption,
                        p.sigma_on, p.sig_a, p.sig_b};
  for (int i = 0; i < 13; ++i) in[19 + i] = sc[i];
  in[32] = float(p.appendix_compat);
  in[33] = float(p.fresnel_half_vector);
  in[34] = float(p.glint_model);
  for (int i = 0; i < 3; ++i) in[35 + i] = p.I_glints[i];
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 3; ++i) in[40 + 3 * k + i] = p.palette[k][i];
  in[64] = float(p.energy_consistent);
  for (int i = 0; i < 4; ++i) in[65 + i] = p.glint_alpha[i];
  in[69] = p.glint_log_density;
  const glint::Params gp = glint::from_gpu(p);  // the model's own parameters, by its declaration
  in[70] = f32(gp.size_variation);
  in[71] = p.glint_intensity;
  in[72] = p.glint_light_cone;
  in[73] = f32(gp.color_saturation);
  put3(74, c.t);
  put3(77, c.b);
  for (int i = 0; i < 2; ++i) in[80 + i] = c.uv[i], in[82 + i] = c.duv_dx[i], in[84 + i] = c.duv_dy[i];
  in[86] = c.cone;
}

sand::Terms sand_terms_of(const SandTermsInput& c, const sand::Features& features) {
  sand::Surface s{c.x_obj, d3(c.n), d3(c.wo), c.dist};
  s.t = d3(c.t);
  s.b = d3(c.b);
  s.uv = glm::dvec2(c.uv[0], c.uv[1]);
  s.duv_dx = glm::dvec2(c.duv_dx[0], c.duv_dx[1]);
  s.duv_dy = glm::dvec2(c.duv_dy[0], c.duv_dy[1]);
  sand::Light l{d3(c.wi), d3(c.L_i), d3(c.L_sky), c.cone};
  return sand::sand_terms(sand::from_gpu(c.p), s, l, features);
}

void round_to_f32(GlintTermsInput& c) {
  auto r2 = [](glint::vec2& v) { v = glint::vec2(f32(v.x), f32(v.y)); };
  auto r3 = [](glint::vec3& v) { v = glint::vec3(f32(v.x), f32(v.y), f32(v.z)); };
  r2(c.uv), r2(c.dx), r2(c.dy), r3(c.t), r3(c.b), r3(c.n), r3(c.wi), r3(c.wo), r3(c.L_i);
  r2(c.p.alpha_g), r2(c.p.relative);
  c.p.log_density = f32(c.p.log_density);
  c.p.size_variation = f32(c.p.size_variation);
  c.p.intensity = f32(c.p.intensity);
  c.p.light_cone = f32(c.p.light_cone);
  c.p.color_saturation = f32(c.p.color_saturation);
  c.p.ior = f32(c.p.ior);
  c.sun_cone = f32(c.sun_cone);
}

std::vector<float> run_glint_terms(core::VkContext& ctx, const std::vector<GlintTermsInput>& cases) {
  std::vector<float> in(cases.size() * kGlintTermsIn, 0.0f);
  for (size_t i = 0; i < cases.size(); ++i) {
    const GlintTermsInput& c = cases[i];
    float* r = &in[i * kGlintTermsIn];
    auto p2 = [&](size_t o, glint::vec2 v) { r[o] = f32(v.x), r[o + 1] = f32(v.y); };
    auto p3 = [&](size_t o, glint::vec3 v) { r[o] = f32(v.x), r[o + 1] = f32(v.y), r[o + 2] = f32(v.z); };
    p2(0, c.uv), p2(2, c.dx), p2(4, c.dy);
    p3(6, c.t), p3(9, c.b), p3(12, c.n), p3(15, c.wi), p3(18, c.wo), p3(21, c.L_i);
    p2(24, c.p.alpha_g), p2(26, c.p.relative);
    r[28] = f32(c.p.log_density);
    r[29] = f32(c.p.size_variation);
    r[30] = f32(c.p.intensity);
    r[31] = f32(c.p.light_cone);
    r[32] = f32(c.p.color_saturation);
    r[33] = f32(c.p.ior);
    r[34] = f32(c.sun_cone);
    r[35] = float(glint::gpu_of_twin(c.model));
    r[36] = c.p.half_vector_blend ? 1.0f : 0.0f;
  }
  return run_chunked(ctx, "tests/glint_terms.comp", twin_defines(), in, kGlintTermsIn, kGlintTermsOut, cases.size());
}

glint::Roughness gpu_roughness(const float* o, const GlintTermsInput& c) {
  auto o2 = [](const float* v) { return glint::vec2(v[0], v[1]); };
  glint::Roughness rg;
  rg.alpha_surface = o2(o + 10);
  rg.alpha_g = o2(o + 12);
  rg.alpha_l = o2(o + 14);
  rg.alpha_m = o2(o + 16);
  rg.stretch = o2(o + 18);
  rg.h_cell = o2(o + 20);
  rg.s_ref = o[22];
  rg.cone = o[23];
  rg.hv_blend = c.p.half_vector_blend;
  return rg;
}

GlintRadiance glint_radiance_of(const float* o, const GlintTermsInput& c, const glint::Frame& f,
                                const glint::Roughness& rg) {
  auto o3 = [](const float* v) { return glint::vec3(v[0], v[1], v[2]); };
  const glint::vec3 D = c.model == glint::kGlintBeckmann ? glint::vec3(o[24])
                        : c.model == glint::kGlintGrains ? o3(o + 60)
                                                         : o3(o + 56);
  GlintRadiance r;
  r.L = glint::glint_radiance(D, f, rg, c.p.ior, c.L_i, c.p.intensity);
  r.L_max = std::max({r.L.x, r.L.y, r.L.z});
  r.G_over_4cos = f.valid ? 0.25 * glint::smith_G2_over_cos_o(f.wi, f.wo, f.h, rg.alpha_surface) : 0.0;
  const double D_max = std::max({std::fabs(D.x), std::fabs(D.y), std::fabs(D.z)});
  const double Li_max = std::max({c.L_i.x, c.L_i.y, c.L_i.z});
  r.fresnel_allowance = 1.5e-6 * r.G_over_4cos * D_max * Li_max * c.p.intensity;
  return r;
}

}  // namespace glintlab::reference::harness

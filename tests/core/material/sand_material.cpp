// The Kajs 2022 sand material: parameters/presets/pruning (core/sand_material),
// properties of the fp64 reference (tests/reference/sand_reference), and the
// GLSL terms (shaders/sand/, run through shaders/tests/sand_terms.comp)
// against the fp64 reference on random and extreme inputs.
#include "core/vk/compute_harness.h"
#include "core/util/json_check.h"
#include "core/material/sand_material.h"
#include "core/testkit/harness_io.h"
#include "core/testkit/glint_fp64.h"
#include "core/testkit/sand_fp64.h"
#include "tests/support/vk_test_util.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <map>
#include <limits>
#include <random>

using namespace glintlab;
namespace ref = glintlab::reference::sand;
using ref::vec3;

namespace {

bool finite_nonneg(const vec3& v) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]) || v[i] < 0) return false;
  return true;
}

ref::Params default_params() { return ref::from_gpu(core::SandParams::preset("thesis-default").pack()); }

}  // namespace

// ---------------------------------------------------------------- parameters

TEST(SandParams, PresetsHoldTheThesisValues) {
  auto d = core::SandParams::preset("thesis-default");  // Appendix A properties
  EXPECT_EQ(d.SSS, 0.8);
  EXPECT_EQ(d.R_s, 0.12);
  EXPECT_EQ(d.T, 0.8);
  EXPECT_EQ(d.R_t, 0.2);
  EXPECT_EQ(d.glint_sigma, 1e-5);
  EXPECT_EQ(d.P, 0.1);
  EXPECT_EQ(d.noise_scale, 2000);
  EXPECT_EQ(d.scattering, 0.2);
  EXPECT_EQ(d.absorption, 0.8);
  EXPECT_EQ(d.oren_nayar_sigma, 0.1);
  EXPECT_EQ(d.sigmoid_a, 2);
  EXPECT_EQ(d.sigmoid_b, 1.3);
  EXPECT_EQ(d.ior, 1.458);
  EXPECT_EQ(d.appendix_compat, 0u);
  auto h = core::SandParams::preset("thesis-hdri-match");  // Fig. 6.5 / 6.8
  EXPECT_EQ(h.R_s, 0.3);
  EXPECT_EQ(h.T, 0.25);
  EXPECT_EQ(h.R_t, 0.3);
  EXPECT_EQ(h.SSS, 0.0);
  for (const auto& c : h.palette) EXPECT_EQ(c, (core::SandParams::RGB{0.895, 0.713, 0.602}));
  EXPECT_EQ(core::SandParams::preset("thesis-appendix-a").appendix_compat, uint32_t(core::kSandCompatAll));
  EXPECT_THROW(core::SandParams::preset("no-such"), ConfigError);
  for (const auto& n : core::SandParams::preset_names()) EXPECT_NO_THROW(core::SandParams::preset(n).validate());
}

TEST(SandParams, JsonOverridesAndRangeErrors) {
  nlohmann::json j = {{"preset", "thesis-hdri-match"}, {"P", 0.5}, {"appendix_compat", {"glint_sky", "gate_xi1"}},
                      {"I_glints", {2, 3, 4}}};
  JsonReader r(j, "exp.json", "material");
  auto p = core::SandParams::from_json(r);
  EXPECT_EQ(p.P, 0.5);
  EXPECT_EQ(p.R_s, 0.3);
  EXPECT_EQ(p.appendix_compat, uint32_t(core::kSandCompatGlintSky | core::kSandCompatGateXi1));
  EXPECT_EQ(p.I_glints[2], 4.0);
  auto expect_error = [](nlohmann::json bad, const std::string& must_contain) {
    JsonReader rb(bad, "exp.json", "material");
    try {
      core::SandParams::from_json(rb);
      ADD_FAILURE() << "accepted " << bad.dump();
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(must_contain), std::string::npos) << e.what();
    }
  };
  expect_error({{"R_s", 1.5}}, "material.R_s");
  expect_error({{"glint_sigma", 0.0}}, "glint_sigma");
  expect_error({{"noise_scale", -1}}, "noise_scale");
  expect_error({{"palette", {{1, 1, 1}}}}, "palette");
  expect_error({{"appendix_compat", {"bogus"}}}, "bogus");
  expect_error({{"roughness", 0.3}}, "roughness");  // unknown key
  core::SandParams bad;
  bad.T = -0.1;
  EXPECT_THROW(bad.validate(), ConfigError);
  EXPECT_THROW(bad.pack(), ConfigError);
}

TEST(SandParams, PackMatchesFieldsAndModes) {
  auto p = core::SandParams::preset("thesis-hdri-match");
  p.fresnel_half_vector = "light_view";
  p.appendix_compat = core::kSandCompatOrenNayarWorld;
  auto g = p.pack();
  EXPECT_FLOAT_EQ(g.palette[5][1], 0.713f);
  EXPECT_EQ(g.palette[5][3], 1.0f);
  EXPECT_FLOAT_EQ(g.R_t, 0.3f);
  EXPECT_FLOAT_EQ(g.sig_b, 1.3f);
  EXPECT_EQ(g.fresnel_half_vector, ref::kFresnelLightView);
  EXPECT_EQ(g.glint_model, ref::kGlintKajs);
  EXPECT_EQ(g.appendix_compat, ref::kCompatOrenNayarWorld);
}

TEST(SandParams, ShaderDefinesPruneWhatARunDoesNotNeed) {
  auto has = [](const std::vector<std::string>& d, const std::string& x) {
    return std::find(d.begin(), d.end(), x) != d.end();
  };
  core::SandParams p;  // a = 2, b = 1.3
  auto all = core::shader_defines(p, {});
  EXPECT_TRUE(has(all, "SAND_TRANSMISSION=1") && has(all, "SAND_GLINTS=1") && has(all, "SAND_CLOSE=1") &&
              has(all, "SAND_FAR=1") && has(all, "SAND_DEBUG=0"));
  p.T = 0;
  EXPECT_TRUE(has(core::shader_defines(p, {}), "SAND_TRANSMISSION=0"));
  p.glint_model = core::kGlintModelNone;
  EXPECT_TRUE(has(core::shader_defines(p, {}), "SAND_GLINTS=0"));
  // sig(x) = 1/(1+exp(-2(x-1.3))) < 1e-4 for x < 1.3 - ln(9999)/2 = -3.305: never for x >= 0,
  // so make b larger: b = 10 -> far unreachable below 10 - 4.605 = 5.395.
  core::SandParams q;
  q.sigmoid_b = 10;
  EXPECT_TRUE(has(core::shader_defines(q, {0.1, 5.3}), "SAND_FAR=0"));
  EXPECT_TRUE(has(core::shader_defines(q, {0.1, 5.5}), "SAND_FAR=1"));
  auto far_only = core::shader_defines(q, {14.7, 1e9});  // 1 - sig(14.7) = 9.2e-5
  EXPECT_TRUE(has(far_only, "SAND_CLOSE=0") && has(far_only, "SAND_GLINTS=0")) << far_only[2];
  EXPECT_TRUE(has(core::shader_defines(q, {14.5, 1e9}), "SAND_CLOSE=1"));
  // a debug view keeps both fields
  auto dbg = core::shader_defines(q, {0.1, 5.3, "sigmoid"});
  EXPECT_TRUE(has(dbg, "SAND_FAR=1") && has(dbg, "SAND_DEBUG=7"));
  EXPECT_THROW(core::shader_defines(q, {0, 1, "nonsense"}), ConfigError);
  auto names = core::SandParams::debug_output_names();
  EXPECT_EQ(names.front(), "final");
  EXPECT_EQ(core::SandParams::debug_output_define("grain_id"), 8);
}

TEST(SandParams, SigmoidIsStableAtExtremes) {
  for (double x : {-1e6, 1e6, -1e300, 1e300, -std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::infinity()}) {
    double s = core::sand_sigmoid(x, 2.0, 1.3), r = ref::sig(x, 2.0, 1.3);
    EXPECT_TRUE(std::isfinite(s) && std::isfinite(r));
    EXPECT_EQ(s, x > 0 ? 1.0 : 0.0);
    EXPECT_EQ(r, x > 0 ? 1.0 : 0.0);
  }
  EXPECT_DOUBLE_EQ(core::sand_sigmoid(1.3, 2.0, 1.3), 0.5);
  EXPECT_NEAR(core::sand_sigmoid(2.3, 2.0, 1.3), 1.0 / (1.0 + std::exp(-2.0)), 1e-15);
  EXPECT_NEAR(ref::sig(2.3, 2.0, 1.3), 1.0 / (1.0 + std::exp(-2.0)), 1e-15);
}

// ---------------------------------------------------------------- fp64 reference properties

TEST(SandReference, StrengthFunctionsMatchThesisTables) {
  // Table 4.2 (T_ext, eq. 4.25 interpolates it exactly)
  const double T[5] = {0, 0.25, 0.5, 0.75, 1}, Text[5] = {1, 0.85, 0.7, 0.55, 0.1};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(ref::T_ext(T[i]), Text[i], 1e-12) << T[i];
  // Table 4.1 (F qualitatively; eq. 4.22 "min(1, .)"; G "does not exactly capture" the table)
  const double Ft[5] = {0.25, 1.0, 1.0, 0.4, 0.1}, Gt[5] = {1.0, 0.9, 0.25, 0.0, 0.0};
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(ref::F_strength(T[i]), Ft[i], 0.01) << T[i];
    EXPECT_NEAR(ref::G_strength(T[i]), Gt[i], 0.05) << T[i];
  }
  // F's polynomial stays in [0, 1] on [0, 1] without the clamp's help below 0
  for (int i = 0; i <= 1000; ++i) {
    double r = i / 1000.0;
    double poly = -20.80 * std::pow(r, 5) + 60 * std::pow(r, 4) - 55.90 * std::pow(r, 3) + 14.55 * r * r + 2 * r + 0.25;
    EXPECT_GT(poly, 0.0) << r;
  }
  EXPECT_NEAR(ref::fresnel_f0(1.458), 0.0347, 1e-4);  // silica, eq. 4.15
}

TEST(SandReference, FrisvadBasisIsOrthonormalIncludingMinusZ) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> N;
  std::vector<vec3> ns = {{0, 0, 1}, {0, 0, -1}, {0, 1e-9, -1}, {1e-4, 0, -0.999999995}, {1, 0, 0}, {0, -1, 0}};
  for (int i = 0; i < 2000; ++i) ns.push_back(glm::normalize(vec3(N(rng), N(rng), N(rng))));
  for (auto n : ns) {
    n = glm::normalize(n);
    vec3 b1, b2;
    ref::frisvad_basis(n, b1, b2);
    EXPECT_NEAR(glm::length(b1), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(b2), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(b1, b2), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(b1, n), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(glm::cross(b1, b2) - n), 0.0, 1e-12);  // right-handed
  }
}

TEST(SandReference, MicroNormalIsUnitAndMostAlignedFace) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U;
  std::normal_distribution<double> N;
  double sum_z = 0, sum_z2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    double xi1 = U(rng), xi2 = U(rng);
    vec3 q = ref::sphere_direction(xi1, xi2);
    EXPECT_NEAR(glm::length(q), 1.0, 1e-12);
    sum_z += q.z;
    sum_z2 += q.z * q.z;
    vec3 wo = glm::normalize(vec3(N(rng), N(rng), N(rng)));
    int face;
    double margin;
    vec3 m = ref::micro_normal(xi1, xi2, wo, face, margin);
    EXPECT_NEAR(glm::length(m), 1.0, 1e-12);
    // the best of 6 orthonormal +-axes has |dot| >= 1/sqrt(3)
    EXPECT_GE(glm::dot(m, wo), 1.0 / std::sqrt(3.0) - 1e-12);
    // and beats every other cube face: a rotated cube's faces are +-q and its tangent basis
    vec3 b1, b2;
    ref::frisvad_basis(q, b1, b2);
    for (const vec3& f : {b1, b2, q, -b1, -b2, -q}) EXPECT_GE(glm::dot(m, wo), glm::dot(f, wo));
  }
  // eq. 4.1 is uniform on the sphere: E[z] = 0, E[z^2] = 1/3 (4 sigma bounds)
  EXPECT_NEAR(sum_z / n, 0.0, 4 * std::sqrt(1.0 / 3.0 / n));
  EXPECT_NEAR(sum_z2 / n, 1.0 / 3.0, 4 * std::sqrt(4.0 / 45.0 / n));
}

TEST(SandReference, PaletteIndexIsUniformOverCells) {
  for (uint32_t compat : {0u, ref::kCompatRandNormalized}) {
    std::array<int, 8> count{};
    const int n = 64000;
    for (int i = 0; i < n; ++i) {
      std::array<float, 3> x{float(i % 40) + 0.5f, float((i / 40) % 40) + 0.5f, float(i / 1600) + 0.5f};
      auto r = ref::grain_random(ref::grain_cell_key(x, 1.0f), compat);
      count[ref::palette_index(r.xi)]++;
    }
    double chi2 = 0, e = n / 8.0;
    for (int c : count) chi2 += (c - e) * (c - e) / e;
    EXPECT_LT(chi2, 35.0) << "compat " << compat;  // df 7: P(chi2 > 35) ~ 1e-5
  }
}

TEST(SandReference, GrainCellKeyIsSafeAtHugeAndSignedCoordinates) {
  auto key = [](float x) { return ref::grain_cell_key({x, 0.0f, 0.0f}, 2000.0f)[0]; };
  EXPECT_EQ(key(0.0f), key(-0.0f));
  EXPECT_NE(key(0.25f / 2000), key(-0.25f / 2000));  // Appendix A's int() truncation merges these
  EXPECT_EQ(key(0.25f / 2000), key(0.75f / 2000));
  // no float -> int conversion: huge and infinite products still give a key, and
  // distinct huge coordinates give distinct cells
  EXPECT_NE(key(1e7f), key(1.0001e7f));
  EXPECT_NE(key(1e30f), key(-1e30f));
  EXPECT_NE(key(3e38f), key(1e30f));  // 3e38 * 2000 = inf in fp32
  auto r = ref::grain_random(ref::grain_cell_key({3e38f, -3e38f, 1e30f}, 1e6f), 0);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(r.xi[i] >= 0 && r.xi[i] < 1);
}

TEST(SandReference, PorosityIntensityRangeAndMean) {
  for (double P : {0.0, 0.1, 1.0})
    for (double dist : {0.0, 1e-30, 0.05, 1.0, 1e30}) {
      double Im = ref::I_min(P, dist);
      ASSERT_TRUE(Im >= 0 && Im <= 1);
      EXPECT_NEAR(Im, dist > 0 ? std::exp(-P / dist) : (P > 0 ? 0.0 : 1.0), 1e-15);
      for (uint32_t compat : {0u, ref::kCompatIntensityXi1 | ref::kCompatRandNormalized}) {
        double sum = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
          auto r = ref::grain_random(ref::pcg3d({uint32_t(i), 17u, 5u}), compat);
          double I = ref::rho_m_intensity(Im, (compat & ref::kCompatIntensityXi1) ? r.xi.x : r.xi.z);
          ASSERT_GE(I, Im - 1e-15);
          ASSERT_LE(I, 1.0 + 1e-15);
          sum += I;
        }
        // eq. 4.9 is the mean of eq. 4.7 for uniform xi (not for the normalised appendix vector)
        if (compat == 0) {
          EXPECT_NEAR(sum / n, ref::rho_n_intensity(Im), 4 * (1 - Im) / std::sqrt(12.0 * n) + 1e-15);
        }
      }
    }
}

TEST(SandReference, OrenNayarLimits) {
  vec3 n(0, 0, 1);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> N;
  for (int i = 0; i < 500; ++i) {
    vec3 wi = glm::normalize(vec3(N(rng), N(rng), N(rng))), wo = glm::normalize(vec3(N(rng), N(rng), N(rng)));
    EXPECT_DOUBLE_EQ(ref::L_oren(n, wi, wo, 0.0, 0), 1.0);  // sigma = 0: Lambert
  }
  // in-plane, theta_i = 30 deg, theta_o = 60 deg: A + B sin(60) tan(30)
  double s = 0.3, s2 = s * s, A = 1 - s2 / (2 * (s2 + 0.33)), B = 0.45 * s2 / (s2 + 0.09);
  const double d = 3.14159265358979323846 / 180;
  vec3 wi(std::sin(30 * d), 0, std::cos(30 * d)), wo(std::sin(60 * d), 0, std::cos(60 * d));
  EXPECT_NEAR(ref::L_oren(n, wi, wo, s, 0), A + B * std::sin(60 * d) * std::tan(30 * d), 1e-12);
  // opposite azimuths: cos(phi_i - phi_o) = -1 -> A
  EXPECT_NEAR(ref::L_oren(n, wi, vec3(-wo.x, 0, wo.z), s, 0), A, 1e-12);
  // any normal: rotating the configuration does not matter
  vec3 n2 = glm::normalize(vec3(1, 2, -3)), t1, t2;
  ref::frisvad_basis(n2, t1, t2);
  auto rot = [&](const vec3& v) { return v.x * t1 + v.y * t2 + v.z * n2; };
  EXPECT_NEAR(ref::L_oren(n2, rot(wi), rot(wo), s, 0), A + B * std::sin(60 * d) * std::tan(30 * d), 1e-12);
}

TEST(SandReference, FiniteAndNonNegativeOnExtremeInputs) {
  const double inf = std::numeric_limits<double>::infinity();
  auto p0 = default_params();
  vec3 up(0, 0, 1), down(0, 0, -1);
  std::vector<vec3> dirs = {up, down, {1, 0, 0}, glm::normalize(vec3(1, 0, 1e-9)), glm::normalize(vec3(1, 1, -0.3))};
  int checked = 0;
  for (const vec3& n : {up, down, glm::normalize(vec3(0, 1e-8, -1))})
    for (const vec3& wo : dirs)
      for (const vec3& wi : dirs)
        for (double dist : {0.0, 1e-30, 1.3, 1e30, inf})
          for (double sigma : {1e-6, 1e-5, 1.0})
            for (double R_s : {0.0, 1.0})
              for (double P : {0.0, 1.0})
                for (uint32_t compat : {0u, 63u}) {
                  ref::Params p = p0;
                  p.sigma_g = sigma;
                  p.R_s = R_s;
                  p.P = P;
                  p.appendix_compat = compat;
                  p.sigma_on = R_s;
                  p.fresnel_half_vector = compat ? 1u : 0u;
                  ref::Surface s{{1e30f, -1e7f, 0.0f}, n, wo, dist};
                  ref::Light l{wi, vec3(5, 4, 3), vec3(1, 1, 2)};
                  auto t = ref::sand_terms(p, s, l);
                  ASSERT_TRUE(finite_nonneg(t.L_final) && finite_nonneg(t.L_close) && finite_nonneg(t.L_far))
                      << "n " << n.z << " dist " << dist << " sigma " << sigma;
                  ASSERT_TRUE(std::isfinite(t.L_oren) && t.f >= 0 && t.f <= 1 && t.t >= 0 && t.t <= 1);
                  ++checked;
                }
  EXPECT_GT(checked, 1000);
}

// ---------------------------------------------------------------- GPU terms vs fp64

namespace {

using Case = reference::harness::SandTermsInput;
constexpr size_t kIn = reference::harness::kSandTermsIn, kOut = reference::harness::kSandTermsOut;

using reference::harness::d3;
using reference::harness::f3;

std::vector<Case> make_cases(size_t n_random, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::mt19937_64 rng2(seed + 1);  // the glint models' and units' draws (rng's sequence stays the thesis cases')
  std::uniform_real_distribution<double> U;
  std::normal_distribution<double> N;
  auto unit = [&] { return glm::normalize(vec3(N(rng), N(rng), N(rng))); };
  auto logu = [&](double lo, double hi) { return std::exp(std::log(lo) + U(rng) * (std::log(hi) - std::log(lo))); };
  auto pick01 = [&] { double u = U(rng); return u < 0.1 ? 0.0 : (u < 0.2 ? 1.0 : U(rng)); };
  std::vector<Case> cases;
  const size_t n_extreme = n_random / 2;
  for (size_t i = 0; i < n_random + n_extreme; ++i) {
    bool ext = i >= n_random;
    auto coin = [&] { return ext && U(rng) < 0.4; };
    core::SandParams sp;
    for (auto& c : sp.palette) c = {U(rng), U(rng), U(rng)};
    sp.I_glints = {logu(0.1, 1e3), logu(0.1, 1e3), logu(0.1, 1e3)};
    sp.SSS = pick01();
    sp.R_s = pick01();
    sp.T = pick01();
    sp.R_t = pick01();
    sp.glint_sigma = coin() ? (U(rng) < 0.5 ? 1e-5 : 1e-6) : logu(1e-6, 1.0);
    sp.P = pick01();
    sp.noise_scale = logu(1, 1e6);
    sp.ior = 1 + 2 * U(rng);
    sp.scattering = U(rng);
    sp.absorption = U(rng);
    sp.oren_nayar_sigma = coin() ? 0.0 : U(rng) * 1.5;
    sp.sigmoid_a = logu(1e-3, 1e3);
    sp.sigmoid_b = 20 * U(rng);
    sp.appendix_compat = U(rng) < 0.5 ? 0u : uint32_t(rng() % 64);
    sp.fresnel_half_vector = U(rng) < 0.5 ? "macro_normal" : "light_view";
    sp.glint_model = U(rng) < 0.9 ? core::kGlintModelKajs : core::kGlintModelNone;
    // 40 % of the kajs items use grains, zirr or beckmann; half of all items are energy consistent
    if (sp.glint_model == core::kGlintModelKajs && U(rng2) < 0.4)
      sp.glint_model = std::vector<std::string>{"grains", "zirr", "beckmann"}[rng2() % 3];
    auto own = [&sp](const char* name, double v) {  // a model's own parameter, where it declares it
      if (const core::GlintModelDecl* d = sp.glint_decl(); d && d->parameter(name)) sp.glints.model[name] = v;
    };
    sp.energy_consistent = U(rng2) < 0.5;
    auto logu2 = [&](double lo, double hi) { return std::exp(std::log(lo) + U(rng2) * (std::log(hi) - std::log(lo))); };
    sp.glints.alpha_g = {logu2(0.05, 1), logu2(0.05, 1)};
    sp.glints.relative_roughness = {logu2(0.05, 1), logu2(0.05, 1)};
    sp.glints.log_density = 14 * U(rng2);
    own("size_variation", U(rng2) < 0.5 ? 0.0 : 2 * U(rng2));
    sp.glints.intensity = logu2(0.1, 100);
    if (U(rng2) < 0.5) sp.glints.light_cone = 0.5 * U(rng2);
    own("color_saturation", U(rng2) < 0.5 ? 0.0 : U(rng2));
    Case c;
    c.p = sp.pack();
    c.cone = float(0.01 * U(rng2));
    c.uv = {float(10 * U(rng2)), float(10 * U(rng2))};
    double fs = logu2(1e-8, 0.1);
    c.duv_dx = {float(N(rng2) * fs), float(N(rng2) * fs)};
    c.duv_dy = {float(N(rng2) * fs), float(N(rng2) * fs)};
    vec3 n = coin() ? vec3(0, 0, -1) : (coin() ? vec3(0, 0, 1) : unit());
    vec3 wo = unit(), wi = unit();
    if (ext) {
      vec3 t = glm::normalize(glm::cross(n, unit()));
      double u = U(rng);
      if (u < 0.2) wo = t;                                        // grazing view
      else if (u < 0.4) wo = glm::normalize(wo - 2.0 * n * std::max(0.0, glm::dot(wo, n)));  // back-facing
      else if (u < 0.5) wo = n;
      u = U(rng);
      if (u < 0.2) wi = -wo;
      else if (u < 0.3) wi = wo;
      else if (u < 0.4) wi = glm::normalize(glm::cross(n, unit()));
    }
    c.n = f3(n);
    c.wo = f3(wo);
    c.wi = f3(wi);
    {
      vec3 t = glm::normalize(glm::cross(n, glm::normalize(vec3(N(rng2), N(rng2), N(rng2)))));
      c.t = f3(t);
      c.b = f3(glm::cross(n, t) * (U(rng2) < 0.5 ? 1.0 : -1.0));
    }
    vec3 x = coin() ? vec3(N(rng), N(rng), N(rng)) * logu(1e7, 1e30) : vec3(N(rng), N(rng), N(rng)) * 10.0;
    c.x_obj = f3(x);
    double dist = logu(1e-6, 1e6);
    if (coin()) dist = std::vector<double>{0.0, 1e-30, 1e30, 3e38}[rng() % 4];
    c.dist = float(dist);
    c.L_i = f3(vec3(U(rng), U(rng), U(rng)) * 10.0);
    c.L_sky = f3(vec3(U(rng), U(rng), U(rng)) * 2.0);
    cases.push_back(c);
  }
  return cases;
}

ref::Terms ref_terms(const Case& c, const ref::Features& ft = {}) { return reference::harness::sand_terms_of(c, ft); }

std::vector<float> run(core::VkContext& ctx, const std::vector<Case>& cases, const std::vector<std::string>& defines) {
  std::vector<float> in(cases.size() * kIn, 0.0f);
  for (size_t i = 0; i < cases.size(); ++i) reference::harness::write_sand_terms_input(cases[i], &in[i * kIn]);
  std::vector<std::string> d = defines;
  for (auto& t : reference::harness::twin_defines()) d.push_back(t);
  return core::run_compute(ctx, "tests/sand_terms.comp", d, in, cases.size() * kOut, uint32_t(cases.size()));
}

// Error statistics of one term: |gpu - ref| <= rel |ref| + abs_floor must hold.
std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

struct TermCheck {
  std::string name;
  size_t compared = 0, failed = 0, skipped = 0;
  double worst_rel = 0;
  std::string first_failure;
  void check(size_t item, double gpu, double want, double rel, double abs_floor) {
    ++compared;
    double err = std::fabs(gpu - want);
    double scale = std::max(std::fabs(want), rel > 0 ? abs_floor / rel : abs_floor);
    worst_rel = std::max(worst_rel, err / scale);
    if (!(err <= rel * std::fabs(want) + abs_floor)) {
      if (!failed++)
        first_failure = "item " + std::to_string(item) + ": gpu " + fmt(gpu) + " ref " + fmt(want) + " (err " + fmt(err) +
                        ", bound " + fmt(rel * std::fabs(want) + abs_floor) + ")";
    }
  }
};

}  // namespace

// Stated bounds (fp32 shader vs fp64 reference, both on the same fp32 inputs):
//   every term:  |gpu - ref| <= 2e-5 |ref| + floor, floor = 1e-6 S, where S is the
//     item's radiance scale (max L_i + max L_sky) * max(1, I_glints, palette), and
//     S = 1 for dimensionless terms; added to the floor where a term contains
//   - F(R_s) (f, L_f, L_d, L_s, L_brdf, L_far, L_close, L_final): 2e-5 S (eq. 4.22's
//     polynomial cancels terms up to 60 down to 0.1);
//   - Oren-Nayar (L_oren, L_brdf, L_far, L_final): 1e-6 S / max(cos beta, 1e-3) (tan beta);
//   - the Gaussian gate (GDF, g, L_g and sums): relative part 2e-5 + 2e-7 r^2 with
//     r = |x|/sigma (the exponent -r^2/2 carries fp32 rounding ~ r^2 1.2e-7), and
//     G gdf (2e-5 max(0, n.w_i) + 3e-7) S for the mirror term (micro normal m:
//     |dm| <= 1e-5) and the fp32 cosine max(0, n.w_i) (absolute error ~3e-7). Discontinuous terms must agree exactly: grain
// random numbers, palette index, cube face; the face and the terms built on the
// micro normal are compared only where the fp64 face margin exceeds 1e-4, the
// palette (normalised-random option only) where |xi - 0.5| > 1e-5.
TEST(SandGpu, EveryTermMatchesFp64OnRandomAndExtremeInputs) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  auto cases = make_cases(4000, 2024);
  auto out = run(ctx, cases, {});
  ASSERT_EQ(out.size(), cases.size() * kOut);

  std::map<std::string, TermCheck> checks;
  size_t nonfinite = 0, negative = 0, face_skipped = 0, palette_mismatch = 0, face_mismatch = 0, xi_mismatch = 0,
         lobe_items = 0, lobe_skipped = 0, cells_compared = 0, cells_mismatch = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const float* o = &out[i * kOut];
    for (size_t k = 0; k < 71; ++k) {
      if (!std::isfinite(o[k])) ++nonfinite;
      bool signed_out = (k >= 3 && k <= 5) || (k >= 7 && k <= 9) || k >= 61;  // xi_pm, m, basis
      if (!signed_out && o[k] < 0) ++negative;
    }
    ref::Terms r = ref_terms(c);
    double S = 0;
    for (int k = 0; k < 3; ++k) S = std::max(S, double(c.L_i[k])), S = std::max(S, double(c.L_i[k]) + c.L_sky[k]);
    double gain = 1;
    for (int k = 0; k < 3; ++k) gain = std::max(gain, double(c.p.I_glints[k]));
    for (auto& col : c.p.palette) gain = std::max({gain, double(col[0]), double(col[1]), double(col[2])});
    S *= gain;
    if (c.p.energy_consistent) S *= 3.14159265358979323846;  // the sky diffuse's factor pi
    const double rel = 2e-5, floor1 = 1e-6, floorS = 1e-6 * S;
    // eq. 4.22's polynomial cancels terms up to 60 to values down to 0.1: F carries
    // an fp32 error up to sum|c_k| 2^-24 ~ 1e-5, and so does every term with f or 1 - f
    const double floorF = 2e-5, floorFS = 2e-5 * S;
    // the mirror term of eq. 4.18 reads m, whose components carry 1e-5 (cos/sin of 2 pi xi in fp32)
    double cos_ni = std::max(0.0, glm::dot(d3(c.n), d3(c.wi)));
    // and max(0, n.w_i), whose fp32 dot carries ~3e-7 absolute
    const double floor_g = r.G_Rs * r.gdf * (2e-5 * cos_ni + 3e-7), floor_Lg = floor_g * S;
    double gate_r = std::fabs(r.gate_x) / double(c.p.sigma_g);
    double rel_g = rel + 2e-7 * std::min(gate_r * gate_r, 200.0);
    vec3 n = d3(c.n);
    double cos_beta = std::max({0.0, glm::dot(n, d3(c.wi)), glm::dot(n, d3(c.wo))});
    if (c.p.appendix_compat & ref::kCompatOrenNayarWorld)
      cos_beta = std::max(std::fabs(double(c.wi[2])), std::fabs(double(c.wo[2])));
    double floorON = floorS / std::max(cos_beta, 1e-3);

    auto chk = [&](const std::string& name, size_t off, double want, double rl, double fl) {
      auto& t = checks[name];
      t.name = name;
      t.check(i, o[off], want, rl, fl);
    };
    auto chk3 = [&](const std::string& name, size_t off, const vec3& want, double rl, double fl) {
      for (int k = 0; k < 3; ++k) chk(name, off + k, want[k], rl, fl);
    };
    for (int k = 0; k < 3; ++k) {
      // exact: xi are multiples of 2^-24 computed from the exact uint32 hash
      bool exact = !(c.p.appendix_compat & ref::kCompatRandNormalized);
      if (exact && o[k] != r.xi[k]) ++xi_mismatch;
      if (!exact) chk("xi (normalised)", k, r.xi[k], rel, 1e-6);
    }
    bool palette_decidable = r.palette_margin > 1e-5;
    if (palette_decidable && o[10] != r.palette_index) ++palette_mismatch;
    bool glints_on = c.p.glint_model == ref::kGlintKajs;
    bool face_ok = !glints_on || r.face_margin > 1e-4;
    if (!face_ok) ++face_skipped;
    if (glints_on && face_ok && o[6] != r.face) ++face_mismatch;
    if (palette_decidable) chk3("rho_m", 11, r.rho_m, 0, 0);
    chk3("rho_n", 14, r.rho_n, rel, floor1);
    chk("I_min", 17, r.I_min, rel, floor1);
    if (palette_decidable) chk("rho_m_intensity", 18, r.rho_m_intensity, rel, floor1);
    chk("rho_n_intensity", 19, r.rho_n_intensity, rel, floor1);
    chk("f_s", 20, r.f_s, rel, floor1);
    chk("f_e", 21, r.f_e, rel, floor1);
    chk("F(R_s)", 22, r.F_Rs, rel, floorF);
    chk("f", 24, r.f, rel, floorF);
    chk3("L_f", 30, r.L_f, rel, floorFS);
    chk("T_ext", 39, r.T_ext, rel, floor1);
    chk("t", 40, r.t, rel, floor1);
    chk3("L_t", 41, r.L_t, rel, floorS);
    chk("L_oren", 44, r.L_oren, rel, floor1 / std::max(cos_beta, 1e-3));
    chk3("L_brdf", 45, r.L_brdf, rel, floorON + floorFS);
    // the glint models of Zirr & Kaplanyan 2016: the beckmann lobe (beckmann's L_g and every
    // model's L_g_far) against the twin with its sensitivity to the fp32 half vector
    // (dh ~ 3e-7: dot products and normalisation), rel_b = 3e-5 + 2 sqrt(q) dx / alpha_min
    // + 4 dh / h.z, dx = dh (1 + |x|) / h.z the slope's error, q = |x / alpha_g|^2;
    // compared where rel_b < 1e-2. grains and zirr decide per cell on fp32 h and are
    // compared stage by stage in glint_models.cpp: here their GPU L_g is substituted into
    // the sums, which checks the wiring.
    const uint32_t model = reference::glint::twin_of_gpu(c.p.glint_model);
    const bool micro = model == reference::glint::kGlintGrains || model == reference::glint::kGlintZirr;
    const bool lobe_model = micro || model == reference::glint::kGlintBeckmann;
    double rel_b = 1.0;
    if (lobe_model) {
      namespace gr = glintlab::reference::glint;
      gr::Frame fr = gr::frame(d3(c.t), d3(c.b), n, d3(c.wi), d3(c.wo));
      gr::Roughness rr = gr::roughness(gr::from_gpu(c.p), c.cone);
      // the validity of the lobe (w_i, w_o, h above the surface) is decided on fp32 directions
      double margin = std::min({std::fabs(fr.wi.z), std::fabs(fr.wo.z), glm::length(fr.wi + fr.wo)});
      if (fr.valid) margin = std::min(margin, fr.h.z);
      if (margin < 1e-5) {
        rel_b = 1.0;
      } else if (fr.valid) {
        double dh = 3e-7, xmax = std::max(std::fabs(fr.h.x), std::fabs(fr.h.y)) / fr.h.z;
        double q = std::pow(fr.h.x / fr.h.z / rr.alpha_g.x, 2) + std::pow(fr.h.y / fr.h.z / rr.alpha_g.y, 2);
        double dx = dh * (1 + xmax) / fr.h.z;
        rel_b = 3e-5 + 2 * std::sqrt(q) * dx / std::min(rr.alpha_g.x, rr.alpha_g.y) + 4 * dh / fr.h.z;
        if (q > 87) rel_b = 1.0;  // the exp cut-off at 88
      } else {
        rel_b = 0;  // no lobe: exactly 0 on both sides
      }
    }
    const bool lobe_ok = rel_b < 1e-2;
    lobe_items += lobe_model;
    if (lobe_model && !lobe_ok) ++lobe_skipped;
    vec3 L_g_far_gpu(o[68], o[69], o[70]);
    double floor_far = 0;
    if (lobe_model && lobe_ok) {
      chk3("L_g_far (beckmann)", 68, r.L_g_far, rel_b, 1e-30);
      floor_far = rel_b * std::max({r.L_g_far.x, r.L_g_far.y, r.L_g_far.z}) * r.rho_n_intensity;
    }
    if (!lobe_model) chk3("L_g_far (none)", 68, vec3(0), 0, 0);
    if (!lobe_model || lobe_ok) chk3("L_far", 48, r.L_far, rel, floorON + floorFS + floor_far);
    vec3 L_g_gpu(o[33], o[34], o[35]);
    double floor_new = 0;  // the new models' L_g error in the sums
    vec3 L_g_sub = r.L_g;
    if (model == reference::glint::kGlintBeckmann && lobe_ok) {
      chk3("L_g (beckmann)", 33, r.L_g, rel_b, 1e-30);
      floor_new = rel_b * std::max({r.L_g.x, r.L_g.y, r.L_g.z});
    }
    if (micro) {
      L_g_sub = L_g_gpu;
      floor_new = 1e-6 * std::max({L_g_gpu.x, L_g_gpu.y, L_g_gpu.z});
      if (model == reference::glint::kGlintZirr && r.glint_slack > 0 && r.glint_cells > 0 && o[67] > 0) {
        ++cells_compared;
        if (o[67] != r.glint_cells) ++cells_mismatch;
      }
    } else {
      chk("glint_cells (not zirr)", 67, 0.0, 0, 0);
    }
    // the sums with L_g substituted (no change for kajs/none/beckmann)
    vec3 L_s_sub = r.L_f + L_g_sub;
    vec3 L_close_sub = ref::L_close(r.L_d, L_s_sub, r.L_t, r.rho_m_intensity);
    vec3 L_final_sub = ref::L_final(L_close_sub, r.L_far, r.sig);
    chk("sig", 54, r.sig, rel, floor1);
    if (palette_decidable) chk3("L_d", 27, r.L_d, rel, floorFS);
    if (glints_on && face_ok) {
      chk3("m", 7, r.m, 0, 1e-5);
      chk("G(R_s)", 23, r.G_Rs, rel, floor1);
      chk("GDF", 25, r.gdf, rel_g, 1e-30);
      chk("g", 26, r.g, rel_g, floor_g + 1e-30);
      chk3("L_g", 33, r.L_g, rel_g, floor_Lg + 1e-30);
    }
    if (face_ok && palette_decidable && (!lobe_model || lobe_ok || micro)) {
      double fl_new = floor_new + floor_far;
      chk3("L_s", 36, L_s_sub, rel_g, floorFS + floor_Lg + floor_new);
      chk3("L_close", 51, L_close_sub, rel_g, floorFS + floor_Lg + floor_new);
      if (!micro || lobe_ok) {
        chk3("L_final", 55, L_final_sub, rel_g, floorON + floorFS + floor_Lg + fl_new);
        chk3("sand_shade", 58, L_final_sub, rel_g, floorON + floorFS + floor_Lg + fl_new);
        // The glint layer the glint-aware TAA reads (passes/sand.frag): G within the bound of its
        // L_g terms; its share of the luma where L_final's luma is 1e3 times its absolute bound at
        // least, within 4 rel_g + 2 (bound of G + bound of L_final) / luma (a ratio of two values
        // with those errors).
        const vec3 G_sub = ref::glint_radiance(L_g_sub, r.L_g_far, r.rho_m_intensity, r.rho_n_intensity, r.sig);
        const double floor_G = floor_Lg + fl_new;
        chk3("glint radiance", 72, G_sub, rel_g, floor_G + 1e-30);
        const double lf = glm::dot(L_final_sub, vec3(0.2126, 0.7152, 0.0722));
        const double floor_all = floorON + floorFS + floor_Lg + fl_new;
        if (lf > 1e3 * floor_all) {
          chk("glint share", 75, ref::glint_share(G_sub, L_final_sub), 0, 4 * rel_g + 2 * (floor_G + floor_all) / lf);
        }
      }
    }
    vec3 b1, b2;
    ref::frisvad_basis(n, b1, b2);
    chk3("frisvad b1", 61, b1, rel, floor1);
    chk3("frisvad b2", 64, b2, rel, floor1);
  }
  EXPECT_EQ(nonfinite, 0u);
  EXPECT_EQ(negative, 0u);
  EXPECT_EQ(xi_mismatch, 0u);
  EXPECT_EQ(palette_mismatch, 0u);
  EXPECT_EQ(face_mismatch, 0u);
  EXPECT_LT(face_skipped, cases.size() / 50) << "too many items near a face boundary to be a real test";
  // (a third of the items are extreme: grazing, w_i = -w_o, w_o = n ...)
  EXPECT_LT(lobe_skipped, lobe_items / 4) << "too many beckmann lobes too sensitive to fp32 to compare";
  EXPECT_EQ(cells_mismatch, 0u);
  EXPECT_GT(cells_compared, 20u);
  for (auto& [name, t] : checks) {
    EXPECT_EQ(t.failed, 0u) << name << ": " << t.failed << " of " << t.compared << " outside the bound; first "
                            << t.first_failure;
    EXPECT_GT(t.compared, 100u) << name;
    RecordProperty("max_rel_" + name, std::to_string(t.worst_rel));
  }
  if (std::getenv("GLINTLAB_PRINT_ERRORS"))
    for (auto& [name, t] : checks) printf("%-18s compared %6zu worst err/bound-scale %.3g\n", name.c_str(), t.compared, t.worst_rel);
}

TEST(SandGpu, PrunedAndDebugVariantsAgree) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  auto cases = make_cases(300, 99);
  for (auto& c : cases) {
    c.p.T = 0;  // so SAND_TRANSMISSION=0 is exact
    c.p.appendix_compat = 0;
  }
  // 6 compiles (pipeline creation dominates the cold run): each variant checks
  // several defines at once
  auto full = run(ctx, cases, {});
  auto no_t_g = run(ctx, cases, {"SAND_TRANSMISSION=0", "SAND_GLINTS=0"});
  auto no_far = run(ctx, cases, {"SAND_FAR=0"});
  auto no_close = run(ctx, cases, {"SAND_CLOSE=0", "SAND_DEBUG=7"});
  auto dbg_grain = run(ctx, cases, {"SAND_DEBUG=8"});
  auto dbg_glints = run(ctx, cases, {"SAND_DEBUG=3"});
  auto dbg_cells = run(ctx, cases, {"SAND_DEBUG=10"});
  size_t glinting = 0, counting = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const float* f = &full[i * kOut];
    const size_t o = i * kOut;
    glinting += f[33] > 0;
    counting += f[67] > 0;
    const bool lobe_model = reference::glint::twin_of_gpu(cases[i].p.glint_model) != 0u;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(no_t_g[o + 41 + k], 0.0f) << i;         // no L_t
      EXPECT_EQ(no_t_g[o + 33 + k], 0.0f) << i;         // no L_g
      EXPECT_EQ(no_t_g[o + 27 + k], f[27 + k]) << i;    // L_d: T = 0 gives T_ext = 1 exactly
      if (!lobe_model) {
        EXPECT_EQ(no_t_g[o + 48 + k], f[48 + k]) << i;  // L_far unchanged (no glints in it)
      }
      EXPECT_EQ(no_t_g[o + 68 + k], 0.0f) << i;         // no beckmann glints in L_far either
      EXPECT_EQ(dbg_cells[o + 58 + k], f[67]) << i;     // debug glint_cells = cells visited
      EXPECT_EQ(no_far[o + 58 + k], f[51 + k]) << i;    // L_final = L_close
      EXPECT_EQ(no_close[o + 55 + k], f[48 + k]) << i;  // L_final = L_far
      EXPECT_EQ(no_close[o + 58 + k], 1.0f) << i;       // debug sigmoid: far only
      EXPECT_EQ(dbg_grain[o + 58 + k], f[0 + k]) << i;  // debug grain id = xi
      EXPECT_EQ(dbg_glints[o + 58 + k], f[33 + k]) << i;
    }
  }
  EXPECT_GT(glinting, 0u);  // the glint comparison is not vacuous
  EXPECT_GT(counting, 0u);  // some zirr items visited cells
}

// The C++ mirror must have the offsets glslang gives the GLSL struct in a
// std140 uniform block (the renderer's UBO).
TEST(SandParams, GpuStructMatchesGlslStd140Offsets) {
  std::ifstream f(std::string(GLINTLAB_SHADER_DIR) + "/sand/sand_params.glsl");
  ASSERT_TRUE(f.good());
  std::stringstream ss;
  ss << f.rdbuf();
  std::string src = "#version 450\n" + ss.str() +
                    "layout(std140, set = 0, binding = 0) uniform U { SandParams p; } u;\n"
                    "layout(local_size_x = 1) in;\n"
                    "layout(std430, set = 0, binding = 1) buffer O { float o[]; };\n"
                    "void main() { o[0] = u.p.palette[7].x + u.p.I_glints.x + u.p.SSS + u.p.sigma_g + u.p.scattering"
                    " + u.p.sig_b + float(u.p.appendix_compat + u.p.glint_model + u.p.energy_consistent)"
                    " + u.p.glint_intensity + u.p.glint_light_cone + u.p.glint_pad0 + u.p.glint_alpha.w"
                    " + u.p.glint_log_density + u.p.glint_parameters[1].w; }\n";
  glslang::InitializeProcess();  // reference-counted; idempotent
  {
    glslang::TShader sh(EShLangCompute);
    const char* text = src.c_str();
    sh.setStrings(&text, 1);
    sh.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
    sh.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
    sh.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
    ASSERT_TRUE(sh.parse(GetDefaultResources(), 450, false, EShMsgDefault)) << sh.getInfoLog();
    glslang::TProgram prog;
    prog.addShader(&sh);
    ASSERT_TRUE(prog.link(EShMsgDefault)) << prog.getInfoLog();
    ASSERT_TRUE(prog.buildReflection());
    std::map<std::string, int> off;
    for (int i = 0; i < prog.getNumUniformVariables(); ++i)
      off[prog.getUniform(i).name] = prog.getUniform(i).offset;
    auto at = [&](const std::string& m) {
      auto it = off.find("U.p." + m);
      return it == off.end() ? -1 : it->second;
    };
    EXPECT_EQ(at("palette"), int(offsetof(core::SandParamsGPU, palette)));
    EXPECT_EQ(at("I_glints"), int(offsetof(core::SandParamsGPU, I_glints)));
    EXPECT_EQ(at("SSS"), int(offsetof(core::SandParamsGPU, SSS)));
    EXPECT_EQ(at("sigma_g"), int(offsetof(core::SandParamsGPU, sigma_g)));
    EXPECT_EQ(at("scattering"), int(offsetof(core::SandParamsGPU, scattering)));
    EXPECT_EQ(at("sig_b"), int(offsetof(core::SandParamsGPU, sig_b)));
    EXPECT_EQ(at("appendix_compat"), int(offsetof(core::SandParamsGPU, appendix_compat)));
    EXPECT_EQ(at("glint_model"), int(offsetof(core::SandParamsGPU, glint_model)));
    EXPECT_EQ(at("energy_consistent"), int(offsetof(core::SandParamsGPU, energy_consistent)));
    EXPECT_EQ(at("glint_intensity"), int(offsetof(core::SandParamsGPU, glint_intensity)));
    EXPECT_EQ(at("glint_light_cone"), int(offsetof(core::SandParamsGPU, glint_light_cone)));
    EXPECT_EQ(at("glint_pad0"), int(offsetof(core::SandParamsGPU, glint_pad0)));
    EXPECT_EQ(at("glint_alpha"), int(offsetof(core::SandParamsGPU, glint_alpha)));
    EXPECT_EQ(at("glint_log_density"), int(offsetof(core::SandParamsGPU, glint_log_density)));
    EXPECT_EQ(at("glint_parameters"), int(offsetof(core::SandParamsGPU, glint_parameters)));
    int block = -1;
    for (int i = 0; i < prog.getNumUniformBlocks(); ++i)
      if (prog.getUniformBlock(i).name == "U") block = i;
    ASSERT_GE(block, 0);
    EXPECT_EQ(prog.getUniformBlock(block).size, int(sizeof(core::SandParamsGPU)));
  }
  // no FinalizeProcess: other tests of this process may call glslang too
}

// Geometric specular anti-aliasing ("specular_aa", shaders/sand/specular_aa.glsl): the shader against
// its fp64 twin (core/testkit/specular_aa_fp64.h) on random and extreme derivatives, the twin against
// widenings worked out by hand from the papers' equations, and the option's JSON, defines and truth.
#include "core/material/sand_material.h"
#include "core/testkit/specular_aa_fp64.h"
#include "core/util/json_check.h"
#include "core/vk/compute_harness.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace glintlab;
using reference::SpecularAA;
using reference::SpecularAAInput;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kIn = 16, kOut = 6;  // shaders/tests/specular_aa.comp

struct Case {
  glm::dvec4 alpha;
  SpecularAAInput d;
  double sigma2, kappa;
};

std::vector<float> run(SpecularAA method, const std::vector<Case>& cases) {
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  std::vector<float> in;
  for (const Case& c : cases) {
    for (int i = 0; i < 4; ++i) in.push_back(float(c.alpha[i]));
    for (const glm::dvec3& v : {c.d.dn_dx, c.d.dn_dy})
      for (int i = 0; i < 3; ++i) in.push_back(float(v[i]));
    for (const glm::dvec2& v : {c.d.dh_dx, c.d.dh_dy})
      for (int i = 0; i < 2; ++i) in.push_back(float(v[i]));
    in.push_back(float(c.sigma2));
    in.push_back(float(c.kappa));
  }
  return core::run_compute(ctx, "tests/specular_aa.comp", {"SAND_SPECULAR_AA=" + std::to_string(int(method))}, in,
                           cases.size() * kOut, uint32_t(cases.size()));
}

// The case as the GPU sees it: every input rounded to fp32 first.
Case as_fp32(Case c) {
  for (int i = 0; i < 4; ++i) c.alpha[i] = float(c.alpha[i]);
  for (int i = 0; i < 3; ++i) {
    c.d.dn_dx[i] = float(c.d.dn_dx[i]);
    c.d.dn_dy[i] = float(c.d.dn_dy[i]);
  }
  for (int i = 0; i < 2; ++i) {
    c.d.dh_dx[i] = float(c.d.dh_dx[i]);
    c.d.dh_dy[i] = float(c.d.dh_dy[i]);
  }
  c.sigma2 = float(c.sigma2);
  c.kappa = float(c.kappa);
  return c;
}

std::vector<Case> cases() {
  std::mt19937 rng(56);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Case> out;
  for (int n = 0; n < 2000; ++n) {
    Case c;
    c.alpha = {std::pow(10.0, -3.0 + 3.0 * u(rng)), std::pow(10.0, -3.0 + 3.0 * u(rng)), 0.001 + u(rng),
               0.001 + u(rng)};
    // derivatives over six decades: from a plane's rounding noise to a normal turning by a radian a pixel
    auto dv = [&] { return std::pow(10.0, -6.0 + 6.0 * u(rng)) * (u(rng) < 0.5 ? -1.0 : 1.0); };
    c.d.dn_dx = {dv(), dv(), dv()};
    c.d.dn_dy = {dv(), dv(), dv()};
    c.d.dh_dx = {dv(), dv()};
    c.d.dh_dy = {dv(), dv()};
    c.sigma2 = n % 3 == 0 ? 1.0 / (2.0 * kPi) : 0.25;
    c.kappa = n % 5 == 0 ? 0.01 : 0.18;
    out.push_back(c);
  }
  // the ends: alpha 1, the smallest alpha, a NaN and an infinite derivative, a normal that does not turn
  Case e{{1.0, 1e-3, 0.5, 1.0}, {{0.1, 0, 0}, {0, 0, 0}, {0.2, 0.0}, {0.0, 0.3}}, 0.25, 0.18};
  out.push_back(e);
  e.d.dh_dx = {std::nan(""), 0.0};
  e.d.dn_dy = {0.0, std::numeric_limits<double>::infinity(), 0.0};
  out.push_back(e);
  e.d = {};
  e.d.dh_dx = {0.5, 0.5};  // the view turns but the normal does not: unchanged
  out.push_back(e);
  return out;
}

}  // namespace

TEST(SpecularAA, ShaderMatchesFp64Twin) {
  const std::vector<Case> cs = cases();
  for (SpecularAA m : {SpecularAA::Kaplanyan2016, SpecularAA::Tokuyoshi2019, SpecularAA::Tokuyoshi2021}) {
    const std::vector<float> gpu = run(m, cs);
    double worst = 0.0;
    for (size_t i = 0; i < cs.size(); ++i) {
      const Case c = as_fp32(cs[i]);
      const glm::dvec4 want = reference::specular_aa_glint_alpha(m, c.alpha, c.d, c.sigma2, c.kappa);
      const glm::dvec2 k = reference::specular_aa_kernel(m, c.d, c.sigma2, c.kappa);
      for (int j = 0; j < 4; ++j) {
        ASSERT_TRUE(std::isfinite(gpu[i * kOut + j])) << "method " << int(m) << " case " << i;
        worst = std::max(worst, std::fabs(gpu[i * kOut + j] - want[j]) / std::max(std::fabs(want[j]), 1e-3));
      }
      for (int j = 0; j < 2; ++j) worst = std::max(worst, std::fabs(gpu[i * kOut + 4 + j] - k[j]));
    }
    EXPECT_LT(worst, 1e-5) << "method " << int(m);
  }
}

TEST(SpecularAA, Fp64TwinWidensAsThePapersSay) {
  const double s = 0.25, kap = 0.18;
  // tokuyoshi2019 on a sphere of radius R seen at f px per unit: |dn/dx| = 1 / (f R) per pixel
  SpecularAAInput d;
  d.dn_dx = {0.1, 0.0, 0.0};
  glm::dvec4 a = reference::specular_aa_glint_alpha(SpecularAA::Tokuyoshi2019, {0.02, 0.05, 0.1, 0.2}, d, s, kap);
  EXPECT_NEAR(a.x * a.x, 0.02 * 0.02 + 2 * 0.25 * 0.01, 1e-15);  // alpha^2 + 2 sigma^2 |dn/dx|^2
  EXPECT_NEAR(a.y * a.y, 0.05 * 0.05 + 2 * 0.25 * 0.01, 1e-15);
  EXPECT_NEAR(a.x * a.z, 0.02 * 0.1, 1e-15);  // alpha_l = alpha_g * relative roughness is kept
  EXPECT_NEAR(a.y * a.w, 0.05 * 0.2, 1e-15);
  // the clamp kappa: a normal turning by a radian a pixel adds kappa, no more
  d.dn_dx = {1.0, 0.0, 0.0};
  a = reference::specular_aa_glint_alpha(SpecularAA::Tokuyoshi2019, {0.02, 0.02, 0.1, 0.1}, d, s, kap);
  EXPECT_NEAR(a.x * a.x, 0.02 * 0.02 + kap, 1e-15);
  // kaplanyan2016: the bounding rectangle's half extent r = (|dp/dx| + |dp/dy|) / 2 adds 2 r^2
  d.dh_dx = {0.04, -0.01};
  d.dh_dy = {-0.02, 0.0};
  a = reference::specular_aa_glint_alpha(SpecularAA::Kaplanyan2016, {0.02, 0.02, 0.1, 0.1}, d, s, kap);
  EXPECT_NEAR(a.x * a.x, 0.02 * 0.02 + 2 * 0.03 * 0.03, 1e-15);
  EXPECT_NEAR(a.y * a.y, 0.02 * 0.02 + 2 * 0.005 * 0.005, 1e-15);
  // tokuyoshi2021: widened in projected space, alpha_p^2 = alpha^2 / (1 - alpha^2), and mapped back
  const double s21 = 1.0 / (2.0 * kPi), ap = 0.3 * 0.3 / (1 - 0.3 * 0.3) + 2 * s21 * (0.04 * 0.04 + 0.02 * 0.02);
  a = reference::specular_aa_glint_alpha(SpecularAA::Tokuyoshi2021, {0.3, 0.3, 0.1, 0.1}, d, s21, kap);
  EXPECT_NEAR(a.x * a.x, ap / (1 + ap), 1e-15);
  // for a narrow lobe the projected-space widening is the additive one to first order in alpha^2
  a = reference::specular_aa_glint_alpha(SpecularAA::Tokuyoshi2021, {0.02, 0.02, 0.1, 0.1}, d, s21, kap);
  EXPECT_NEAR(a.x * a.x, 0.02 * 0.02 + 2 * s21 * (0.04 * 0.04 + 0.02 * 0.02), 1e-6);
  // every method saturates: alpha never passes 1, and a normal that does not turn changes nothing
  d.dn_dx = {3.0, 0.0, 0.0};
  d.dh_dx = {9.0, 9.0};
  for (SpecularAA m : {SpecularAA::Kaplanyan2016, SpecularAA::Tokuyoshi2019, SpecularAA::Tokuyoshi2021}) {
    a = reference::specular_aa_glint_alpha(m, {0.95, 1.0, 0.1, 0.1}, d, 0.25, 1.0);
    EXPECT_LE(a.x, 1.0);
    EXPECT_LE(a.y, 1.0);
    SpecularAAInput still;
    still.dh_dx = {0.5, 0.5};
    EXPECT_EQ(reference::specular_aa_glint_alpha(m, {0.02, 0.03, 0.1, 0.2}, still, 0.25, 0.18),
              glm::dvec4(0.02, 0.03, 0.1, 0.2));
  }
}

namespace {
core::SandParams parse(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text);
  JsonReader r(j, "material.json", "material");
  return core::SandParams::from_json(r);
}
bool has_define(const std::vector<std::string>& d, const std::string& name) {
  return std::find(d.begin(), d.end(), name) != d.end();
}
}  // namespace

TEST(SpecularAA, OptionSelectsPublishedParametersAndTheTruthHasNone) {
  core::SandParams p = parse(R"({"glint_model": "beckmann", "specular_aa": "tokuyoshi2019"})");
  EXPECT_EQ(p.specular_aa.method, "tokuyoshi2019");
  EXPECT_EQ(p.specular_aa.sigma2, 0.25);
  EXPECT_EQ(p.specular_aa.kappa, 0.18);
  EXPECT_EQ(p.pack().specular_aa_sigma2, 0.25f);
  EXPECT_TRUE(has_define(core::shader_defines(p, {}), "SAND_SPECULAR_AA=2"));
  EXPECT_FALSE(p.reference().specular_aa.on());
  EXPECT_EQ(p.reference().pack().specular_aa_sigma2, 0.0f);

  p = parse(R"({"glint_model": "zirr", "specular_aa": {"method": "tokuyoshi2021", "kappa": 0.05}})");
  EXPECT_NEAR(p.specular_aa.sigma2, 1.0 / (2.0 * kPi), 1e-15);
  EXPECT_EQ(p.specular_aa.kappa, 0.05);
  EXPECT_TRUE(has_define(core::shader_defines(p, {}), "SAND_SPECULAR_AA=3"));
  p = parse(R"({"glint_model": "zirr", "specular_aa": {"method": "kaplanyan2016"}})");
  EXPECT_EQ(p.specular_aa.sigma2, 0.25);
  EXPECT_TRUE(has_define(core::shader_defines(p, {}), "SAND_SPECULAR_AA=1"));

  // "none" (the default) compiles nothing and packs zeros: the material block is the one of before
  p = parse(R"({"glint_model": "zirr"})");
  for (const auto& d : core::shader_defines(p, {})) EXPECT_EQ(d.find("SAND_SPECULAR_AA"), std::string::npos) << d;
  EXPECT_EQ(p.pack().specular_aa_kappa, 0.0f);
}

TEST(SpecularAA, BadOptionsNameTheKeyAndWhatIsAllowed) {
  auto error_of = [](const std::string& text) {
    try {
      parse(text);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string e = error_of(R"({"glint_model": "zirr", "specular_aa": "fxaa"})");
  EXPECT_NE(e.find("specular_aa"), std::string::npos) << e;
  EXPECT_NE(e.find("tokuyoshi2019"), std::string::npos) << e;
  e = error_of(R"({"glint_model": "zirr", "specular_aa": {"method": "tokuyoshi2019", "kappa": 2}})");
  EXPECT_NE(e.find("kappa"), std::string::npos) << e;
  e = error_of(R"({"glint_model": "zirr", "specular_aa": {"method": "tokuyoshi2019", "sigma": 0.2}})");
  EXPECT_NE(e.find("sigma"), std::string::npos) << e;
  e = error_of(R"({"glint_model": "zirr", "specular_aa": {"method": "none", "kappa": 0.1}})");
  EXPECT_NE(e.find("kappa"), std::string::npos) << e;
  // kajs and none have no roughness to widen
  e = error_of(R"({"glint_model": "kajs", "specular_aa": "tokuyoshi2019"})");
  EXPECT_NE(e.find("specular_aa"), std::string::npos) << e;
  EXPECT_NE(e.find("kajs"), std::string::npos) << e;
}

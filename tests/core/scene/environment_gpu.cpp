// The GLSL SH irradiance of shaders/common/environment.glsl (env_sh_irradiance, env_irradiance,
// Kajs eq. 4.2 via Ramamoorthi & Hanrahan 2001 eq. 7) against the C++ evaluation of
// core/scene/spherical_harmonics.h, on lavapipe with validation on (shaders/tests/env_sh.comp).
#include "core/vk/compute_harness.h"
#include "core/scene/environment.h"
#include "core/scene/spherical_harmonics.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace glintlab;
using namespace glintlab::core;

namespace {

constexpr size_t kOut = 6;  // E.rgb, env_irradiance.rgb per item (env_sh.comp)

// max over the unit sphere of |Y_k| (basis of core/scene/spherical_harmonics.h): |xy|, |yz|, |xz| and
// |x² - y²| peak at 1/2 and 1, |3z² - 1| at 2.
constexpr double kYMax[9] = {0.282094791773878, 0.488602511902920, 0.488602511902920,
                             0.488602511902920, 1.092548430592079 * 0.5, 1.092548430592079 * 0.5,
                             0.315391565252520 * 2.0, 1.092548430592079 * 0.5, 0.546274215296040};

// Per-channel magnitude of the coefficient set: an upper bound of |Σ E_lm Y_lm(n)| over every
// direction and the scale float rounding of the sum works at.
glm::dvec3 coefficient_magnitude(const SH9& sh) {
  glm::dvec3 m(0.0);
  for (int k = 0; k < 9; ++k) m += glm::abs(glm::dvec3(sh[k])) * kYMax[k];
  return m;
}

// Normals: axis-aligned, grazing (a hair above/below the horizon and the other two axis
// planes), non-unit lengths (the GLSL normalizes), and `n_random` uniform on the sphere.
std::vector<glm::vec3> make_normals(size_t n_random, uint32_t seed) {
  std::vector<glm::vec3> ns = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (float eps : {1e-6f, 1e-3f, 0.0871557f /* 5 deg */}) {
    for (float s : {1.0f, -1.0f}) {
      for (double phi = 0.0; phi < 2.0 * M_PI; phi += M_PI / 6.0) {
        float c = std::sqrt(1.0f - eps * eps);
        ns.push_back({c * float(std::cos(phi)), s * eps, c * float(std::sin(phi))});  // grazing the horizon
        ns.push_back({s * eps, c * float(std::cos(phi)), c * float(std::sin(phi))});  // near the x = 0 plane
        ns.push_back({c * float(std::cos(phi)), c * float(std::sin(phi)), s * eps});  // near the z = 0 plane
      }
    }
  }
  for (float len : {1e-3f, 0.25f, 7.0f, 1e3f}) ns.push_back(glm::vec3(0.6f, -0.48f, 0.64f) * len);
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0f, 1.0f);
  while (ns.size() < n_random + 100) {
    glm::vec3 v(g(rng), g(rng), g(rng));
    float l = glm::length(v);
    if (l > 1e-3f) ns.push_back(v / l);
  }
  return ns;
}

std::vector<float> run_sh(VkContext& ctx, const SH9& sh, const std::vector<glm::vec3>& normals) {
  std::vector<float> in;
  in.reserve(27 + 3 * normals.size());
  for (const glm::vec3& c : sh) in.insert(in.end(), {c.x, c.y, c.z});
  for (const glm::vec3& n : normals) in.insert(in.end(), {n.x, n.y, n.z});
  return run_compute(ctx, "tests/env_sh.comp", {}, in, kOut * normals.size(), uint32_t(normals.size()));
}

// Unclamped fp64 Σ E_lm Y_lm(n̂) (to count how many directions the clamp acted on).
glm::dvec3 unclamped(const SH9& sh, glm::vec3 n) {
  auto Y = sh_basis(glm::normalize(glm::dvec3(n)));
  glm::dvec3 E(0.0);
  for (int k = 0; k < 9; ++k) E += glm::dvec3(sh[k]) * Y[k];
  return E;
}

struct Stats {
  double worst = 0;     // max |gpu - cpp| / magnitude
  double worst_pi = 0;  // max |L - E/π| / E
  double min_E = 0;     // smallest GPU E
  size_t clamped = 0;   // channels where the unclamped sum < -bound (so the clamp matters)
};

// Relative bound on |E_gpu - E_cpp| per channel, in units of the coefficient magnitude: fp32
// has eps 6e-8, the sum has 9 terms each with a couple of roundings (normalize, products);
// lavapipe measures <= 3.3e-7.
constexpr double kRelBound = 2e-6;
// env_irradiance = E * (1/π) in fp32: two roundings (the constant and the product).
constexpr double kPiBound = 4e-7;

// Runs the GPU on every normal and checks E against eval_sh_irradiance and L against E / π;
// failures report the worst item only.
Stats compare(VkContext& ctx, const SH9& sh, const std::vector<glm::vec3>& normals, const std::string& what) {
  auto out = run_sh(ctx, sh, normals);
  glm::dvec3 mag = coefficient_magnitude(sh);
  Stats st;
  size_t worst_i = 0, worst_pi_i = 0, bad = 0;
  for (size_t i = 0; i < normals.size(); ++i) {
    glm::vec3 ref = eval_sh_irradiance(sh, normals[i]);
    glm::dvec3 raw = unclamped(sh, normals[i]);
    for (int c = 0; c < 3; ++c) {
      double E = out[kOut * i + c], L = out[kOut * i + 3 + c];
      if (!std::isfinite(E) || !std::isfinite(L)) ++bad;
      double m = std::max(mag[c], 1e-30);
      double err = std::abs(E - double(ref[c])) / m;
      double err_pi = E > 1e-30 ? std::abs(L - E / M_PI) / (E / M_PI) : std::abs(L);
      if (err > st.worst) st.worst = err, worst_i = i;
      if (err_pi > st.worst_pi) st.worst_pi = err_pi, worst_pi_i = i;
      st.min_E = std::min(st.min_E, E);
      if (raw[c] < -kRelBound * m) ++st.clamped;
    }
  }
  auto show = [&](size_t i) {
    const glm::vec3& n = normals[i];
    glm::vec3 ref = eval_sh_irradiance(sh, n);
    return "normal " + std::to_string(i) + " (" + std::to_string(n.x) + ", " + std::to_string(n.y) + ", " +
           std::to_string(n.z) + "): gpu E (" + std::to_string(out[kOut * i]) + ", " + std::to_string(out[kOut * i + 1]) +
           ", " + std::to_string(out[kOut * i + 2]) + ") cpp (" + std::to_string(ref.x) + ", " +
           std::to_string(ref.y) + ", " + std::to_string(ref.z) + ")";
  };
  EXPECT_EQ(bad, 0u) << what << ": non-finite outputs";
  EXPECT_GE(st.min_E, 0.0) << what << ": the GLSL does not clamp E >= 0 like eval_sh_irradiance";
  EXPECT_LE(st.worst, kRelBound) << what << ": worst " << show(worst_i);
  EXPECT_LE(st.worst_pi, kPiBound) << what << ": env_irradiance != E / pi at " << show(worst_pi_i) << " L = "
                                   << out[kOut * worst_pi_i + 3];
  if (std::getenv("GLINTLAB_PRINT_ERRORS"))
    std::printf("%-28s worst |dE|/magnitude %.3g  worst |L - E/pi|/(E/pi) %.3g  clamped channels %zu\n",
                what.c_str(), st.worst, st.worst_pi, st.clamped);
  return st;
}

}  // namespace

TEST(EnvironmentGpu, ShIrradianceOfPreethamSkiesMatchesCpp) {
  VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  auto normals = make_normals(4000, 11);
  struct Sky { float turbidity, elevation, azimuth, intensity, albedo; };
  for (const Sky& s : {Sky{3.0f, 30.0f, 0.0f, 1.0f, 0.3f}, Sky{2.0f, 5.0f, 120.0f, 0.5f, 0.1f},
                       Sky{9.0f, 80.0f, -45.0f, 20.0f, 0.9f}}) {
    SkySpec spec;
    spec.turbidity = s.turbidity;
    spec.sky_intensity = s.intensity;
    spec.ground_albedo = s.albedo;
    spec.resolution = 64;
    spec.sun.direction = direction_from_elevation_azimuth(s.elevation, s.azimuth);
    Environment env = make_procedural_sky(spec);
    compute_sh_irradiance(env);
    // A real sky: E(+Y) is positive and dominated by band 0.
    ASSERT_GT(env.sh_irradiance[0].y, 0.0f);
    std::string what = "Preetham T=" + std::to_string(s.turbidity) + " elev=" + std::to_string(s.elevation);
    Stats st = compare(ctx, env.sh_irradiance, normals, what);
    RecordProperty("worst_rel_" + std::to_string(int(s.elevation)), std::to_string(st.worst));
  }
}

TEST(EnvironmentGpu, ShIrradianceOfRandomCoefficientsMatchesCppIncludingClamp) {
  VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  auto normals = make_normals(4000, 23);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), decade(-3.0f, 3.0f);
  size_t clamped = 0;
  for (int set = 0; set < 5; ++set) {
    SH9 sh;
    // Magnitudes spread over six decades; set 0 is sky-like (band 0 dominant, so E > 0 almost
    // everywhere), the others are arbitrary (E < 0 over much of the sphere: the clamp acts).
    float scale = std::pow(10.0f, decade(rng));
    for (int k = 0; k < 9; ++k) sh[k] = glm::vec3(u(rng), u(rng), u(rng)) * scale;
    if (set == 0) sh[0] = glm::vec3(6.0f * scale);
    Stats st = compare(ctx, sh, normals, "random set " + std::to_string(set));
    clamped += st.clamped;
  }
  // The clamp to >= 0 must have been exercised (both sides clamp: EXPECT_GE and the bound above).
  EXPECT_GT(clamped, 1000u);
}

TEST(EnvironmentGpu, EachBasisFunctionAloneMatchesCpp) {
  // One coefficient at a time, different in each channel (r = +1, g = -2, b = +0.5): an
  // order or constant mismatch between the GLSL and C++ basis shows up as a whole-function error.
  VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  auto normals = make_normals(300, 37);
  for (int k = 0; k < 9; ++k) {
    SH9 sh{};
    sh[k] = glm::vec3(1.0f, -2.0f, 0.5f);
    compare(ctx, sh, normals, "basis " + std::to_string(k));
  }
}

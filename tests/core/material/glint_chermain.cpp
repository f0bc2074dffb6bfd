// The dictionary of the `chermain` glint model (shaders/glint/models/
// chermain.glsl; Chermain et al. 2020 sec. 5.1), read back as glintlab
// generates it on the GPU (core::glint_table) and checked in fp64 from the
// table values alone:
//  - every marginal of every level and MIP level integrates to 1 under the
//    model's interpolation (midpoint sum over the bin centres);
//  - the average over the dictionary of the randomly rotated products of two
//    marginals, (1 / 2 pi) int F(r cos t) F(r sin t) dt with F the mean
//    marginal of a level, is Beckmann with alpha_dict = 0.5 (eq. 11's
//    expectation), within the sampling error of a finite dictionary;
//  - each prefiltered (ggaa) MIP level is the box filter of the finer one,
//    and the model reads it: a slope footprint wider than the tabulated range
//    makes every marginal its coarsest level, the constant 1 / (8 sigma_dict).
#include "core/material/glint_model.h"
#include "core/material/glint_table.h"
#include "core/material/sand_material.h"
#include "core/vk/compute_harness.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

using namespace glintlab;

namespace {

// The dictionary's constants as the model file states them.
constexpr int kLevels = 16, kDists = 192, kBins = 64, kMips = 7, kBlock = 128;
constexpr double kAlphaDict = 0.5;
const double kSigmaDict = kAlphaDict / std::sqrt(2.0);
const double kSlopeMax = 4.0 * kSigmaDict;
const double kBin = kSlopeMax / kBins;
constexpr double kLobeStd = 0.02;
const double kPi = std::acos(-1.0);

// The table once per machine: every test of this file runs as its own
// process under ctest, and generating it takes ~45 s of CPU on lavapipe, so
// it is kept in the test cache folder (XDG_CACHE_HOME, which ctest sets)
// like a run keeps it beside its truths; the folder is unset afterwards.
std::shared_ptr<const std::vector<float>> chermain_table(const core::VkContext& ctx, const core::GlintModelDecl& d) {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && *xdg) core::set_glint_table_cache_dir(std::string(xdg) + "/glintlab-test");
  auto t = core::glint_table(ctx, d);
  core::set_glint_table_cache_dir("");
  return t;
}

size_t mip_offset(int m) { return size_t(kBlock - (kBlock >> m)); }

struct Dictionary {
  std::vector<float> t;
  const float* marginal(int k, int d, int m) const {
    return t.data() + (size_t(k) * kDists + size_t(d)) * kBlock + mip_offset(m);
  }
};

const Dictionary& dictionary() {
  static Dictionary dict = [] {
    auto& ctx = test::shared_context();
    test::ValidationGuard guard(ctx);
    const core::GlintModelDecl* decl = core::find_builtin_glint_model("chermain");
    EXPECT_NE(decl, nullptr);
    Dictionary d;
    if (decl) {
      std::shared_ptr<const std::vector<float>> table = chermain_table(ctx, *decl);
      if (table) d.t = *table;
    }
    return d;
  }();
  return dict;
}

// Marginal values v (n bins of width w) at |x|, as the shader interpolates:
// linear between bin centres, mirrored at 0, constant in the last half bin,
// 0 beyond the tabulated range.
double interpolate(const std::vector<double>& v, double w, double x) {
  x = std::abs(x);
  if (x >= kSlopeMax) return 0.0;
  int n = int(v.size());
  double t = x / w - 0.5;
  double t0 = std::floor(t);
  double f = t - t0;
  int b0 = std::clamp(int(t0), -1, n - 1);
  int b1 = std::min(b0 + 1, n - 1);
  b0 = std::max(b0, 0);
  return (1.0 - f) * v[size_t(b0)] + f * v[size_t(b1)];
}

}  // namespace

TEST(GlintChermain, TableHasTheDeclaredSize) {
  const Dictionary& d = dictionary();
  ASSERT_EQ(d.t.size(), size_t(kLevels) * kDists * kBlock);
  for (float v : d.t) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
}

// Under the model's interpolation the integral over the line of a marginal
// of n bins of width w is exactly 2 w sum_b f_b (each half line: half a bin
// at f_0, trapezoids between the centres, half a bin at f_(n-1)). The
// generator normalises the lobes' midpoint sums (summing those near the
// range's end, counting the others as 1, true to ~1e-7), each entry on its
// own; the bound 1e-4 is the fp32 accumulation of up to 2^16 lobe terms per
// entry. A wrong lobe count, width or normalisation misses it by far more.
TEST(GlintChermain, EveryMarginalOfEveryLevelIntegratesToOne) {
  const Dictionary& d = dictionary();
  ASSERT_EQ(d.t.size(), size_t(kLevels) * kDists * kBlock);
  double worst = 0.0;
  for (int k = 0; k < kLevels; ++k)
    for (int i = 0; i < kDists; ++i)
      for (int m = 0; m < kMips; ++m) {
        const float* f = d.marginal(k, i, m);
        double sum = 0.0;
        for (int b = 0; b < (kBins >> m); ++b) sum += f[b];
        double integral = 2.0 * kBin * double(1 << m) * sum;
        worst = std::max(worst, std::abs(integral - 1.0));
        ASSERT_NEAR(integral, 1.0, 1e-4) << "level " << k << " marginal " << i << " mip " << m;
      }
  std::printf("chermain: largest |integral - 1| over 16 x 192 x 7 marginals: %.3g\n", worst);
}

// Level k of marginal d is a mixture of 2^k lobe pairs; a coarser level is
// rough (few lobes), a finer one smooth. The mean marginal of level k is a
// kernel density estimate of N(0, sigma_dict^2) from n = 192 2^k means with a
// Gaussian kernel of width s = 0.02, so it is N(0, sigma_dict^2 + s^2)
// (alpha 0.5008) up to a relative sampling error of standard deviation
// 1 / sqrt(n s 2 sqrt(pi) f(x)) (the KDE variance f / (n s 2 sqrt(pi))).
// The rotated product's average at radius r <= 1.5 sigma_dict is compared
// with Beckmann alpha_dict: bound = 0.01 (the kernel's widening, < 0.4 %,
// and the interpolation) + 5 x twice that relative error at x = r / sqrt(2)
// (the product of two independent marginals). A mean marginal of the wrong
// width, count of lobes or normalisation misses it at every fine level.
TEST(GlintChermain, RotatedProductsAverageToBeckmannOfTheDictionary) {
  const Dictionary& d = dictionary();
  ASSERT_EQ(d.t.size(), size_t(kLevels) * kDists * kBlock);
  for (int k = 4; k < kLevels; ++k) {
    std::vector<double> mean(kBins, 0.0);
    for (int i = 0; i < kDists; ++i) {
      const float* f = d.marginal(k, i, 0);
      for (int b = 0; b < kBins; ++b) mean[size_t(b)] += f[b] / double(kDists);
    }
    double n = double(kDists) * std::ldexp(1.0, k);
    double worst = 0.0, worst_bound = 0.0, worst_r = 0.0;
    for (int ri = 0; ri <= 30; ++ri) {
      double r = 1.5 * kSigmaDict * ri / 30.0;
      const int T = 720;
      double avg = 0.0;
      for (int t = 0; t < T; ++t) {
        double th = 2.0 * kPi * (t + 0.5) / T;
        avg += interpolate(mean, kBin, r * std::cos(th)) * interpolate(mean, kBin, r * std::sin(th));
      }
      avg /= T;
      double beck = std::exp(-r * r / (kAlphaDict * kAlphaDict)) / (kPi * kAlphaDict * kAlphaDict);
      double x = r / std::sqrt(2.0);
      double fx = std::exp(-0.5 * x * x / (kSigmaDict * kSigmaDict)) / (kSigmaDict * std::sqrt(2.0 * kPi));
      double rel_sd = 1.0 / std::sqrt(n * kLobeStd * 2.0 * std::sqrt(kPi) * fx);
      double bound = 0.01 + 5.0 * 2.0 * rel_sd;
      double rel = std::abs(avg / beck - 1.0);
      if (rel / bound > worst / std::max(worst_bound, 1e-300)) {
        worst = rel;
        worst_bound = bound;
        worst_r = r;
      }
      EXPECT_LT(rel, bound) << "level " << k << " r " << r << " average " << avg << " Beckmann " << beck;
    }
    std::printf("chermain: level %2d: largest relative error %.4f at r %.3f (bound there %.4f)\n", k, worst, worst_r,
                worst_bound);
  }
}

// ggaa (Chermain et al. 2021): bin j of MIP level m is the box average of
// bins 2j, 2j+1 of level m - 1. The table computes every MIP bin directly
// from the lobes (the mean over its 2^m base bins), so this checks that
// construction against the finer level's values; the bound 1e-4 of the
// marginal's peak is the fp32 accumulation of both sides' entries.
TEST(GlintChermain, PrefilteredLevelsAreTheBoxFilterOfTheFinerOnes) {
  const Dictionary& d = dictionary();
  ASSERT_EQ(d.t.size(), size_t(kLevels) * kDists * kBlock);
  double worst = 0.0;
  for (int k = 0; k < kLevels; ++k)
    for (int i = 0; i < kDists; ++i) {
      const float* base = d.marginal(k, i, 0);
      double peak = *std::max_element(base, base + kBins);
      for (int m = 1; m < kMips; ++m) {
        const float* fine = d.marginal(k, i, m - 1);
        const float* coarse = d.marginal(k, i, m);
        for (int j = 0; j < (kBins >> m); ++j) {
          double box = 0.5 * (double(fine[2 * j]) + double(fine[2 * j + 1]));
          double err = std::abs(double(coarse[j]) - box) / peak;
          worst = std::max(worst, err);
          ASSERT_LT(err, 1e-4) << "level " << k << " marginal " << i << " mip " << m << " bin " << j;
        }
      }
    }
  std::printf("chermain: largest |MIP bin - box of the finer bins| / peak: %.3g\n", worst);
}

// The table is what eq. 11 needs at the extremes: the finest level's
// marginals are single lobe pairs (peaks of height ~ 1 / (2 s sqrt(2 pi)) =
// 10 at +-mu, or 20 where mu ~ 0), the coarsest are smooth (peak near the
// Gaussian's 1.13). A table with the levels reversed fails both.
TEST(GlintChermain, LevelZeroIsOneLobePairAndLevelFifteenIsSmooth) {
  const Dictionary& d = dictionary();
  ASSERT_EQ(d.t.size(), size_t(kLevels) * kDists * kBlock);
  double peak0 = 0.0, peak15 = 0.0;
  for (int i = 0; i < kDists; ++i) {
    const float* f0 = d.marginal(0, i, 0);
    const float* f15 = d.marginal(15, i, 0);
    peak0 += *std::max_element(f0, f0 + kBins) / kDists;
    peak15 += *std::max_element(f15, f15 + kBins) / kDists;
  }
  double gauss0 = 1.0 / (kSigmaDict * std::sqrt(2.0 * kPi));
  EXPECT_GT(peak0, 6.0);
  EXPECT_NEAR(peak15 / gauss0, 1.0, 0.06);
  std::printf("chermain: mean peak level 0 %.3f, level 15 %.3f (Gaussian %.3f)\n", peak0, peak15, gauss0);
}

// ggaa in the model (glint/conformance.comp with the model's defines and its
// table): a slope footprint of 1e3 (GLINT_CHERMAIN_SLOPE_DERIVATIVES, the
// hook for an includer that has the half vector's screen derivatives)
// selects MIP level 6 of every marginal, the constant 1 / (8 sigma_dict), so
// at h = n every cell's P-SDF is (1 / (8 sigma_dict))^2 (alpha_dict /
// alpha)^2 = 0.125 for alpha = 0.5 whatever the cell's marginals, rotation
// and weight: D = 0.125. log_density -3 puts every cell on a dictionary
// level (l_dist ~ -15 before the jitter). Without the hook, ggaa on and off
// give the same bits (a zero footprint reads MIP level 0).
TEST(GlintChermain, GgaaReadsThePrefilteredLevels) {
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const core::GlintModelDecl* decl = core::find_builtin_glint_model("chermain");
  ASSERT_NE(decl, nullptr);
  auto table = chermain_table(ctx, *decl);
  ASSERT_TRUE(table && !table->empty());
  const size_t kIn = 28, kOut = 8, n = 64;
  std::vector<float> in(n * kIn, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    float* r = &in[i * kIn];
    r[0] = 0.37f + 0.013f * float(i / 2);  // uv: pairs (ggaa off, on) share it
    r[1] = 0.61f + 0.029f * float(i / 2);
    r[2] = 1e-3f;  // duv_dx
    r[5] = 1e-3f;  // duv_dy
    r[8] = 1.0f;   // wi = n
    r[11] = 1.0f;  // wo = n
    r[12] = r[13] = 0.5f;  // alpha_g
    r[14] = r[15] = 0.1f;  // relative roughness (unused by the model)
    r[16] = -3.0f;         // log_density
    r[17] = 0.0f;          // light cone
    r[20] = 1.0f;          // microfacet_relative_area
    r[21] = 8.0f;          // max_anisotropy
    r[22] = i % 2 ? 1.0f : 0.0f;  // ggaa
    r[23] = 0.5f;          // ggaa_kernel
  }
  std::vector<std::string> defines = core::glint_model_defines(*decl);
  auto plain = core::run_compute(ctx, "glint/conformance.comp", defines, in, n * kOut, uint32_t(n), table.get());
  defines.push_back("GLINT_CHERMAIN_SLOPE_DERIVATIVES=vec4(1e3,0.0,0.0,1e3)");
  auto filtered = core::run_compute(ctx, "glint/conformance.comp", defines, in, n * kOut, uint32_t(n), table.get());
  double worst = 0.0;
  for (size_t i = 0; i < n; i += 2) {
    EXPECT_EQ(plain[i * kOut], plain[(i + 1) * kOut]) << i;  // ggaa off = on without a footprint
    EXPECT_EQ(plain[i * kOut], filtered[i * kOut]) << i;     // the hook acts only with ggaa on
    double D = filtered[(i + 1) * kOut];
    worst = std::max(worst, std::abs(D / 0.125 - 1.0));
    EXPECT_NEAR(D, 0.125, 0.125 * 3e-4) << i;
  }
  std::printf("chermain: ggaa with a 1e3 slope footprint at h = n: largest |D / 0.125 - 1| %.3g\n", worst);
}

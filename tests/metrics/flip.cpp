// FLIP (Andersson et al. 2020) and HDR-FLIP (Andersson et al. 2021): limits and invariants of the
// published pipeline.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numeric>
#include <random>
#include <stdexcept>

#include "metrics/color/image_io.h"
#include "metrics/flip.h"
#include "metrics/flip_pooling.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {
// Linear sRGB / Rec.709 -> XYZ (SMPTE RP 177 from the Rec.709 primaries, D65 (0.3127, 0.3290)), the
// published 7-digit matrix.
void srgb_to_xyz(double r, double g, double b, float* xyz) {
  xyz[0] = float(0.4123908 * r + 0.3575843 * g + 0.1804808 * b);
  xyz[1] = float(0.2126390 * r + 0.7151687 * g + 0.0721923 * b);
  xyz[2] = float(0.0193308 * r + 0.1191948 * g + 0.9505322 * b);
}
Image uniform_srgb(int w, int h, double r, double g, double b) {
  Image im(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) srgb_to_xyz(r, g, b, im.px(x, y));
  return im;
}
double mean(const Image& m) { return std::accumulate(m.data.begin(), m.data.end(), 0.0) / double(m.data.size()); }
Image random_xyz(int w, int h, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Image im(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) srgb_to_xyz(scale * u(rng), scale * u(rng), scale * u(rng), im.px(x, y));
  return im;
}
}  // namespace

TEST(Flip, DefaultViewingSetup) {
  // 0.7 m from a 0.7 m wide 3840 px monitor (FLIP 2020): 67.02 px/deg.
  EXPECT_NEAR(flip_pixels_per_degree(0.7, 0.7, 3840), 3840.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(flip_pixels_per_degree(0.7, 0.7, 3840), kFlipDefaultPpd, 0.05);
  // FLIP v1.6's default is that formula, not a rounded 67 (its tool prints the rounded value).
  EXPECT_NEAR(kFlipDefaultPpd, 67.0206433, 1e-6);
  static_assert(flip_pixels_per_degree(0.5, 0.6, 1920) > 27.9 && flip_pixels_per_degree(0.5, 0.6, 1920) < 28.0);
}

TEST(Flip, IdenticalImagesGiveZero) {
  const Image a = random_xyz(40, 30, 1.0, 1);
  for (float v : ldr_flip_map(a, a).data) EXPECT_EQ(v, 0.0f);
  const Image hdr = random_xyz(40, 30, 20.0, 2);
  Image same = hdr;
  for (float& v : same.data) v *= 1.0f;
  for (float v : hdr_flip_map(same, hdr).data) EXPECT_EQ(v, 0.0f);
}

TEST(Flip, ErrorInUnitIntervalOnRandomImages) {
  const Image a = random_xyz(48, 32, 1.2, 3), b = random_xyz(48, 32, 1.2, 4);
  const Image m = ldr_flip_map(a, b);
  for (float v : m.data) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
  EXPECT_GT(mean(m), 0.1);
}

TEST(Flip, BlackVersusWhiteIsNearMaximal) {
  // Uniform images: no features, so FLIP = ΔE_c. Expected value from published CIELAB coordinates of the
  // sRGB primaries (D65): green (87.7347, -86.1827, 83.1793), blue (32.3026, 79.1967, -107.8637).
  const double gL = 87.7347, ga = 0.01 * gL * -86.1827, gb = 0.01 * gL * 83.1793;  // Hunt adjustment
  const double bL = 32.3026, ba = 0.01 * bL * 79.1967, bb = 0.01 * bL * -107.8637;
  const double cmax = std::pow(std::abs(gL - bL) + std::hypot(ga - ba, gb - bb), 0.7);
  const double e = std::pow(100.0, 0.7);  // HyAB(black, white) = ΔL = 100
  const double expected = 0.95 + (e - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
  const Image black = uniform_srgb(24, 24, 0, 0, 0), white = uniform_srgb(24, 24, 1, 1, 1);
  const Image m = ldr_flip_map(black, white);
  for (float v : m.data) EXPECT_NEAR(v, expected, 1e-3);
  EXPECT_GT(expected, 0.95);
  // Green vs blue is the definition of the maximal colour error: exactly 1.
  const Image mg = ldr_flip_map(uniform_srgb(16, 16, 0, 1, 0), uniform_srgb(16, 16, 0, 0, 1));
  for (float v : mg.data) EXPECT_NEAR(v, 1.0, 1e-5);
}

TEST(Flip, MonotonicInColourShift) {
  const Image ref = uniform_srgb(20, 20, 0.4, 0.4, 0.4);
  double prev = 0.0;
  for (double d : {0.01, 0.03, 0.06, 0.1, 0.2, 0.4}) {
    const double f = mean(ldr_flip_map(uniform_srgb(20, 20, 0.4 + d, 0.4, 0.4), ref));
    EXPECT_GT(f, prev) << d;
    prev = f;
  }
}

TEST(Flip, CheckerboardFadesAtHighPixelsPerDegree) {
  // A 1-px checkerboard is invisible from far away (high ppd, CSF low-pass) but clearly different from
  // its mean grey up close (low ppd).
  const int n = 48;
  Image cb(n, n, 3), grey(n, n, 3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double v = ((x + y) % 2) ? 0.8 : 0.2;
      srgb_to_xyz(v, v, v, cb.px(x, y));
      srgb_to_xyz(0.5, 0.5, 0.5, grey.px(x, y));
    }
  const double near_view = mean(ldr_flip_map(cb, grey, 10.0));
  const double far_view = mean(ldr_flip_map(cb, grey, 120.0));
  EXPECT_LT(far_view, near_view);
  EXPECT_LT(far_view, 0.5 * near_view);
}

TEST(Flip, AcesToneMapperAndExposureRange) {
  EXPECT_EQ(flip_aces_tonemap(0.0), 0.0);
  EXPECT_EQ(flip_aces_tonemap(-3.0), 0.0);
  EXPECT_EQ(flip_aces_tonemap(INFINITY), 1.0);
  // Narkowicz 2016 ACES fit evaluated at 0.6 x.
  auto narkowicz = [](double x) { return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14); };
  for (double x : {0.05, 0.3, 1.0, 2.5}) EXPECT_NEAR(flip_aces_tonemap(x), std::min(1.0, narkowicz(0.6 * x)), 1e-12);

  // Uniform reference Y = 1: start = stop, and exposure 2^start maps it to 0.85 (HDR-FLIP t).
  const HdrFlipExposures u = hdr_flip_exposures(uniform_srgb(8, 8, 1, 1, 1));
  EXPECT_NEAR(u.start, u.stop, 1e-9);
  EXPECT_EQ(u.count, 2);
  EXPECT_NEAR(flip_aces_tonemap(std::exp2(u.start) * 1.0), 0.85, 1e-6);
  // Three pixels at 1 and one at 1024: median 1 (FLIP's: element 2 of 4 sorted), max 1024 -> range of
  // log2(1024) = 10 stops.
  Image r(4, 1, 3);
  for (int x = 0; x < 4; ++x) srgb_to_xyz(x == 2 ? 1024 : 1, x == 2 ? 1024 : 1, x == 2 ? 1024 : 1, r.px(x, 0));
  const HdrFlipExposures e = hdr_flip_exposures(r);
  EXPECT_NEAR(e.stop - e.start, 10.0, 1e-4);
  EXPECT_EQ(e.count, 10);
  EXPECT_NEAR(e.stop, u.stop, 1e-4);
  // Black reference: c_start = c_stop = 0.
  const HdrFlipExposures z = hdr_flip_exposures(uniform_srgb(4, 4, 0, 0, 0));
  EXPECT_EQ(z.start, 0.0);
  EXPECT_EQ(z.stop, 0.0);
  // Mostly black reference: stop stays finite (median of the positive luminances; FLIP's own stop
  // would be +inf).
  Image mb(5, 1, 3, 0.0f);
  srgb_to_xyz(4, 4, 4, mb.px(0, 0));
  const HdrFlipExposures m = hdr_flip_exposures(mb);
  EXPECT_TRUE(std::isfinite(m.stop));
  EXPECT_GE(m.count, 2);
}

TEST(Flip, HdrHandlesHighValuesWithoutNan) {
  const Image ref = random_xyz(32, 24, 50.0, 5);
  Image test = ref;
  for (std::size_t i = 0; i < test.data.size(); i += 7) test.data[i] *= 1.5f;
  test.at(3, 3, 1) = 1e6f;  // a firefly far above the reference range
  const Image m = hdr_flip_map(test, ref);
  for (float v : m.data) {
    ASSERT_FALSE(std::isnan(v));
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
  EXPECT_GT(mean(m), 0.0);
  // On a flat reference the firefly is the only error and the map's maximum. (HDR-FLIP takes its exposures
  // from the reference only, so the firefly is seen as a clipped 1.0 against the reference's 0.85.)
  const Image flat = uniform_srgb(32, 32, 2, 2, 2);
  Image fly = flat;
  srgb_to_xyz(1e6, 1e6, 1e6, fly.px(16, 16));
  const Image mf = hdr_flip_map(fly, flat);
  for (float v : mf.data) ASSERT_FALSE(std::isnan(v));
  EXPECT_GT(mf.at(16, 16, 0), 0.02f);
  EXPECT_EQ(mf.at(16, 16, 0), *std::max_element(mf.data.begin(), mf.data.end()));
  EXPECT_EQ(mf.at(0, 0, 0), 0.0f);
  // HDR-FLIP sees differences above white that LDR-FLIP clips away.
  const Image bright = uniform_srgb(16, 16, 4, 4, 4), brighter = uniform_srgb(16, 16, 8, 8, 8);
  for (float v : ldr_flip_map(brighter, bright).data) EXPECT_EQ(v, 0.0f);
  EXPECT_GT(mean(hdr_flip_map(brighter, bright)), 0.1);
}

TEST(Flip, RejectsBadInput) {
  EXPECT_THROW(ldr_flip_map(Image(4, 4, 3), Image(4, 5, 3)), std::invalid_argument);
  EXPECT_THROW(ldr_flip_map(Image(4, 4, 3), Image(4, 4, 3), 0.0), std::invalid_argument);
  EXPECT_THROW(hdr_flip_map(Image(4, 4, 3), Image(4, 4, 3), NAN), std::invalid_argument);
}

TEST(Flip, ExposureRangeUsesFlipsUpperMedian) {
  // Luminances 1, 2, 8, 16 (grey pixels): FLIP's median is element n/2 = 2 of the sorted four, 8 -- not
  // the mean of the middle two (5). Hence stop - start = log2(16 / 8) = 1 -> max(2, 1) = 2 exposures.
  Image r(4, 1, 3);
  const double ys[4] = {8, 1, 16, 2};
  for (int x = 0; x < 4; ++x) srgb_to_xyz(ys[x], ys[x], ys[x], r.px(x, 0));
  const HdrFlipExposures e = hdr_flip_exposures(r);
  EXPECT_NEAR(flip_aces_tonemap(std::exp2(e.stop) * 8.0), 0.85, 1e-5);
  EXPECT_NEAR(flip_aces_tonemap(std::exp2(e.start) * 16.0), 0.85, 1e-5);
  EXPECT_NEAR(e.stop - e.start, 1.0, 1e-5);
  EXPECT_EQ(e.count, 2);
  // Odd count: the middle one. Five pixels 1, 2, 4, 8, 16 -> median 4, range log2(16 / 4) = 2 stops.
  Image o(5, 1, 3);
  for (int x = 0; x < 5; ++x) srgb_to_xyz(std::exp2(x), std::exp2(x), std::exp2(x), o.px(x, 0));
  const HdrFlipExposures eo = hdr_flip_exposures(o);
  EXPECT_NEAR(flip_aces_tonemap(std::exp2(eo.stop) * 4.0), 0.85, 1e-5);
  EXPECT_EQ(eo.count, 2);
}

TEST(Flip, ToneMappersAndTheirExposureRanges) {
  double c[3] = {0.5, 2.0, -1.0};
  flip_tonemap(FlipToneMapper::Aces, c);
  EXPECT_DOUBLE_EQ(c[0], flip_aces_tonemap(0.5));
  EXPECT_DOUBLE_EQ(c[1], flip_aces_tonemap(2.0));
  EXPECT_EQ(c[2], 0.0);
  // Hable, FLIP's rational fit, per channel and clamped.
  auto hable = [](double x) { return std::min(1.0, (0.231683 * x * x + 0.013791 * x) / (0.18 * x * x + 0.3 * x + 0.018)); };
  double h[3] = {0.1, 1.0, 50.0};
  flip_tonemap(FlipToneMapper::Hable, h);
  EXPECT_NEAR(h[0], hable(0.1), 1e-12);
  EXPECT_NEAR(h[1], hable(1.0), 1e-12);
  EXPECT_NEAR(h[2], hable(50.0), 1e-12);
  // Reinhard on luminance: every channel divided by 1 + L.
  double rh[3] = {1.0, 0.5, 0.25};
  const double L = 0.2126 * 1.0 + 0.7152 * 0.5 + 0.0722 * 0.25;
  flip_tonemap(FlipToneMapper::Reinhard, rh);
  EXPECT_NEAR(rh[0], 1.0 / (1.0 + L), 1e-12);
  EXPECT_NEAR(rh[1], 0.5 / (1.0 + L), 1e-12);
  EXPECT_NEAR(rh[2], 0.25 / (1.0 + L), 1e-12);
  // Each tone mapper's range puts the reference maximum at 0.85 for the start exposure (grey pixels;
  // Reinhard's x_max = 0.85 / 0.15 from x / (1 + x) = 0.85).
  Image r(3, 1, 3);
  for (int x = 0; x < 3; ++x) srgb_to_xyz(0.5 * (x + 1), 0.5 * (x + 1), 0.5 * (x + 1), r.px(x, 0));
  for (FlipToneMapper tm : {FlipToneMapper::Aces, FlipToneMapper::Hable, FlipToneMapper::Reinhard}) {
    const HdrFlipExposures e = hdr_flip_exposures(r, tm);
    double g[3] = {1.5 * std::exp2(e.start), 1.5 * std::exp2(e.start), 1.5 * std::exp2(e.start)};
    flip_tonemap(tm, g);
    EXPECT_NEAR(g[1], 0.85, 1e-5) << enum_name(kFlipToneMapperNames, tm);
    EXPECT_NEAR(e.stop - e.start, std::log2(1.5 / 1.0), 1e-5);  // median 1.0
  }
  EXPECT_NEAR(std::exp2(hdr_flip_exposures(r, FlipToneMapper::Reinhard).start) * 1.5, 0.85 / 0.15, 1e-4);
}

TEST(Flip, ResolvedExposuresFollowFlipsRules) {
  Image r(4, 1, 3);
  const double ys[4] = {0.5, 1, 4, 64};
  for (int x = 0; x < 4; ++x) srgb_to_xyz(ys[x], ys[x], ys[x], r.px(x, 0));
  const HdrFlipExposures a = hdr_flip_exposures(r);
  EXPECT_EQ(a.count, 4);  // log2(64 / 4) = 4 stops
  HdrFlipOptions o;
  HdrFlipExposures e = resolve_hdr_flip_exposures(r, o);
  EXPECT_EQ(e.start, a.start);
  EXPECT_EQ(e.stop, a.stop);
  EXPECT_EQ(e.count, 4);
  o.start_exposure = a.stop - 2.5;  // the given start, the computed stop, the count from their distance
  e = resolve_hdr_flip_exposures(r, o);
  EXPECT_EQ(e.start, a.stop - 2.5);
  EXPECT_EQ(e.stop, a.stop);
  EXPECT_EQ(e.count, 3);
  o.num_exposures = 7;
  EXPECT_EQ(resolve_hdr_flip_exposures(r, o).count, 7);
  o = {};
  o.start_exposure = -1;
  o.stop_exposure = 1;
  e = resolve_hdr_flip_exposures(r, o);
  EXPECT_EQ(e.start, -1.0);
  EXPECT_EQ(e.stop, 1.0);
  EXPECT_EQ(e.count, 2);
  o.start_exposure = a.stop + 1;  // above the computed stop
  o.stop_exposure = NAN;
  EXPECT_THROW(resolve_hdr_flip_exposures(r, o), std::invalid_argument);
  o = {};
  o.num_exposures = -2;
  EXPECT_THROW(resolve_hdr_flip_exposures(r, o), std::invalid_argument);
  // One exposure: the start alone. HDR-FLIP then equals LDR-FLIP of the images tone mapped at 2^start.
  const Image t = random_xyz(12, 10, 3.0, 11), ref = random_xyz(12, 10, 3.0, 12);
  o = {};
  o.start_exposure = -0.5;
  o.stop_exposure = 2;
  o.num_exposures = 1;
  HdrFlipExposures used;
  const Image one = hdr_flip_map(t, ref, kFlipDefaultPpd, o, &used);
  EXPECT_EQ(used.count, 1);
  o.stop_exposure = -0.5;
  o.num_exposures = 2;
  const Image same = hdr_flip_map(t, ref, kFlipDefaultPpd, o);
  for (std::size_t i = 0; i < one.data.size(); ++i) EXPECT_EQ(one.data[i], same.data[i]);
}

TEST(FlipPooling, FlipsPooledValues) {
  // Errors 0.3, 0, 0.4, 0.1, 0.2: total 1; sorted running sums 0, 0.1, 0.3, 0.6, 1.0. The weighted
  // percentile p is the first error whose running sum exceeds p: median 0.3, quartiles 0.2 and 0.4.
  Image m(5, 1, 1);
  const float v[5] = {0.3f, 0.0f, 0.4f, 0.1f, 0.2f};
  std::copy(v, v + 5, m.data.begin());
  const FlipPooled p = flip_pooled(m);
  EXPECT_EQ(p.pixels, 5u);
  EXPECT_NEAR(p.mean, 0.2, 1e-7);
  EXPECT_FLOAT_EQ(p.weighted_median, 0.3f);
  EXPECT_FLOAT_EQ(p.weighted_quartile_1, 0.2f);
  EXPECT_FLOAT_EQ(p.weighted_quartile_3, 0.4f);
  EXPECT_EQ(p.min, 0.0);
  EXPECT_FLOAT_EQ(p.max, 0.4f);
  // The weighting: one large error among many small ones pulls the weighted median up to it.
  Image w(10, 1, 1, 0.01f);
  w.data[7] = 0.9f;  // 0.9 of a total 0.99
  EXPECT_FLOAT_EQ(flip_pooled(w).weighted_median, 0.9f);
  EXPECT_FLOAT_EQ(flip_pooled(w).weighted_quartile_1, 0.9f);
  // All zero: every statistic 0 (FLIP's percentile never passes a zero total).
  const FlipPooled z = flip_pooled(Image(3, 3, 1, 0.0f));
  EXPECT_EQ(z.weighted_median, 0.0);
  EXPECT_EQ(z.max, 0.0);
  // A NaN error, or no pixels: NaN, never a number.
  Image n(3, 1, 1, 0.5f);
  n.data[1] = NAN;
  const FlipPooled pn = flip_pooled(n);
  EXPECT_TRUE(std::isnan(pn.mean));
  EXPECT_TRUE(std::isnan(pn.weighted_median));
  EXPECT_TRUE(std::isnan(pn.max));
  EXPECT_TRUE(std::isnan(flip_pooled(Image(0, 0, 1)).mean));
}

// ------------------------------------------------------------------------------------------------
// Agreement with NVIDIA FLIP v1.6 (github.com/NVlabs/flip, commit 1eb247cabcf2862c2c8207ab15314304394132b9,
// 2025-09-01; its C++ tool built from src/cpp/tool/FLIP-tool.cpp with `g++ -O2 -std=c++17 -fopenmp`)
// on the committed images of tests/data/flip/ (made by FlipData.DISABLED_WriteTestImages below).
// Each expected value is the tool's printed output (6 decimals) of
//   flip -r tests/data/flip/<ref> -t tests/data/flip/<test> -nerm -nexm [options]
// Here the images are decoded as FLIP decodes them (EXR: linear RGB as stored; PNG: the sRGB curve)
// and converted to XYZ with the Rec.709 matrix; tests/experiments/compare.cpp checks the same numbers
// through `glintlab compare` and OCIO. Measured agreement: within 1.1e-5 for every value.
namespace {
struct FlipExpected {
  double mean, weighted_median, q1, q3, min, max;
};
void expect_flip(const Image& map, const FlipExpected& e, const std::string& what) {
  const FlipPooled p = flip_pooled(map);
  constexpr double tol = 1e-4;
  EXPECT_NEAR(p.mean, e.mean, tol) << what;
  EXPECT_NEAR(p.weighted_median, e.weighted_median, tol) << what;
  EXPECT_NEAR(p.weighted_quartile_1, e.q1, tol) << what;
  EXPECT_NEAR(p.weighted_quartile_3, e.q3, tol) << what;
  EXPECT_NEAR(p.min, e.min, tol) << what;
  EXPECT_NEAR(p.max, e.max, tol) << what;
}
// A test image as FLIP reads it, as relative XYZ.
Image flip_data_xyz(const std::string& name) {
  const bool srgb = name.size() > 4 && name.substr(name.size() - 4) == ".png";
  const Image im = read_image(std::string(GLINTLAB_TEST_DATA_DIR) + "/flip/" + name);
  Image out(im.width, im.height, 3);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      double c[3];
      for (int k = 0; k < 3; ++k) {
        const double v = im.at(x, y, k);
        c[k] = !srgb ? v : v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
      }
      srgb_to_xyz(c[0], c[1], c[2], out.px(x, y));
    }
  return out;
}
}  // namespace

TEST(FlipReference, LdrMatchesNvidiaFlip) {
  const Image ref = flip_data_xyz("ldr_ref.png");
  const Image noise = flip_data_xyz("ldr_test_noise.png"), shift = flip_data_xyz("ldr_test_shift.png");
  // flip -r ldr_ref.png -t ldr_test_noise.png ldr_test_shift.png -nerm   ("Pixels per degree: 67")
  expect_flip(ldr_flip_map(noise, ref), {0.081440, 0.090092, 0.069457, 0.114668, 0.007287, 0.221094}, "noise");
  expect_flip(ldr_flip_map(shift, ref), {0.295312, 0.374807, 0.291198, 0.427104, 0.023947, 0.868661}, "shift");
  // ... -t ldr_test_noise.png -ppd 40
  expect_flip(ldr_flip_map(noise, ref, 40.0), {0.122746, 0.134524, 0.105719, 0.172262, 0.014452, 0.319318}, "ppd 40");
}

TEST(FlipReference, HdrBimodalMatchesNvidiaFlip) {
  const Image ref = flip_data_xyz("hdr_bimodal_ref.exr"), test = flip_data_xyz("hdr_bimodal_test.exr");
  HdrFlipExposures e;
  // flip -r hdr_bimodal_ref.exr -t hdr_bimodal_test.exr -nerm -nexm
  //   "Start exposure: -4.2029, Stop exposure: -0.9069, Number of exposures: 4". Exactly half the pixels
  //   are dark: the mean of the two middle luminances (0.1006 and 3.973, glintlab's rule before) would
  //   put the stop 0.96 stop higher, at 0.057, with 5 exposures and a mean of 0.0565 (FLIP with -cstop 0.057037).
  expect_flip(hdr_flip_map(test, ref, kFlipDefaultPpd, {}, &e),
              {0.049458, 0.068389, 0.045050, 0.098722, 0.000593, 0.862510}, "aces");
  EXPECT_NEAR(e.start, -4.2029, 1e-4);
  EXPECT_NEAR(e.stop, -0.9069, 1e-4);
  EXPECT_EQ(e.count, 4);
  EXPECT_EQ(hdr_flip_map(test, ref).data, hdr_flip_map(test, ref, kFlipDefaultPpd, {}).data);
  // -tm hable: exposures -3.6411 to -0.3450, 4
  HdrFlipOptions o;
  o.tone_mapper = FlipToneMapper::Hable;
  expect_flip(hdr_flip_map(test, ref, kFlipDefaultPpd, o, &e),
              {0.051696, 0.063526, 0.043313, 0.089486, 0.002940, 0.845463}, "hable");
  EXPECT_NEAR(e.start, -3.6411, 1e-4);
  EXPECT_NEAR(e.stop, -0.3450, 1e-4);
  // -tm reinhard: exposures -2.7837 to 0.5123, 4
  o.tone_mapper = FlipToneMapper::Reinhard;
  expect_flip(hdr_flip_map(test, ref, kFlipDefaultPpd, o, &e),
              {0.080044, 0.104290, 0.073943, 0.132843, 0.004091, 0.814486}, "reinhard");
  EXPECT_NEAR(e.start, -2.7837, 1e-4);
  EXPECT_NEAR(e.stop, 0.5123, 1e-4);
  // -ppd 30
  expect_flip(hdr_flip_map(test, ref, 30.0), {0.092305, 0.135361, 0.085996, 0.185222, 0.001319, 0.979886}, "ppd 30");
  // -vc 0.5 0.6 1920
  expect_flip(hdr_flip_map(test, ref, flip_pixels_per_degree(0.5, 0.6, 1920)),
              {0.098777, 0.145679, 0.092118, 0.197087, 0.001141, 0.982250}, "vc");
  // -cstart -3 -cstop 2 -n 6
  o = {};
  o.start_exposure = -3;
  o.stop_exposure = 2;
  o.num_exposures = 6;
  expect_flip(hdr_flip_map(test, ref, kFlipDefaultPpd, o),
              {0.065192, 0.076480, 0.054088, 0.104283, 0.004056, 0.858680}, "explicit");
  // -cstart -2.5: stop from the reference, "Number of exposures: 2"
  o = {};
  o.start_exposure = -2.5;
  expect_flip(hdr_flip_map(test, ref, kFlipDefaultPpd, o, &e),
              {0.037086, 0.048125, 0.030694, 0.077228, 0.000558, 0.855361}, "start");
  EXPECT_EQ(e.count, 2);
  // -n 3
  o = {};
  o.num_exposures = 3;
  expect_flip(hdr_flip_map(test, ref, kFlipDefaultPpd, o),
              {0.049096, 0.067796, 0.044553, 0.097621, 0.000558, 0.862510}, "n 3");
}

TEST(FlipReference, HdrMedianZeroUsesPositiveMedian) {
  // More than half the reference is black. NVIDIA FLIP v1.6 with its defaults
  //   flip -r hdr_black_ref.exr -t hdr_black_test.exr -nerm -nexm
  // prints "Start exposure: -4.5606, Stop exposure: inf, Number of exposures: -2147483648" and a mean,
  // median, quartiles, min and max of 0.000000 (no exposure is evaluated): no number to match.
  // glintlab's stop comes from the median of the positive luminances instead (metrics/flip.h); the
  // expected values are FLIP's with that stop given:
  //   flip -r hdr_black_ref.exr -t hdr_black_test.exr -nerm -nexm -cstop 2.838110505
  //   ("Start exposure: -4.5606, Stop exposure: 2.8381, Number of exposures: 8")
  const Image ref = flip_data_xyz("hdr_black_ref.exr"), test = flip_data_xyz("hdr_black_test.exr");
  HdrFlipExposures e;
  const Image m = hdr_flip_map(test, ref, kFlipDefaultPpd, {}, &e);
  EXPECT_NEAR(e.start, -4.5606, 1e-4);
  EXPECT_NEAR(e.stop, 2.838110505, 1e-6);
  EXPECT_EQ(e.count, 8);
  expect_flip(m, {0.067461, 0.069428, 0.062303, 0.077556, 0.011289, 0.172801}, "median zero");
}

// ------------------------------------------------------------------------------------------------
// Test images for the comparisons with NVIDIA FLIP (tests/data/flip/, committed). They are made by
// this generator, deterministically (an integer hash, no library random numbers):
//   test_metrics --gtest_also_run_disabled_tests --gtest_filter='FlipData.DISABLED_WriteTestImages'
// writes them again (the FLIP numbers in the tests belong to the committed files; a rewrite gives the
// same pixels, the EXR files differ only in their DateTime attribute).
namespace {
uint32_t hash32(uint32_t x) {  // "lowbias32" integer hash (C. Wellons)
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
double rnd(int x, int y, int k) { return hash32(uint32_t(x) + 1000u * uint32_t(y) + 1000003u * uint32_t(k)) / 4294967296.0; }

constexpr int kW = 96, kH = 64;

// LDR reference, sRGB-encoded in [0, 1]: gradients, a red rectangle, a thin bright diagonal, a 1-px
// checkerboard patch.
void ldr_ref_px(int x, int y, double c[3]) {
  c[0] = 0.15 + 0.7 * x / kW;
  c[1] = 0.2 + 0.6 * y / kH;
  c[2] = 0.5 + 0.3 * std::sin(0.2 * x) * std::cos(0.15 * y);
  if (x >= 10 && x < 30 && y >= 8 && y < 24) c[0] = 0.9, c[1] = 0.1, c[2] = 0.1;
  if (std::abs(x - (y + 20)) == 0) c[0] = c[1] = c[2] = 0.97;
  if (x >= 60 && x < 80 && y >= 30 && y < 50) c[0] = c[1] = c[2] = ((x + y) % 2) ? 0.85 : 0.15;
}
Image ldr_image(int variant) {
  Image im(kW, kH, 3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      double c[3];
      if (variant == 2 && x >= 12 && x < 32 && y >= 9 && y < 25) ldr_ref_px(x - 2, y - 1, c);  // shifted rectangle
      else ldr_ref_px(x, y, c);
      if (variant == 1)  // noise
        for (int k = 0; k < 3; ++k) c[k] += 0.12 * (rnd(x, y, k) - 0.5);
      if (variant == 2) {  // colour shift, the diagonal lost, the checkerboard averaged
        c[1] *= 0.9;
        if (std::abs(x - (y + 20)) == 0) ldr_ref_px(x + 1, y, c), c[1] *= 0.9;
        if (x >= 60 && x < 80 && y >= 30 && y < 50) c[0] = c[1] = c[2] = 0.5;
      }
      for (int k = 0; k < 3; ++k) im.at(x, y, k) = float(std::clamp(c[k], 0.0, 1.0));
    }
  return im;
}

// HDR, linear sRGB. Bimodal: the left half is a dark room (Y about 0.02 to 0.1), the right half a
// window (Y about 4 to 40), exactly half the pixels each, so the two middle luminances lie far apart.
Image hdr_bimodal(bool test) {
  Image im(kW, kH, 3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      double base[3];
      if (x < kW / 2) {
        const double v = 0.02 + 0.08 * (0.5 + 0.5 * std::sin(0.3 * x + 0.2 * y)) * (0.7 + 0.3 * rnd(x, y, 7));
        base[0] = 1.1 * v, base[1] = v, base[2] = 0.8 * v;
      } else {
        const double v = 4.0 * std::exp2(3.3 * (0.5 + 0.5 * std::cos(0.25 * x - 0.1 * y)) * (0.8 + 0.2 * rnd(x, y, 8)));
        base[0] = 0.9 * v, base[1] = v, base[2] = 1.2 * v;
      }
      for (int k = 0; k < 3; ++k) {
        double c = base[k];
        if (test) c *= 1.0 + 0.4 * (rnd(x, y, 10 + k) - 0.5);  // Monte Carlo-like noise
        im.at(x, y, k) = float(c);
      }
    }
  if (test) im.at(20, 30, 0) = im.at(20, 30, 1) = im.at(20, 30, 2) = 500.0f;  // a firefly in the dark room
  return im;
}

// HDR with more than half the reference exactly black (the top 40 of 64 rows: Y_median = 0), a lit
// floor (Y about 0.05 to 2) and three lamps (Y 50).
Image hdr_black(bool test) {
  Image im(kW, kH, 3, 0.0f);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      double c[3] = {0, 0, 0};
      if (y >= 40) {
        const double v = 0.05 + 1.95 * (0.5 + 0.5 * std::sin(0.4 * x)) * (y - 39) / 24.0 * (0.6 + 0.4 * rnd(x, y, 20));
        c[0] = v, c[1] = 0.9 * v, c[2] = 0.7 * v;
      }
      for (int lamp = 0; lamp < 3; ++lamp)
        if (std::abs(x - (20 + 28 * lamp)) <= 1 && std::abs(y - 12) <= 1) c[0] = c[1] = c[2] = 50.0;
      for (int k = 0; k < 3; ++k) {
        double v = c[k];
        if (test) v = v * (1.0 + 0.3 * (rnd(x, y, 30 + k) - 0.5)) + (y < 40 ? 0.002 * rnd(x, y, 40 + k) : 0.0);
        im.at(x, y, k) = float(v);
      }
    }
  return im;
}
}  // namespace

TEST(FlipData, DISABLED_WriteTestImages) {
  const std::string dir = std::string(GLINTLAB_TEST_DATA_DIR) + "/flip";
  std::filesystem::create_directories(dir);
  const std::array<float, 8> rec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  write_png(dir + "/ldr_ref.png", ldr_image(0));
  write_png(dir + "/ldr_test_noise.png", ldr_image(1));
  write_png(dir + "/ldr_test_shift.png", ldr_image(2));
  write_exr(dir + "/hdr_bimodal_ref.exr", hdr_bimodal(false), rec709);
  write_exr(dir + "/hdr_bimodal_test.exr", hdr_bimodal(true), rec709);
  write_exr(dir + "/hdr_black_ref.exr", hdr_black(false), rec709);
  write_exr(dir + "/hdr_black_test.exr", hdr_black(true), rec709);
}

// FLIP (Andersson et al. 2020) and HDR-FLIP (Andersson et al. 2021): limits and invariants of the
// published pipeline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

#include "metrics/flip.h"

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
  // Three pixels at 1 and one at 1024: median 1, max 1024 -> range of log2(1024) = 10 stops.
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
  // Mostly black reference: stop stays finite (median of the positive luminances).
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

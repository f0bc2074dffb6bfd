// Flicker: temporal error and flicker ratio in the PQ luminance encoding (DESIGN.md "Flicker").
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "metrics/delta_e_itp.h"
#include "metrics/flicker.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {
Image frame_y(int w, int h, const std::vector<float>& Y) {
  Image im(w, h, 3, 0.0f);
  for (int i = 0; i < w * h; ++i) {
    im.data[std::size_t(i) * 3 + 0] = 0.95f * Y[i];
    im.data[std::size_t(i) * 3 + 1] = Y[i];
    im.data[std::size_t(i) * 3 + 2] = 1.09f * Y[i];
  }
  return im;
}
// A flickering "reference": a glint field whose pixels switch on and off from frame to frame.
std::vector<std::vector<float>> flickering_sequence(int n, int frames, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<std::vector<float>> seq(frames, std::vector<float>(n));
  for (int f = 0; f < frames; ++f)
    for (int i = 0; i < n; ++i) seq[f][i] = 0.3f + (u(rng) < 0.1f ? 8.0f * u(rng) : 0.0f);
  return seq;
}
}  // namespace

TEST(Flicker, EncodingIsPqOfAbsoluteLuminance) {
  EXPECT_NEAR(perceptual_luminance(1.0), 0.5081, 5e-5);  // 100 cd/m^2, published PQ code value
  EXPECT_NEAR(perceptual_luminance(10.0), 0.7518, 5e-5);  // 1000 cd/m^2
  EXPECT_EQ(perceptual_luminance(-1.0), perceptual_luminance(0.0));
  EXPECT_EQ(perceptual_luminance(2.0, 50.0), pq_inverse_eotf(100.0));
}

TEST(Flicker, RatioSentinels) {
  EXPECT_EQ(flicker_ratio(0.0, 0.0), 1.0);
  EXPECT_EQ(flicker_ratio(0.1, 0.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(flicker_ratio(0.1, 0.2), 0.5);
}

TEST(Flicker, IdenticalSequencesAreExactlyAsStable) {
  const auto seq = flickering_sequence(64, 6, 1);
  FlickerTracker tr;
  for (std::size_t f = 0; f < seq.size(); ++f) {
    const Image im = frame_y(8, 8, seq[f]);
    const auto r = tr.push(im, im);
    if (f == 0) {
      EXPECT_FALSE(r.has_value());
      continue;
    }
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->flicker_ratio, 1.0);
    EXPECT_EQ(r->temporal_error, 0.0);
    EXPECT_GT(r->mean_abs_dR, 0.0);
  }
  EXPECT_EQ(tr.frames().size(), seq.size() - 1);
  EXPECT_EQ(tr.frames_pushed(), seq.size());
  EXPECT_EQ(tr.mean_flicker_ratio(), 1.0);
  EXPECT_EQ(tr.ratio_of_sums(), 1.0);
  EXPECT_EQ(tr.mean_temporal_error(), 0.0);
}

TEST(Flicker, HandComputedTwoPixelSequence) {
  // Pixel values (Y) over three frames; X = PQ(100 Y).
  const std::vector<std::vector<float>> R = {{1.0f, 0.5f}, {1.0f, 1.0f}, {2.0f, 1.0f}};
  const std::vector<std::vector<float>> T = {{1.0f, 0.5f}, {2.0f, 0.5f}, {2.0f, 1.0f}};
  auto X = [](float y) { return pq_inverse_eotf(100.0 * y); };
  FlickerTracker tr;
  tr.push(frame_y(2, 1, T[0]), frame_y(2, 1, R[0]));
  std::vector<FlickerFrame> expect;
  for (int f = 1; f < 3; ++f) {
    double e = 0, st = 0, sr = 0;
    for (int i = 0; i < 2; ++i) {
      const double dT = X(T[f][i]) - X(T[f - 1][i]), dR = X(R[f][i]) - X(R[f - 1][i]);
      e += std::abs(dT - dR);
      st += std::abs(dT);
      sr += std::abs(dR);
    }
    const auto got = tr.push(frame_y(2, 1, T[f]), frame_y(2, 1, R[f]));
    ASSERT_TRUE(got.has_value());
    EXPECT_NEAR(got->temporal_error, e / 2, 1e-6);
    EXPECT_NEAR(got->mean_abs_dT, st / 2, 1e-6);
    EXPECT_NEAR(got->mean_abs_dR, sr / 2, 1e-6);
    EXPECT_NEAR(got->flicker_ratio, st / sr, 1e-5);
    expect.push_back(*got);
  }
  EXPECT_NEAR(tr.mean_flicker_ratio(), 0.5 * (expect[0].flicker_ratio + expect[1].flicker_ratio), 1e-12);
  EXPECT_NEAR(tr.ratio_of_sums(), (expect[0].mean_abs_dT + expect[1].mean_abs_dT) /
                                      (expect[0].mean_abs_dR + expect[1].mean_abs_dR), 1e-12);
  EXPECT_NEAR(tr.mean_temporal_error(), 0.5 * (expect[0].temporal_error + expect[1].temporal_error), 1e-12);
}

TEST(Flicker, NoiseFlickersAndSmoothingOverSmooths) {
  const int w = 16, h = 16, frames = 12;
  const auto ref = flickering_sequence(w * h, frames, 9);
  std::mt19937 rng(4);
  std::normal_distribution<float> noise(0.0f, 0.3f);
  FlickerTracker noisy, smooth;
  std::vector<float> ema = ref[0];
  for (int f = 0; f < frames; ++f) {
    std::vector<float> n = ref[f];
    for (float& v : n) v = std::max(0.0f, v + noise(rng));
    for (int i = 0; i < w * h; ++i) ema[i] = 0.8f * ema[i] + 0.2f * ref[f][i];  // TAA-like history blend
    const Image r = frame_y(w, h, ref[f]);
    noisy.push(frame_y(w, h, n), r);
    smooth.push(frame_y(w, h, ema), r);
  }
  EXPECT_GT(noisy.ratio_of_sums(), 1.0);
  EXPECT_GT(noisy.mean_temporal_error(), 0.0);
  EXPECT_LT(smooth.ratio_of_sums(), 1.0);
  EXPECT_LT(smooth.mean_flicker_ratio(), 1.0);
  EXPECT_GT(smooth.mean_temporal_error(), 0.0);
}

TEST(Flicker, StaticReferenceAndValidation) {
  FlickerTracker tr;
  const Image still = frame_y(2, 2, {1, 1, 1, 1});
  EXPECT_TRUE(std::isnan(tr.mean_flicker_ratio()));  // nothing measured yet
  tr.push(still, still);
  EXPECT_EQ(tr.push(still, still)->flicker_ratio, 1.0);
  EXPECT_EQ(tr.push(frame_y(2, 2, {2, 1, 1, 1}), still)->flicker_ratio, std::numeric_limits<double>::infinity());
  EXPECT_THROW(tr.push(frame_y(1, 4, {1, 1, 1, 1}), frame_y(1, 4, {1, 1, 1, 1})), std::invalid_argument);
  EXPECT_THROW(tr.push(still, frame_y(1, 4, {1, 1, 1, 1})), std::invalid_argument);
  tr.reset();
  EXPECT_FALSE(tr.push(frame_y(1, 4, {1, 1, 1, 1}), frame_y(1, 4, {1, 1, 1, 1})).has_value());
}

// Flicker along the motion (metrics/flicker.h): contrast of the change along
// exact motion vectors, against the reference's; the disocclusion mask; and
// the fixed-pixel temporal error.
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

// Every pixel a surface at distance 10 that moves by (vx, vy) pixels per frame.
Image uniform_motion(int w, int h, float vx, float vy, float dist = 10.0f) {
  Image m(w, h, 4, 0.0f);
  for (std::size_t i = 0; i < m.pixel_count(); ++i) {
    m.data[i * 4 + 0] = vx;
    m.data[i * 4 + 1] = vy;
    m.data[i * 4 + 2] = dist;
    m.data[i * 4 + 3] = dist;
  }
  return m;
}

// A glint field: sparse bright pixels on a 0.3 background.
std::vector<float> glint_field(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(static_cast<size_t>(n));
  for (float& x : v) x = 0.3f + (u(rng) < 0.1f ? 8.0f * u(rng) : 0.0f);
  return v;
}

// Content that moves one pixel right per frame: frame f at x shows pattern[x - f].
std::vector<float> shifted(const std::vector<float>& pattern, int w, int h, int shift) {
  std::vector<float> out(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out[size_t(y) * w + x] = pattern[size_t(y) * (w + 64) + size_t(x - shift + 32)];
  return out;
}

}  // namespace

TEST(Flicker, PqEncodingOfTemporalError) {
  EXPECT_NEAR(perceptual_luminance(1.0), 0.5081, 5e-5);  // 100 cd/m^2, published PQ code value
  EXPECT_NEAR(perceptual_luminance(10.0), 0.7518, 5e-5);  // 1000 cd/m^2
  EXPECT_EQ(perceptual_luminance(-1.0), perceptual_luminance(0.0));
}

TEST(Flicker, RatioSentinels) {
  EXPECT_EQ(flicker_ratio(0.0, 0.0), 1.0);
  EXPECT_EQ(flicker_ratio(0.1, 0.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(flicker_ratio(0.1, 0.2), 0.5);
  EXPECT_TRUE(std::isnan(flicker_ratio(NAN, 1.0)));
}

TEST(Flicker, AdaptationLuminanceIsANormalisedGaussian) {
  // A single bright pixel spreads into a normalised 2-D Gaussian of sigma 2 px.
  Image im = frame_y(31, 31, std::vector<float>(31 * 31, 0.0f));
  im.at(15, 15, 1) = 1.0f;
  std::vector<float> ya = adaptation_luminance(im, 2.0);
  double sum = 0.0;
  for (float v : ya) sum += v;
  EXPECT_NEAR(sum, 1.0, 1e-5);
  const double g0 = 1.0 / (2.0 * M_PI * 4.0);  // continuous 2-D Gaussian peak
  EXPECT_NEAR(ya[15 * 31 + 15], g0, 0.01 * g0 + 1e-4);
  EXPECT_NEAR(ya[15 * 31 + 17] / ya[15 * 31 + 15], std::exp(-0.5), 1e-3);  // one sigma away
}

TEST(Flicker, MovingContentWithExactVectorsIsStable) {
  // Truth and test both show a pattern that moves one pixel per frame: with the
  // exact vectors nothing changes along the motion, though every pixel changes
  // at a fixed position.
  const int w = 24, h = 16;
  std::mt19937 rng(3);
  const std::vector<float> pattern = glint_field((w + 64) * h, rng);
  std::vector<float> noisy_pattern = pattern;
  std::normal_distribution<float> noise(0.0f, 0.2f);
  FlickerTracker exact, noisy;
  const Image motion = uniform_motion(w, h, 1.0f, 0.0f);
  for (int f = 0; f < 6; ++f) {
    const Image ref = frame_y(w, h, shifted(pattern, w, h, f));
    std::vector<float> n = shifted(pattern, w, h, f);
    for (float& v : n) v = std::max(0.0f, v + noise(rng));
    auto r = exact.push(ref, ref, motion);
    auto q = noisy.push(frame_y(w, h, n), ref, motion);
    if (f == 0) {
      EXPECT_FALSE(r.has_value());
      continue;
    }
    ASSERT_TRUE(r.has_value() && q.has_value());
    EXPECT_EQ(r->mean_contrast_ref, 0.0);  // stable along the motion...
    EXPECT_EQ(r->flicker_ratio, 1.0);      // 0 / 0: as stable as the truth
    EXPECT_EQ(r->temporal_error, 0.0);
    EXPECT_EQ(r->temporal_error_mc, 0.0);
    EXPECT_EQ(r->valid_px, size_t((w - 1) * h));  // column 0 came from off-screen
    EXPECT_EQ(r->disoccluded_px, size_t(h));
    EXPECT_GT(q->mean_contrast_test, 0.0);  // ...noise is not
    EXPECT_EQ(q->flicker_ratio, std::numeric_limits<double>::infinity());
    EXPECT_GT(q->temporal_error_mc, 0.0);
  }
}

TEST(Flicker, HandComputedContrastAlongTheMotion) {
  // 3x1 image moving by half a pixel: the previous frame is sampled halfway
  // between two texels.
  const int w = 3, h = 1;
  const std::vector<float> t0 = {1.0f, 3.0f, 5.0f}, r0 = {1.0f, 2.0f, 3.0f};
  const std::vector<float> t1 = {2.0f, 4.0f, 1.0f}, r1 = {1.0f, 1.0f, 1.0f};
  Image motion = uniform_motion(w, h, 0.5f, 0.0f);
  FlickerTracker tr;
  tr.push(frame_y(w, h, t0), frame_y(w, h, r0), motion);
  auto f = tr.push(frame_y(w, h, t1), frame_y(w, h, r1), motion);
  ASSERT_TRUE(f.has_value());
  // Pixel 0 samples x = -0.5: off-screen. Pixels 1 and 2 sample x = 0.5 and 1.5.
  EXPECT_EQ(f->valid_px, 2u);
  EXPECT_EQ(f->disoccluded_px, 1u);
  const std::vector<float> ya = adaptation_luminance(frame_y(w, h, r1));
  const double ct = (std::abs(4.0 - 2.0) / (ya[1] + kContrastEpsilon) + std::abs(1.0 - 4.0) / (ya[2] + kContrastEpsilon)) / 2;
  const double cr = (std::abs(1.0 - 1.5) / (ya[1] + kContrastEpsilon) + std::abs(1.0 - 2.5) / (ya[2] + kContrastEpsilon)) / 2;
  EXPECT_NEAR(f->mean_contrast_test, ct, 1e-6);
  EXPECT_NEAR(f->mean_contrast_ref, cr, 1e-6);
  EXPECT_NEAR(f->flicker_ratio, ct / cr, 1e-6);
  auto X = [](double y) { return pq_inverse_eotf(100.0 * y); };
  double e = 0;
  for (int i = 0; i < 3; ++i) e += std::abs((X(t1[i]) - X(r1[i])) - (X(t0[i]) - X(r0[i])));
  EXPECT_NEAR(f->temporal_error, e / 3, 1e-6);
}

TEST(Flicker, DisocclusionAndBackgroundAreMaskedAndCounted) {
  const int w = 4, h = 1;
  Image m0 = uniform_motion(w, h, 0.0f, 0.0f);
  m0.at(3, 0, 2) = 0.0f;  // pixel 3: sky in frame 0
  Image m1 = uniform_motion(w, h, 0.0f, 0.0f);
  m1.at(0, 0, 3) = 12.0f;   // pixel 0: was at distance 12 but frame 0 saw a surface at 10 there: hidden
  m1.at(1, 0, 3) = -1.0f;   // pixel 1: behind the previous camera
  m1.at(2, 0, 2) = 0.0f;    // pixel 2: sky now (background)
  // pixel 3: surface now, sky in frame 0 at that place: disoccluded
  FlickerTracker tr;
  const Image y = frame_y(w, h, {1, 1, 1, 1});
  tr.push(y, y, m0);
  auto f = tr.push(y, y, m1);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->background_px, 1u);
  EXPECT_EQ(f->disoccluded_px, 3u);
  EXPECT_EQ(f->valid_px, 0u);
  EXPECT_TRUE(std::isnan(f->flicker_ratio));  // nothing to measure is not "as stable as the truth"
}

TEST(Flicker, NoiseFlickersAndSmoothingOverSmooths) {
  const int w = 16, h = 16, frames = 12;
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0.0f, 0.3f);
  const Image still = uniform_motion(w, h, 0.0f, 0.0f);
  FlickerTracker noisy, smooth;
  std::vector<float> ema;
  double ratio_noisy = 0, ratio_smooth = 0;
  for (int f = 0; f < frames; ++f) {
    const std::vector<float> ref = glint_field(w * h, rng);  // a truth that flickers by itself
    std::vector<float> n = ref;
    for (float& v : n) v = std::max(0.0f, v + noise(rng));
    if (ema.empty()) ema = ref;
    for (int i = 0; i < w * h; ++i) ema[i] = 0.8f * ema[i] + 0.2f * ref[i];  // TAA-like history blend
    const Image r = frame_y(w, h, ref);
    auto a = noisy.push(frame_y(w, h, n), r, still);
    auto b = smooth.push(frame_y(w, h, ema), r, still);
    if (a) ratio_noisy += a->flicker_ratio, ratio_smooth += b->flicker_ratio;
  }
  EXPECT_GT(ratio_noisy / (frames - 1), 1.0);
  EXPECT_LT(ratio_smooth / (frames - 1), 1.0);
}

TEST(Flicker, Validation) {
  FlickerTracker tr;
  const Image still = frame_y(2, 2, {1, 1, 1, 1});
  const Image m = uniform_motion(2, 2, 0, 0);
  tr.push(still, still, m);
  EXPECT_THROW(tr.push(frame_y(1, 4, {1, 1, 1, 1}), frame_y(1, 4, {1, 1, 1, 1}), uniform_motion(1, 4, 0, 0)),
               std::invalid_argument);
  EXPECT_THROW(tr.push(still, frame_y(1, 4, {1, 1, 1, 1}), m), std::invalid_argument);
  EXPECT_THROW(tr.push(still, still, Image(2, 2, 2)), std::invalid_argument);
  tr.reset();
  EXPECT_FALSE(tr.push(frame_y(1, 4, {1, 1, 1, 1}), frame_y(1, 4, {1, 1, 1, 1}), uniform_motion(1, 4, 0, 0)));
}

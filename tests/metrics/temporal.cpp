// Flicker along the motion (metrics/flicker.h): contrast of the change along
// exact motion vectors, against the reference's; the disocclusion mask; and
// the fixed-pixel temporal error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
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
  const auto ya = adaptation_luminance(im, 2.0);
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
  const auto ya = adaptation_luminance(frame_y(w, h, r1));
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

namespace {

// Sparkles drawn anti-aliased at sub-pixel positions: each the pixel integral of a Gaussian of
// σ = 0.35 px and peak 20× the background, on a gently textured background; every point of the
// picture (texture and sparkles) at surface position s is at pixel s + v·t in frame t.
struct SparkleScene {
  int w = 96, h = 64;
  std::vector<std::pair<double, double>> at;  // surface positions of the sparkles
  double background(double sx, double sy) const { return 0.3 + 0.05 * std::sin(0.21 * sx) * std::cos(0.17 * sy); }
  // Pixel (x, y)'s integral of a unit Gaussian centred at (cx, cy), σ 0.35 px (separable erf).
  static double coverage(int x, int y, double cx, double cy) {
    const double k = 1.0 / (std::sqrt(2.0) * 0.35);
    auto axis = [&](int p, double c) { return 0.5 * (std::erf((p + 1 - c) * k) - std::erf((p - c) * k)); };
    return axis(x, cx) * axis(y, cy);
  }
  Image frame(double vx, double vy, int t, bool sparkles, const std::vector<std::pair<double, double>>* moved = nullptr) const {
    std::vector<float> Y(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) Y[size_t(y) * w + x] = float(background(x + 0.5 - vx * t, y + 0.5 - vy * t));
    if (sparkles)
      for (const auto& [sx, sy] : moved ? *moved : at) {
        const double cx = moved ? sx : sx + vx * t, cy = moved ? sy : sy + vy * t;
        for (int y = std::max(0, int(cy) - 3); y < std::min(h, int(cy) + 4); ++y)
          for (int x = std::max(0, int(cx) - 3); x < std::min(w, int(cx) + 4); ++x)
            Y[size_t(y) * w + x] += float(6.0 * 2.0 * M_PI * 0.35 * 0.35 * coverage(x, y, cx, cy));
      }
    return frame_y(w, h, Y);
  }
};

struct Excess {
  double excess = 0, lag = 0, fixed = 0, ratio = 0;
};

Excess run_sparkles(const SparkleScene& sc, double vx, double vy, bool redraw, int frames = 10) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> ux(8.0, sc.w - 8.0), uy(8.0, sc.h - 8.0);
  FlickerTracker tr;
  const Image motion = uniform_motion(sc.w, sc.h, float(vx), float(vy));
  Excess e;
  int n = 0;
  for (int t = 0; t < frames; ++t) {
    std::vector<std::pair<double, double>> moved;
    for (size_t i = 0; i < sc.at.size(); ++i) moved.emplace_back(ux(rng), uy(rng));
    const Image ref = sc.frame(vx, vy, t, false);
    const Image test = redraw ? sc.frame(vx, vy, t, true, &moved) : sc.frame(vx, vy, t, true);
    auto f = tr.push(test, ref, motion);
    if (!f) continue;
    e.excess += f->flicker_excess, e.lag += f->temporal_lag, e.fixed += f->flicker_excess_fixed;
    e.ratio += f->flicker_ratio;
    ++n;
  }
  e.excess /= n, e.lag /= n, e.fixed /= n, e.ratio /= n;
  return e;
}

}  // namespace

// A sub-pixel feature that moves exactly with the motion is not flicker: both frames low-passed at
// the eye's resolution before the difference, its excess is interpolation error only — at most 3 %
// of the same sparkles re-drawn at random every frame (measured: see the printed figures), where
// the full-resolution ratio charges the coherent ones with a ratio well above 1.
TEST(Flicker, CoherentSubPixelSparklesAddNoExcess) {
  SparkleScene sc;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(12.0, sc.w - 40.0), uy(12.0, sc.h - 30.0);
  for (int i = 0; i < 40; ++i) sc.at.emplace_back(ux(rng), uy(rng));
  for (double v : {0.1, 0.5, 1.3}) {
    const Excess coherent = run_sparkles(sc, v, 0.4 * v, false), random = run_sparkles(sc, v, 0.4 * v, true);
    std::printf("%.1f px/frame: excess coherent %.3g, re-drawn %.3g (%.2f %%); lag coherent %.3g; "
                "full-resolution ratio coherent %.2f, re-drawn %.2f\n",
                v, coherent.excess, random.excess, 100.0 * coherent.excess / random.excess, coherent.lag, coherent.ratio,
                random.ratio);
    EXPECT_LT(coherent.excess, 0.03 * random.excess) << v;
    EXPECT_GT(random.excess, 0.01) << v;  // clearly > 0: real flicker
  }
}

// The truth against itself: no excess and no lag, exactly. A temporally low-passed truth (a
// TAA-like history blend of a truth that twinkles): lag, and excess at most a tenth of it.
TEST(Flicker, TruthHasNoExcessAndLowPassedTruthLags) {
  const int w = 32, h = 24, frames = 12;
  std::mt19937 rng(13);
  const Image still = uniform_motion(w, h, 0.0f, 0.0f);
  FlickerTracker self, smooth;
  std::vector<float> ema;
  double lag = 0, excess = 0;
  for (int f = 0; f < frames; ++f) {
    const std::vector<float> ref = glint_field(w * h, rng);
    if (ema.empty()) ema = ref;
    for (int i = 0; i < w * h; ++i) ema[size_t(i)] = 0.8f * ema[size_t(i)] + 0.2f * ref[size_t(i)];
    const Image r = frame_y(w, h, ref);
    auto a = self.push(r, r, still);
    auto b = smooth.push(frame_y(w, h, ema), r, still);
    if (!a) continue;
    EXPECT_EQ(a->flicker_excess, 0.0);
    EXPECT_EQ(a->temporal_lag, 0.0);
    EXPECT_EQ(a->flicker_excess_fixed, 0.0);
    lag += b->temporal_lag, excess += b->flicker_excess;
  }
  std::printf("low-passed truth: lag %.4g, excess %.4g\n", lag / (frames - 1), excess / (frames - 1));
  EXPECT_GT(lag, 0.0);
  EXPECT_LT(excess, 0.1 * lag);
}

// Gaze: a dot fixed on the screen over moving content changes for an eye that tracks the surface
// (excess along the motion: at 0.6 px/frame a smooth slide, so measured 13 % of a re-drawn dot's, 7×
// a coherent one's) and not at all for a fixed eye (no excess at a fixed pixel); a dot re-drawn at
// random flickers for both.
TEST(Flicker, ScreenFixedArtefactsShowAlongTheMotionOnly) {
  SparkleScene sc;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> ux(12.0, sc.w - 12.0), uy(12.0, sc.h - 12.0);
  std::vector<std::pair<double, double>> fixed;
  for (int i = 0; i < 40; ++i) fixed.emplace_back(ux(rng), uy(rng));
  const double vx = 0.6, vy = 0.2;
  FlickerTracker screen_fixed;
  const Image motion = uniform_motion(sc.w, sc.h, float(vx), float(vy));
  double along = 0, at_pixel = 0;
  for (int t = 0; t < 10; ++t) {
    auto f = screen_fixed.push(sc.frame(vx, vy, t, true, &fixed), sc.frame(vx, vy, t, false), motion);
    if (f) along += f->flicker_excess, at_pixel += f->flicker_excess_fixed;
  }
  sc.at = fixed;
  const Excess random = run_sparkles(sc, vx, vy, true);
  std::printf("screen-fixed dots: excess along the motion %.3g, at a fixed pixel %.3g; re-drawn: %.3g, %.3g\n",
              along / 9, at_pixel / 9, random.excess, random.fixed);
  EXPECT_GT(along / 9, 0.05 * random.excess);
  EXPECT_LT(along / 9, 0.5 * random.excess);
  EXPECT_LT(at_pixel / 9, 0.001 * random.fixed);
  EXPECT_GT(random.fixed, 0.01);
}

// temporal_score (metrics/flicker.h): the displayed error's change in L* at a fixed pixel, Minkowski
// p = 4. The test images stand for the displayed image here (display planes = the frames themselves).
namespace {

struct ScoreRun {
  FlickerTracker tracker;
  std::vector<double> scores;
  void push(const Image& test, const Image& ref, const Image& motion) {
    auto r = std::make_shared<const FlickerReference>(flicker_reference(ref, &ref));
    if (auto f = tracker.push(test, r, motion, &test)) scores.push_back(f->temporal_score);
  }
  double mean() const {
    double s = 0;
    for (double x : scores) s += x;
    return scores.empty() ? 0.0 : s / double(scores.size());
  }
};

}  // namespace

// The truth against itself scores 0, moving or not; so does an error that does not change (a fixed
// pattern on a still picture): only what changes from frame to frame counts.
TEST(TemporalScore, TruthAgainstItselfAndAConstantErrorScoreZero) {
  const int w = 24, h = 16;
  std::mt19937 rng(31);
  const std::vector<float> pattern = glint_field((w + 64) * h, rng);
  const std::vector<float> still = glint_field(w * h, rng), error = glint_field(w * h, rng);
  std::vector<float> still_test(still.size());
  for (std::size_t i = 0; i < still.size(); ++i) still_test[i] = still[i] + 0.5f * error[i];
  ScoreRun self, constant;
  for (int f = 0; f < 6; ++f) {
    const Image moving = frame_y(w, h, shifted(pattern, w, h, f));
    self.push(moving, moving, uniform_motion(w, h, 1.0f, 0.0f));
    constant.push(frame_y(w, h, still_test), frame_y(w, h, still), uniform_motion(w, h, 0.0f, 0.0f));
  }
  ASSERT_EQ(self.scores.size(), 5u);
  for (double s : self.scores) EXPECT_EQ(s, 0.0);
  for (double s : constant.scores) EXPECT_EQ(s, 0.0);
}

// Noise re-drawn every frame over a still truth: the score grows with the noise, nearly in proportion
// (L* is smooth, so a small change is about linear in it).
TEST(TemporalScore, GrowsWithFlickerAmplitude) {
  const int w = 32, h = 24, frames = 8;
  std::mt19937 rng(17);
  const std::vector<float> ref = glint_field(w * h, rng);
  std::vector<std::vector<float>> noise;
  std::normal_distribution<float> unit(0.0f, 1.0f);
  for (int f = 0; f < frames; ++f) {
    noise.emplace_back(ref.size());
    for (float& v : noise.back()) v = unit(rng);
  }
  auto run = [&](float amplitude) {
    ScoreRun s;
    for (int f = 0; f < frames; ++f) {
      std::vector<float> t = ref;
      for (std::size_t i = 0; i < t.size(); ++i) t[i] = std::max(0.0f, t[i] + amplitude * (0.3f + 0.1f * noise[f][i]));
      s.push(frame_y(w, h, t), frame_y(w, h, ref), uniform_motion(w, h, 0.0f, 0.0f));
    }
    return s.mean();
  };
  const double a = run(0.5f), b = run(1.0f);
  std::printf("temporal_score of re-drawn noise: amplitude 0.5 %.4g, 1.0 %.4g\n", a, b);
  EXPECT_GT(a, 1.0);  // L* units: clearly visible
  EXPECT_GT(b / a, 1.5);
  EXPECT_LT(b / a, 2.5);
}

// A history blend (TAA-like) of a truth that moves one pixel a frame lags behind it: a score above 0
// that falls as the blend follows the current frame more closely (α 0.1 → 0.5 → 1 = no history).
TEST(TemporalScore, LagFallsAsTheHistoryFollows) {
  const int w = 32, h = 16, frames = 10;
  std::mt19937 rng(23);
  const std::vector<float> pattern = glint_field((w + 64) * h, rng);
  auto run = [&](float alpha) {
    ScoreRun s;
    std::vector<float> history;
    for (int f = 0; f < frames; ++f) {
      const std::vector<float> ref = shifted(pattern, w, h, f);
      if (history.empty()) history = ref;
      // The history is reprojected along the motion (one pixel right), then blended.
      std::vector<float> moved(history.size());
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) moved[size_t(y * w + x)] = history[size_t(y * w + std::max(0, x - 1))];
      for (std::size_t i = 0; i < moved.size(); ++i) history[i] = (1 - alpha) * moved[i] + alpha * ref[i];
      s.push(frame_y(w, h, history), frame_y(w, h, ref), uniform_motion(w, h, 1.0f, 0.0f));
    }
    return s.mean();
  };
  const double slow = run(0.1f), half = run(0.5f), none = run(1.0f);
  std::printf("temporal_score of a lagging history: alpha 0.1 %.4g, 0.5 %.4g, 1 %.4g\n", slow, half, none);
  EXPECT_EQ(none, 0.0);
  EXPECT_GT(half, 0.0);
  EXPECT_GT(slow, half);
}

// Minkowski pooling (p = 4): one pixel changing by ΔL* = c outweighs every pixel changing so that the
// sum of their changes is about the same; the value is the hand-computed (Σc⁴/n)^(1/4) with
// L* = 116 Y^(1/3) − 16.
TEST(TemporalScore, FewStrongChangesOutweighManyFaintOnes) {
  const int w = 16, h = 16, n = w * h;
  const std::vector<float> ref(n, 0.5f);
  const Image motion = uniform_motion(w, h, 0.0f, 0.0f);
  std::vector<float> one = ref, all = ref;
  const float step = 0.5f;
  one[8 * w + 8] += step;
  for (float& v : all) v += step / float(n);
  ScoreRun strong, faint;
  strong.push(frame_y(w, h, ref), frame_y(w, h, ref), motion);
  strong.push(frame_y(w, h, one), frame_y(w, h, ref), motion);
  faint.push(frame_y(w, h, ref), frame_y(w, h, ref), motion);
  faint.push(frame_y(w, h, all), frame_y(w, h, ref), motion);
  const double c = 116.0 * (std::cbrt(1.0) - std::cbrt(0.5));  // ΔL* of the one pixel: 23.93
  EXPECT_NEAR(strong.scores.at(0), c / std::pow(double(n), 0.25), 1e-4 * c);
  EXPECT_GT(strong.scores.at(0), 3.0 * faint.scores.at(0));
}

// Without the displayed planes (a tracker fed XYZ only) there is no temporal_score: NaN, never 0.
TEST(TemporalScore, NaNWithoutTheDisplayedImage) {
  const Image y = frame_y(4, 4, std::vector<float>(16, 0.4f));
  FlickerTracker tr;
  tr.push(y, y, uniform_motion(4, 4, 0, 0));
  auto f = tr.push(y, y, uniform_motion(4, 4, 0, 0));
  ASSERT_TRUE(f.has_value());
  EXPECT_TRUE(std::isnan(f->temporal_score));
}

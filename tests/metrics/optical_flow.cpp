// Estimated motion by DIS optical flow (metrics/optical_flow.h): glintlab's
// direction convention, sub-pixel accuracy on a known translation, zero motion,
// the forward-backward mask at a disocclusion, the tone curve, and bad input.
// The frames are evaluated from an analytic texture at shifted coordinates
// (no resampling in the test itself).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "metrics/optical_flow.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {

// A smooth random texture with values in [0.1, 1.9]: three broad sinusoids and
// band-limited noise (random-phase sinusoids with periods of 5 to 24 px in
// random directions), evaluated anywhere.
struct Texture {
  struct Wave {
    double kx, ky, phase, amp;
  };
  std::vector<Wave> waves;
  double norm = 1.0;

  explicit Texture(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double two_pi = 2.0 * M_PI;
    for (double period : {61.0, 43.0, 29.0}) {
      const double a = two_pi * u(rng);
      waves.push_back({two_pi / period * std::cos(a), two_pi / period * std::sin(a), two_pi * u(rng), 1.0});
    }
    for (int i = 0; i < 32; ++i) {
      const double period = 5.0 + 19.0 * u(rng), a = two_pi * u(rng);
      waves.push_back({two_pi / period * std::cos(a), two_pi / period * std::sin(a), two_pi * u(rng), 0.35});
    }
    double sum = 0.0;
    for (const Wave& w : waves) sum += w.amp;
    norm = 0.9 / sum;
  }
  double operator()(double x, double y) const {
    double s = 0.0;
    for (const Wave& w : waves) s += w.amp * std::sin(w.kx * x + w.ky * y + w.phase);
    return 1.0 + norm * s;
  }
};

// One channel: the texture moved by (dx, dy): pixel p shows T(p - d).
Image frame(const Texture& t, int w, int h, double dx = 0.0, double dy = 0.0) {
  Image im(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) im.at(x, y, 0) = float(t(x - dx, y - dy));
  return im;
}

struct Mean {
  double x = 0, y = 0;
  std::size_t n = 0;
};
// Mean of v over the pixels at least `margin` from the border.
Mean interior_mean(const Image& m, int margin) {
  Mean r;
  for (int y = margin; y < m.height - margin; ++y)
    for (int x = margin; x < m.width - margin; ++x) {
      r.x += m.at(x, y, 0);
      r.y += m.at(x, y, 1);
      ++r.n;
    }
  r.x /= double(r.n);
  r.y /= double(r.n);
  return r;
}

// Bilinear sample of channel 0 at (x, y), clamped to the image.
double bilinear(const Image& im, double x, double y) {
  x = std::clamp(x, 0.0, im.width - 1.0);
  y = std::clamp(y, 0.0, im.height - 1.0);
  const int x0 = std::min(int(x), im.width - 2), y0 = std::min(int(y), im.height - 2);
  const double fx = x - x0, fy = y - y0;
  return (1 - fy) * ((1 - fx) * im.at(x0, y0, 0) + fx * im.at(x0 + 1, y0, 0)) +
         fy * ((1 - fx) * im.at(x0, y0 + 1, 0) + fx * im.at(x0 + 1, y0 + 1, 0));
}

constexpr int kW = 192, kH = 144, kMargin = 16;

}  // namespace

TEST(OpticalFlow, SubPixelTranslationInGlintlabsDirection) {
  const Texture tex(7);
  const double tx = 1.3, ty = -0.7;  // content moves 1.3 px right and 0.7 px up
  const Image prev = frame(tex, kW, kH), now = frame(tex, kW, kH, tx, ty);
  const Image m = estimate_motion(prev, now);
  ASSERT_EQ(m.channels, 4);
  ASSERT_EQ(m.width, kW);
  ASSERT_EQ(m.height, kH);
  const Mean v = interior_mean(m, kMargin);
  EXPECT_NEAR(v.x, tx, 0.1);
  EXPECT_NEAR(v.y, ty, 0.1);
  // Nearly every interior pixel on its own, and z = w = 1 everywhere (no check asked for).
  std::size_t close = 0, n = 0;
  for (int y = kMargin; y < kH - kMargin; ++y)
    for (int x = kMargin; x < kW - kMargin; ++x, ++n)
      close += std::hypot(m.at(x, y, 0) - tx, m.at(x, y, 1) - ty) < 0.25;
  EXPECT_GT(double(close) / double(n), 0.95);
  for (std::size_t i = 0; i < m.pixel_count(); ++i) {
    ASSERT_EQ(m.data[i * 4 + 2], 1.0f);
    ASSERT_EQ(m.data[i * 4 + 3], 1.0f);
  }
  // What the convention is for: the previous frame at p - v is the current frame at p
  // (the warping error along v is far below the one without motion and against it).
  double e_v = 0, e_0 = 0, e_flip = 0;
  for (int y = kMargin; y < kH - kMargin; ++y)
    for (int x = kMargin; x < kW - kMargin; ++x) {
      const double vx = m.at(x, y, 0), vy = m.at(x, y, 1), c = now.at(x, y, 0);
      e_v += std::abs(bilinear(prev, x - vx, y - vy) - c);
      e_0 += std::abs(prev.at(x, y, 0) - c);
      e_flip += std::abs(bilinear(prev, x + vx, y + vy) - c);
    }
  EXPECT_LT(e_v, 0.1 * e_0);
  EXPECT_LT(e_v, 0.1 * e_flip);
}

TEST(OpticalFlow, EveryPresetAndAChannelOfAnExposedImage) {
  const Texture tex(11);
  const double tx = -2.4, ty = 1.6;
  const Image p1 = frame(tex, kW, kH), n1 = frame(tex, kW, kH, tx, ty);
  // Y in channel 1 of a 3-channel image, 1000x brighter, other channels noise: the same motion
  // (the tone curve's exposure is the pair's median, so the codes do not depend on the scale).
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 50.0f);
  auto xyz = [&](const Image& y1) {
    Image im(kW, kH, 3);
    for (std::size_t i = 0; i < im.pixel_count(); ++i) {
      im.data[i * 3 + 0] = u(rng);
      im.data[i * 3 + 1] = 1000.0f * y1.data[i];
      im.data[i * 3 + 2] = u(rng);
    }
    return im;
  };
  const Image p3 = xyz(p1), n3 = xyz(n1);
  for (FlowPreset preset : {FlowPreset::kUltrafast, FlowPreset::kFast, FlowPreset::kMedium}) {
    SCOPED_TRACE(int(preset));
    FlowOptions o;
    o.preset = preset;
    const Mean v1 = interior_mean(estimate_motion(p1, n1, o), kMargin);
    EXPECT_NEAR(v1.x, tx, 0.15);
    EXPECT_NEAR(v1.y, ty, 0.15);
    o.channel = 1;
    const Mean v3 = interior_mean(estimate_motion(p3, n3, o), kMargin);
    EXPECT_NEAR(v3.x, v1.x, 0.02);
    EXPECT_NEAR(v3.y, v1.y, 0.02);
  }
}

TEST(OpticalFlow, ZeroMotionIsZeroAndConsistent) {
  const Texture tex(5);
  const Image a = frame(tex, kW, kH);
  FlowOptions o;
  o.forward_backward = true;
  const Image m = estimate_motion(a, a, o);
  double worst = 0.0;
  for (std::size_t i = 0; i < m.pixel_count(); ++i) {
    worst = std::max(worst, std::hypot(double(m.data[i * 4]), double(m.data[i * 4 + 1])));
    ASSERT_EQ(m.data[i * 4 + 3], 1.0f) << "pixel " << i;
  }
  EXPECT_LT(worst, 0.05);
}

TEST(OpticalFlow, ForwardBackwardMarksTheRevealedBackground) {
  // A static background and a 48x48 square of another texture that moves 8 px right:
  // in frame t the strip x in [sx, sx + 8) of the square's rows shows background that the
  // square covered in frame t-1 (disoccluded: nothing in frame t-1 to match). DIS smears the
  // square's motion some 6 px into the background, both ways alike, so the check finds only
  // the part of the strip beyond the smear (about 25 % of it at 6 px, 70 % at 8, all at 12).
  const Texture bg(21), fg(22);
  const int sx = 72, sy = 48, side = 48, d = 8;
  auto make = [&](int ox) {
    Image im(kW, kH, 1);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const bool in = x >= ox && x < ox + side && y >= sy && y < sy + side;
        // The square's texture moves with it and is darker (an object in front).
        im.at(x, y, 0) = in ? float(0.3 * fg(x - ox, y - sy)) : float(bg(x, y));
      }
    return im;
  };
  const Image prev = make(sx), now = make(sx + d);
  FlowOptions o;
  o.forward_backward = true;
  const Image m = estimate_motion(prev, now, o);

  std::size_t revealed = 0, revealed_marked = 0, far = 0, far_ok = 0, inside = 0, inside_ok = 0;
  double inside_vx = 0, far_v = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool w_ok = m.at(x, y, 3) == 1.0f;
      ASSERT_TRUE(m.at(x, y, 3) == 1.0f || m.at(x, y, 3) == -1.0f);
      ASSERT_EQ(m.at(x, y, 2), 1.0f);
      if (y >= sy + 2 && y < sy + side - 2 && x >= sx && x < sx + d) {
        ++revealed;
        revealed_marked += !w_ok;
      }
      // The square's interior, away from its edges, and the background away from the square and the border.
      if (x >= sx + d + 8 && x < sx + d + side - 8 && y >= sy + 8 && y < sy + side - 8) {
        ++inside;
        inside_ok += w_ok;
        inside_vx += m.at(x, y, 0);
      }
      const bool near_square = x >= sx - 12 && x < sx + d + side + 12 && y >= sy - 12 && y < sy + side + 12;
      if (!near_square && x >= kMargin && x < kW - kMargin && y >= kMargin && y < kH - kMargin) {
        ++far;
        far_ok += w_ok;
        far_v += std::hypot(m.at(x, y, 0), m.at(x, y, 1));
      }
    }
  EXPECT_GT(double(revealed_marked) / double(revealed), 0.4) << revealed_marked << " of " << revealed;
  EXPECT_GT(double(inside_ok) / double(inside), 0.9);
  EXPECT_GT(double(far_ok) / double(far), 0.95);
  EXPECT_NEAR(inside_vx / double(inside), d, 0.3);
  EXPECT_LT(far_v / double(far), 0.1);
  // Without the check nothing is marked.
  const Image plain = estimate_motion(prev, now);
  for (std::size_t i = 0; i < plain.pixel_count(); ++i) ASSERT_EQ(plain.data[i * 4 + 3], 1.0f);
}

TEST(OpticalFlow, ToneCurveIsSharedAndGuarded) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  Image a(1, 6, 1), b(1, 2, 1);
  a.data = {0.0f, -1.0f, nan, inf, 2.0f, 2.0f};
  b.data = {4.0f, 1000.0f};
  // Positive finite values of both: 2, 2, 4, 1000 -> median (2 + 4) / 2.
  EXPECT_DOUBLE_EQ(flow_exposure(a, b, 0), 3.0);
  EXPECT_DOUBLE_EQ(flow_exposure(Image(4, 4, 1, 0.0f), Image(4, 4, 1, -1.0f), 0), 1.0);
  Image c(1, 5, 1);
  c.data = {0.0f, 3.0f, 3.0f * 256.0f, 3.0f * 1e6f, 3.0f / 256.0f};
  const std::vector<std::uint8_t> code = encode_for_flow(c, 0, 3.0);
  EXPECT_EQ(code[0], 0);
  EXPECT_EQ(code[1], 128);  // the exposure
  EXPECT_EQ(code[2], 255);  // encode_max
  EXPECT_EQ(code[3], 255);  // clipped
  EXPECT_EQ(code[4], 16);   // the toe: ln(2) / ln(65537) of the way
  const std::vector<std::uint8_t> bad = encode_for_flow(a, 0, 3.0);
  EXPECT_EQ(bad[1], 0);  // negative
  EXPECT_EQ(bad[2], 0);  // NaN
  EXPECT_EQ(bad[3], 0);  // Inf

  // NaN and Inf pixels in real frames: finite motion, still the right one.
  const Texture tex(9);
  Image prev = frame(tex, kW, kH), now = frame(tex, kW, kH, 1.0, 0.5);
  for (int k = 0; k < 40; ++k) {
    prev.at(20 + 3 * k, 30 + k, 0) = nan;
    now.at(25 + 2 * k, 100 - k, 0) = (k % 2) ? inf : -inf;
  }
  FlowOptions o;
  o.forward_backward = true;
  const Image m = estimate_motion(prev, now, o);
  for (float v : m.data) ASSERT_TRUE(std::isfinite(v));
  const Mean v = interior_mean(m, kMargin);
  EXPECT_NEAR(v.x, 1.0, 0.1);
  EXPECT_NEAR(v.y, 0.5, 0.1);
}

TEST(OpticalFlow, BadInputThrows) {
  const Image a(64, 48, 1, 0.5f), b(64, 47, 1, 0.5f), four(64, 48, 4, 0.5f);
  EXPECT_THROW(estimate_motion(a, b), std::invalid_argument);
  EXPECT_THROW(estimate_motion(Image(), Image()), std::invalid_argument);
  FlowOptions o;
  o.channel = 1;
  EXPECT_THROW(estimate_motion(a, four, o), std::invalid_argument);  // no channel 1 in a
  EXPECT_NO_THROW(estimate_motion(four, four, o));
  o.channel = -1;
  EXPECT_THROW(estimate_motion(four, four, o), std::invalid_argument);
  FlowOptions e;
  e.encode_max = std::numeric_limits<double>::infinity();
  EXPECT_THROW(estimate_motion(a, a, e), std::invalid_argument);
  e.encode_max = 1e-3;  // below the toe
  EXPECT_THROW(estimate_motion(a, a, e), std::invalid_argument);
  // Sizes where OpenCV 4.6's DIS would read out of bounds or refuse: a clear error instead.
  EXPECT_THROW(estimate_motion(Image(100, 8, 1), Image(100, 8, 1)), std::invalid_argument);
  EXPECT_THROW(estimate_motion(Image(8, 8, 1), Image(8, 8, 1)), std::invalid_argument);
  FlowOptions fast;
  fast.preset = FlowPreset::kFast;
  EXPECT_THROW(estimate_motion(Image(600, 20, 1), Image(600, 20, 1), fast), std::invalid_argument);
  EXPECT_THROW(estimate_motion(Image(100, 24, 1), Image(100, 24, 1), fast), std::invalid_argument);
  EXPECT_NO_THROW(estimate_motion(Image(100, 24, 1), Image(100, 24, 1)));  // medium: 16 and 46 suffice
  try {
    estimate_motion(a, b);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("64x48"), std::string::npos) << ex.what();
    EXPECT_NE(std::string(ex.what()).find("64x47"), std::string::npos) << ex.what();
  }
}

// Plain errors (PSNR, MSE, MAE, relative), pooled error, glint statistics, pixel scan and the registry.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "metrics/ciede2000.h"
#include "metrics/error_metrics.h"
#include "metrics/glint_stats.h"
#include "metrics/metric_registry.h"
#include "metrics/pixel_scan.h"
#include "metrics/pooled_error.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {
// Grey XYZ image (D65 white chromaticity) with luminance Y everywhere.
Image grey(int w, int h, float Y, int channels = 3) {
  Image im(w, h, channels, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      im.at(x, y, 0) = 0.950456f * Y;
      im.at(x, y, 1) = Y;
      im.at(x, y, 2) = 1.089058f * Y;
    }
  return im;
}
void set_y(Image& im, int x, int y, float Y) {
  im.at(x, y, 0) = 0.950456f * Y;
  im.at(x, y, 1) = Y;
  im.at(x, y, 2) = 1.089058f * Y;
}
}  // namespace

// ---------------------------------------------------------------- error_metrics
TEST(ErrorMetrics, MseAndPsnrAreWhatTheySay) {
  Image r = grey(2, 2, 0.5f), t = r;
  const float d[4] = {1, -1, 3, -3};
  for (int i = 0; i < 4; ++i) t.data[i * 3 + 1] += d[i];
  EXPECT_NEAR(mean_squared_error_y(t, r), 5.0, 1e-6);    // (1+1+9+9)/4
  EXPECT_NEAR(psnr_y(t, r, 1.0), 10.0 * std::log10(1.0 / 5.0), 1e-5);
  // Constant offset 0.1: MSE 0.01 -> 20 dB at peak 1, 10 log10(4 / 0.01) at peak 2.
  Image o = r;
  for (int i = 0; i < 4; ++i) o.data[i * 3 + 1] += 0.1f;
  EXPECT_NEAR(psnr_y(o, r), 20.0, 1e-4);
  EXPECT_NEAR(psnr_y(o, r, 2.0), 10.0 * std::log10(400.0), 1e-4);
  // Identical: +inf.
  EXPECT_EQ(psnr_y(r, r), std::numeric_limits<double>::infinity());
  EXPECT_THROW(psnr_y(o, r, 0.0), std::invalid_argument);
}

TEST(ErrorMetrics, ChannelVariantsSeeChromaErrorsLuminanceDoesNot) {
  Image r = grey(3, 1, 0.5f, 4), t = r;
  for (int x = 0; x < 3; ++x) {
    t.at(x, 0, 0) += 2.0f;  // X only
    t.at(x, 0, 3) = 100.0f;  // alpha ignored
  }
  EXPECT_EQ(mean_squared_error_y(t, r), 0.0);
  EXPECT_NEAR(mean_absolute_error_channels(t, r), 2.0 / 3.0, 1e-6);
}

TEST(ErrorMetrics, RelativeError) {
  Image r(3, 1, 3, 0.0f), t(3, 1, 3, 0.0f);
  r.at(0, 0, 1) = 1.0f;  t.at(0, 0, 1) = 1.5f;     // 0.5 / 1.01
  r.at(1, 0, 1) = 0.0f;  t.at(1, 0, 1) = 0.01f;    // 0.01 / 0.01 = 1
  r.at(2, 0, 1) = -5.0f; t.at(2, 0, 1) = 0.0f;     // negative ref: 5 / (0 + 0.01)
  const Image m = relative_error_map(t, r);
  EXPECT_NEAR(m.at(0, 0, 0), 0.5 / 1.01, 1e-6);
  EXPECT_NEAR(m.at(1, 0, 0), 1.0, 1e-5);
  EXPECT_NEAR(m.at(2, 0, 0), 500.0, 1e-3);
  // Channel variant: X, Y, Z all 1 -> 2: each |1| / 1.01.
  const Image a = grey(1, 1, 1.0f), b = grey(1, 1, 2.0f);
  const double e = (0.950456 / (0.950456 + 0.01) + 1.0 / 1.01 + 1.089058 / (1.089058 + 0.01)) / 3.0;
  EXPECT_NEAR(relative_error_channels_map(b, a).at(0, 0, 0), e, 1e-5);
}

TEST(ErrorMetrics, SizeMismatchNamesBothSizes) {
  try {
    mean_squared_error_y(Image(4, 3, 3), Image(5, 3, 3));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("4x3"), std::string::npos) << m;
    EXPECT_NE(m.find("5x3"), std::string::npos) << m;
  }
}

// ---------------------------------------------------------------- pooled_error
TEST(PooledError, IidNoiseHasNoBiasAndRmsFallsAsOneOverBlockSize) {
  const int n = 512;
  const double sigma = 0.1;
  Image r = grey(n, n, 0.5f), t = r;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, sigma);
  for (int i = 0; i < n * n; ++i) t.data[std::size_t(i) * 3 + 1] += float(noise(rng));
  const auto s = pooled_error(t, r);
  ASSERT_EQ(s.size(), 6u);
  for (const PooledErrorScale& p : s) {
    const double expected = sigma / p.block_size;  // std of the mean of block_size^2 samples
    const double nblocks = double(p.blocks_x) * p.blocks_y;
    // The rms estimate from nblocks samples has relative std ~ 1 / sqrt(2 nblocks); allow 4 of them.
    EXPECT_NEAR(p.rms / expected, 1.0, 4.0 / std::sqrt(2.0 * nblocks) + 0.01) << p.block_size;
    // The bias is the grand mean of the noise over the pooled area: std sigma / sqrt(pixels).
    EXPECT_LT(std::abs(p.bias), 4.0 * sigma / std::sqrt(nblocks * p.block_size * p.block_size)) << p.block_size;
    EXPECT_NEAR(p.ref_mean, 0.5, 1e-6);
  }
}

TEST(PooledError, ConstantOffsetIsTheBiasAtEveryScale) {
  Image r(100, 70, 3, 0.0f), t(100, 70, 3, 0.0f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.5f, 3.0f);
  for (int y = 0; y < 70; ++y)
    for (int x = 0; x < 100; ++x) {
      r.at(x, y, 1) = u(rng);
      t.at(x, y, 1) = r.at(x, y, 1) + 0.25f;
    }
  const auto s = pooled_error(t, r);
  ASSERT_EQ(s.size(), 6u);  // 64 fits once in 70 x 100
  for (const PooledErrorScale& p : s) {
    EXPECT_NEAR(p.bias, 0.25, 1e-5) << p.block_size;
    EXPECT_NEAR(p.rms, 0.25, 1e-5) << p.block_size;
    EXPECT_NEAR(p.relative_bias, 0.25 / p.ref_mean, 1e-5);
    EXPECT_EQ(p.blocks_x, 100 / p.block_size);
    EXPECT_EQ(p.blocks_y, 70 / p.block_size);
  }
}

TEST(PooledError, SkipsBlocksLargerThanImageAndIgnoresRemainder) {
  Image r = grey(40, 40, 1.0f), t = r;
  // Rows and columns beyond 32 are the remainder at s = 32: an error there is invisible at that scale.
  for (int y = 0; y < 40; ++y) t.at(39, y, 1) = 5.0f;
  const auto s = pooled_error(t, r);
  ASSERT_EQ(s.size(), 5u);
  EXPECT_EQ(s.back().block_size, 32);
  EXPECT_EQ(s.back().bias, 0.0);
  EXPECT_GT(s.front().bias, 0.0);  // s = 2 covers column 39
  // Relative values with a black reference never divide by zero.
  const auto z = pooled_error(grey(8, 8, 0.0f), grey(8, 8, 0.0f), 1, {2});
  EXPECT_EQ(z[0].relative_bias, 0.0);
  const auto zi = pooled_error(grey(8, 8, 1.0f), grey(8, 8, 0.0f), 1, {2});
  EXPECT_EQ(zi[0].relative_bias, std::numeric_limits<double>::infinity());
  EXPECT_THROW(pooled_error(r, r, 5), std::invalid_argument);
}

// ---------------------------------------------------------------- glint_stats
// The default sizes double from 2 to 64: each is summed from the blocks of the one before. Against
// every size computed alone from the pixels, on an HDR image whose sizes leave remainders.
TEST(PooledError, BlocksSummedFromHalfBlocksEqualTheDirectSums) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image t(203, 141, 4, 1.0f), r(203, 141, 4, 1.0f);
  for (size_t i = 0; i < t.data.size(); ++i) {
    r.data[i] = u(rng);
    t.data[i] = r.data[i] + 0.3f * (u(rng) - 0.5f) + (u(rng) < 0.002f ? 500.0f : 0.0f);  // sparkles
  }
  const auto all = pooled_error(t, r);
  ASSERT_EQ(all.size(), 6u);  // 64 < 141: every default size fits
  for (const auto& p : all) {
    const auto alone = pooled_error(t, r, 1, {p.block_size});
    ASSERT_EQ(alone.size(), 1u);
    EXPECT_EQ(alone[0].blocks_x, p.blocks_x);
    EXPECT_EQ(alone[0].blocks_y, p.blocks_y);
    EXPECT_NEAR(p.bias, alone[0].bias, 1e-12 * std::abs(alone[0].bias) + 1e-15) << p.block_size;
    EXPECT_NEAR(p.rms, alone[0].rms, 1e-12 * alone[0].rms) << p.block_size;
    EXPECT_NEAR(p.ref_mean, alone[0].ref_mean, 1e-12 * alone[0].ref_mean) << p.block_size;
  }
  // A list that does not double is summed from the pixels at every size.
  const auto odd = pooled_error(t, r, 1, {3, 6, 5});
  ASSERT_EQ(odd.size(), 3u);
  EXPECT_EQ(odd[1].blocks_x, 203 / 6);
  EXPECT_NEAR(odd[1].rms, pooled_error(t, r, 1, {6})[0].rms, 1e-12 * odd[1].rms);
}

TEST(GlintStats, LocalMeanIsTheClippedBoxMean) {
  Image im(9, 7, 3, 0.0f);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 4.0f);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x) im.at(x, y, 1) = u(rng);
  const Image m = local_mean_luminance(im, 5);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x) {
      double s = 0;
      int c = 0;
      for (int j = std::max(0, y - 2); j <= std::min(6, y + 2); ++j)
        for (int i = std::max(0, x - 2); i <= std::min(8, x + 2); ++i) {
          s += im.at(i, j, 1);
          ++c;
        }
      EXPECT_NEAR(m.at(x, y, 0), s / c, 1e-5);
    }
}

TEST(GlintStats, CountsIsolatedSpikesAboveThreshold) {
  // 200 x 100 background of 1 with spikes 20 px apart (windows never see two spikes).
  Image im = grey(200, 100, 1.0f);
  int strong = 0;
  for (int y = 10; y < 100; y += 20)
    for (int x = 10; x < 200; x += 20) {
      // Alternate strong (ratio 10 / (1 + 9/225) = 9.6 > 4) and weak (3 / (1 + 2/225) = 2.97 < 4) spikes.
      const bool s = ((x + y) / 20) % 2 == 0;
      set_y(im, x, y, s ? 10.0f : 3.0f);
      strong += s;
    }
  const GlintStats g = glint_stats(im);
  EXPECT_EQ(g.glints, std::size_t(strong));
  EXPECT_NEAR(g.density_per_1000px, 1000.0 * strong / (200.0 * 100.0), 1e-12);
  // All strong spikes have ratio 10 / (234 / 225): in the bin whose edges bracket it.
  const double ratio = 10.0 / (234.0 / 225.0);
  double total = 0.0;
  for (std::size_t b = 0; b < g.histogram.size(); ++b) {
    const bool inside = g.bin_edges[b] <= ratio && ratio < g.bin_edges[b + 1];
    EXPECT_NEAR(g.histogram[b], inside ? 1.0 : 0.0, 1e-12) << b;
    total += g.histogram[b];
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_NEAR(g.bin_edges.front(), 4.0, 1e-12);
  EXPECT_NEAR(g.bin_edges.back(), 225.0, 1e-9);
  // Flat image: no glints.
  EXPECT_EQ(glint_stats(grey(50, 50, 3.0f)).glints, 0u);
}

TEST(GlintStats, HistogramDistances) {
  GlintOptions o;
  o.bins = 6;
  // Spikes of two brightnesses whose ratios land two bins apart.
  const double lo = std::log2(4.0), bw = (std::log2(225.0) - lo) / 6.0;
  auto spike_for_bin = [&](int b) {  // centre of bin b -> spike value v with v / ((v + 224) / 225) = ratio
    const double ratio = std::exp2(lo + (b + 0.5) * bw);
    return float(224.0 * ratio / (225.0 - ratio));
  };
  Image a = grey(120, 120, 1.0f), b = a;
  for (int y = 10; y < 120; y += 20)
    for (int x = 10; x < 120; x += 20) {
      set_y(a, x, y, spike_for_bin(1));
      set_y(b, x, y, spike_for_bin(3));
    }
  const GlintComparison c = compare_glints(b, a, o);
  EXPECT_EQ(c.test.glints, 36u);
  EXPECT_EQ(c.ref.glints, 36u);
  EXPECT_EQ(c.density_difference_per_1000px, 0.0);
  EXPECT_NEAR(c.emd_octaves, 2.0 * bw, 1e-9);  // all mass moved by two bins
  EXPECT_NEAR(c.hellinger, 1.0, 1e-12);         // disjoint histograms
  const GlintComparison same = compare_glints(a, a, o);
  EXPECT_EQ(same.emd_octaves, 0.0);
  EXPECT_EQ(same.hellinger, 0.0);
  // One side without glints.
  const GlintComparison none = compare_glints(grey(120, 120, 1.0f), a, o);
  EXPECT_EQ(none.emd_octaves, std::numeric_limits<double>::infinity());
  EXPECT_EQ(none.hellinger, 1.0);
  EXPECT_LT(none.density_difference_per_1000px, 0.0);
  EXPECT_THROW(glint_stats(a, GlintOptions{4.0, 14, 12}), std::invalid_argument);
}

// ---------------------------------------------------------------- pixel_scan
TEST(PixelScan, CountsPixelsOncePerCategory) {
  Image im(4, 2, 4, 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  im.at(0, 0, 0) = nan;
  im.at(0, 0, 2) = nan;  // same pixel, still 1
  im.at(1, 0, 1) = inf;
  im.at(2, 0, 0) = -inf;
  im.at(2, 0, 1) = inf;  // both +inf and -inf in one pixel
  im.at(3, 0, 2) = -0.25f;
  im.at(3, 0, 0) = -1.0f;
  im.at(0, 1, 1) = -0.0f;  // not negative
  im.at(1, 1, 3) = nan;    // alpha is scanned by default
  const PixelScan s = scan_pixels(im);
  EXPECT_EQ(s.pixels, 8u);
  EXPECT_EQ(s.nan, 2u);
  EXPECT_EQ(s.pos_inf, 2u);
  EXPECT_EQ(s.neg_inf, 1u);
  EXPECT_EQ(s.infinite, 2u);
  EXPECT_EQ(s.negative, 1u);
  EXPECT_FALSE(s.clean());
  EXPECT_EQ(scan_pixels(im, 3).nan, 1u);  // alpha left out
  EXPECT_TRUE(scan_pixels(Image(3, 3, 4, 1.0f)).clean());
}

// scan_pixels skips blocks whose bits are all clean: against the definition, pixel by pixel, with
// special values scattered over many blocks, the last one partial, some only in the unscanned alpha.
TEST(PixelScan, TheBlockTestCountsWhatThePixelDefinitionCounts) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float special[] = {nan, inf, -inf, -1e-30f, -0.0f, 0.0f, std::numeric_limits<float>::max(),
                           std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(), -3.0f};
  std::mt19937 rng(11);
  Image im(1000, 3, 4, 0.25f);  // 3000 pixels: 11 full blocks of 256 and a partial one
  for (int k = 0; k < 60; ++k) {
    const size_t i = rng() % im.data.size();
    im.data[i] = special[rng() % (sizeof special / sizeof special[0])];
  }
  for (int nc : {3, 4}) {
    PixelScan want;
    want.pixels = im.pixel_count();
    for (size_t p = 0; p < im.pixel_count(); ++p) {
      bool n = false, pi = false, ni = false, neg = false;
      for (int c = 0; c < nc; ++c) {
        const float v = im.data[p * 4 + size_t(c)];
        n |= std::isnan(v);
        pi |= v == inf;
        ni |= v == -inf;
        neg |= std::isfinite(v) && v < 0.0f;
      }
      want.nan += n, want.pos_inf += pi, want.neg_inf += ni, want.infinite += pi || ni, want.negative += neg;
    }
    const PixelScan got = scan_pixels(im, nc);
    EXPECT_EQ(got.pixels, want.pixels);
    EXPECT_EQ(got.nan, want.nan) << nc;
    EXPECT_EQ(got.pos_inf, want.pos_inf) << nc;
    EXPECT_EQ(got.neg_inf, want.neg_inf) << nc;
    EXPECT_EQ(got.infinite, want.infinite) << nc;
    EXPECT_EQ(got.negative, want.negative) << nc;
    EXPECT_GT(want.nan + want.infinite + want.negative, 10u);
  }
}

// ---------------------------------------------------------------- metric_registry
TEST(MetricRegistry, NamesAndErrors) {
  EXPECT_EQ(metric_names(), (std::vector<std::string>{"deltaE2000", "deltaEITP", "flip", "psnr", "relative"}));
  const Image a = grey(8, 8, 0.5f);
  try {
    evaluate_metric("ssim", a, a);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("ssim"), std::string::npos);
    for (const std::string& n : metric_names()) EXPECT_NE(m.find(n), std::string::npos) << m;
  }
  try {
    evaluate_metric("psnr", a, grey(8, 9, 0.5f));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("8x8"), std::string::npos) << m;
    EXPECT_NE(m.find("8x9"), std::string::npos) << m;
  }
}

// A metrics list names per-pixel metrics and groups: no group = every group; any group = flicker and
// the named ones. Unknown and repeated names are errors that list what is allowed.
TEST(MetricRegistry, ListsSelectGroups) {
  EXPECT_EQ(metric_group_names(), (std::vector<std::string>{"flicker", "glints", "pooled"}));
  auto select = [](std::vector<std::string> list, bool glints, bool pooled, std::vector<std::string> per_pixel) {
    MetricOptions o;
    o.glints = !glints, o.pooled = !pooled;  // set either way by select_metrics
    EXPECT_EQ(select_metrics(list, o), per_pixel);
    EXPECT_EQ(o.glints, glints);
    EXPECT_EQ(o.pooled, pooled);
  };
  select({"flip", "deltaE2000"}, true, true, {"flip", "deltaE2000"});
  select({"deltaE2000", "flicker"}, false, false, {"deltaE2000"});
  select({"pooled", "psnr"}, false, true, {"psnr"});
  select({"glints", "pooled", "flicker"}, true, true, {});
  select({}, true, true, {});
  MetricOptions o;
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"ssim"}, {"glint"}}) {
    try {
      (void)select_metrics(bad, o);
      FAIL() << "no throw";
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("'" + bad[0] + "'"), std::string::npos) << m;
      for (const std::string& n : metric_names()) EXPECT_NE(m.find(n), std::string::npos) << m;
      for (const std::string& n : metric_group_names()) EXPECT_NE(m.find(n), std::string::npos) << m;
    }
  }
  EXPECT_THROW((void)select_metrics({"flip", "glints", "flip"}, o), std::invalid_argument);
}

TEST(MetricRegistry, EveryMetricGivesAOneChannelMapAndZeroOnIdentity) {
  const Image a = grey(24, 16, 0.5f, 4);
  for (const std::string& n : metric_names()) {
    const MetricResult r = evaluate_metric(n, a, a);
    EXPECT_EQ(r.name, n);
    EXPECT_FALSE(r.unit.empty());
    EXPECT_EQ(r.map.channels, 1);
    EXPECT_EQ(r.map.width, 24);
    EXPECT_EQ(r.map.height, 16);
    if (n == "psnr") {
      EXPECT_EQ(r.mean, std::numeric_limits<double>::infinity());
      EXPECT_EQ(r.max, std::numeric_limits<double>::infinity());  // worst pixel is exact too
      EXPECT_EQ(r.unit, "dB");
    } else {
      EXPECT_EQ(r.mean, 0.0) << n;
      EXPECT_EQ(r.max, 0.0) << n;
    }
  }
}

TEST(MetricRegistry, ValuesMatchTheUnderlyingMetrics) {
  Image r = grey(16, 16, 0.5f), t = r;
  set_y(t, 3, 4, 0.8f);
  const MetricResult p = evaluate_metric("psnr", t, r, MetricOptions{100, 67.0, true, 2.0});
  EXPECT_NEAR(p.mean, 10.0 * std::log10(4.0 / (0.09 / 256.0)), 1e-4);
  EXPECT_NEAR(p.max, 10.0 * std::log10(4.0 / 0.09), 1e-4);  // worst-pixel PSNR, dB
  EXPECT_NEAR(p.map.at(3, 4, 0), 0.09, 1e-6);
  const MetricResult rel = evaluate_metric("relative", t, r);
  EXPECT_NEAR(rel.max, 0.3 / 0.51, 1e-5);
  EXPECT_NEAR(rel.mean, 0.3 / 0.51 / 256.0, 1e-6);
  const MetricResult de = evaluate_metric("deltaE2000", t, r);
  const float* q = t.px(3, 4);
  const float* s = r.px(3, 4);
  EXPECT_NEAR(de.max, ciede2000(xyz_to_lab(q[0], q[1], q[2]), xyz_to_lab(s[0], s[1], s[2])), 1e-4);
  // Brighter ITP convention -> larger absolute difference for the same relative step.
  const double itp100 = evaluate_metric("deltaEITP", t, r).max;
  const double itp1000 = evaluate_metric("deltaEITP", t, r, MetricOptions{1000, 67.0, true, 1.0}).max;
  EXPECT_GT(itp100, 1.0);
  EXPECT_NE(itp100, itp1000);
  const MetricResult f = evaluate_metric("flip", t, r);
  EXPECT_GT(f.max, 0.0);
  EXPECT_LE(f.max, 1.0);
  EXPECT_EQ(f.unit, "FLIP");
}

TEST(MetricRegistry, PsnrMeanAndMaxAreBothDecibels) {
  glintlab::Image ref(4, 4, 3, 0.5f), test = ref;
  test.at(1, 2, 1) += 0.1f;  // one pixel's Y off by 0.1: MSE = 0.01 / 16
  auto r = glintlab::metrics::evaluate_metric("psnr", test, ref);
  EXPECT_NEAR(r.mean, 10.0 * std::log10(16.0 / 0.01), 1e-3);
  EXPECT_NEAR(r.max, 10.0 * std::log10(1.0 / 0.01), 1e-3);  // the worst pixel alone
  EXPECT_EQ(r.unit, "dB");
}

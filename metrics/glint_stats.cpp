#include "metrics/glint_stats.h"

#include "metrics/parallel.h"
#include "metrics/simd_clones.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "metrics/error_metrics.h"

namespace glintlab::metrics {

namespace {

void check_options(const GlintOptions& o) {
  if (!(o.k > 1.0) || !std::isfinite(o.k))
    throw std::invalid_argument("glint_stats: k must be finite and > 1, got " + std::to_string(o.k));
  if (o.window < 3 || o.window % 2 == 0)
    throw std::invalid_argument("glint_stats: window must be odd and >= 3, got " + std::to_string(o.window));
  if (o.bins < 1) throw std::invalid_argument("glint_stats: bins must be >= 1, got " + std::to_string(o.bins));
}

double clean_y(float v) { return v > 0.0f && std::isfinite(v) ? double(v) : 0.0; }

void check_comparable(const GlintStats& a, const GlintStats& b, const char* who) {
  if (a.bin_edges != b.bin_edges || a.histogram.size() != b.histogram.size())
    throw std::invalid_argument(std::string(who) + ": histograms have different bins (compute both with the same GlintOptions)");
}

}  // namespace

namespace {
// dst[x] += src[x] for x < n: one row of the summed-area table's sums down the columns.
GLINTLAB_AVX2_CLONES void add_row(double* __restrict dst, const double* __restrict src, std::size_t n) {
  for (std::size_t x = 0; x < n; ++x) dst[x] += src[x];
}
}  // namespace

Image local_mean_luminance(const Image& xyz, int window) {
  if (xyz.channels < 2) throw std::invalid_argument("local_mean_luminance: image needs the Y channel");
  if (window < 1 || window % 2 == 0)
    throw std::invalid_argument("local_mean_luminance: window must be odd and >= 1, got " + std::to_string(window));
  const int w = xyz.width, h = xyz.height, r = window / 2;
  const std::size_t stride = std::size_t(w) + 1;
  // Summed-area table with a zero row and column: S(x, y) = sum of Y over [0, x) x [0, y). Each row's
  // running sum first (the rows in parallel), then the rows added down the columns in order: every
  // S(x, y) = S(x, y - 1) + (the row's running sum at x), the additions of a single pass over both.
  NoFillVector<double> S(stride * (std::size_t(h) + 1));
  std::fill(S.begin(), S.begin() + std::ptrdiff_t(stride), 0.0);
  parallel_for(h, [&](long y) {
    double* row = S.data() + std::size_t(y + 1) * stride;
    row[0] = 0.0;
    double sum = 0.0;
    for (int x = 0; x < w; ++x) row[x + 1] = sum += clean_y(xyz.at(x, int(y), 1));
  });
  for (int y = 0; y < h; ++y)
    add_row(S.data() + std::size_t(y + 1) * stride + 1, S.data() + std::size_t(y) * stride + 1, std::size_t(w));
  Image m = Image::unfilled(w, h, 1);  // every pixel written below
  parallel_for(h, [&](long yl) {
    const int y = int(yl);
    const int y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1);
      const double sum = S[std::size_t(y1) * stride + x1] - S[std::size_t(y0) * stride + x1] -
                         S[std::size_t(y1) * stride + x0] + S[std::size_t(y0) * stride + x0];
      m.at(x, y, 0) = float(std::max(0.0, sum) / (double(x1 - x0) * (y1 - y0)));
    }
  });
  return m;
}

GlintStats glint_stats(const Image& xyz, const GlintOptions& o) {
  check_options(o);
  if (xyz.channels < 3) throw std::invalid_argument("glint_stats: image needs >= 3 channels (X, Y, Z)");
  GlintStats s;
  s.pixels = xyz.pixel_count();
  const double lo = std::log2(o.k), hi = std::log2(double(o.window) * o.window);
  const double bw = (hi - lo) / o.bins;
  for (int i = 0; i <= o.bins; ++i) s.bin_edges.push_back(std::exp2(lo + i * bw));
  s.histogram.assign(o.bins, 0.0);
  const Image m = local_mean_luminance(xyz, o.window);
  // Counts per row (the rows in parallel), added in order: integers, so the same for any thread count.
  const std::size_t bins = std::size_t(o.bins);
  std::vector<std::size_t> counts(std::size_t(xyz.height) * bins, 0);
  parallel_for(xyz.height, [&](long yl) {
    const int y = int(yl);
    std::size_t* row = counts.data() + std::size_t(y) * bins;
    for (int x = 0; x < xyz.width; ++x) {
      const double Y = clean_y(xyz.at(x, y, 1)), mean = m.at(x, y, 0);
      if (!(mean > 0.0) || !(Y > o.k * mean)) continue;
      const double t = (std::log2(Y / mean) - lo) / bw;  // > 0 since Y / mean > k
      ++row[std::size_t(std::min(o.bins - 1, int(std::min(t, double(o.bins)))))];
    }
  });
  for (std::size_t i = 0; i < counts.size(); ++i) s.glints += counts[i];
  for (int y = 0; y < xyz.height; ++y)
    for (std::size_t b = 0; b < bins; ++b) s.histogram[b] += double(counts[std::size_t(y) * bins + b]);
  if (s.glints)
    for (double& v : s.histogram) v /= double(s.glints);
  s.density_per_1000px = s.pixels ? 1000.0 * double(s.glints) / double(s.pixels) : 0.0;
  return s;
}

double glint_histogram_emd_octaves(const GlintStats& t, const GlintStats& r) {
  check_comparable(t, r, "glint_histogram_emd_octaves");
  if (t.glints == 0 && r.glints == 0) return 0.0;
  if (t.glints == 0 || r.glints == 0) return std::numeric_limits<double>::infinity();
  const std::size_t n = t.histogram.size();
  const double bw = std::log2(t.bin_edges.back() / t.bin_edges.front()) / double(n);
  double ct = 0.0, cr = 0.0, d = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {  // the last CDF difference is 0
    ct += t.histogram[i];
    cr += r.histogram[i];
    d += std::abs(ct - cr);
  }
  return d * bw;
}

double glint_histogram_hellinger(const GlintStats& t, const GlintStats& r) {
  check_comparable(t, r, "glint_histogram_hellinger");
  if (t.glints == 0 && r.glints == 0) return 0.0;
  if (t.glints == 0 || r.glints == 0) return 1.0;
  double bc = 0.0;  // Bhattacharyya coefficient
  for (std::size_t i = 0; i < t.histogram.size(); ++i) bc += std::sqrt(t.histogram[i] * r.histogram[i]);
  return std::sqrt(std::max(0.0, 1.0 - bc));
}

GlintComparison compare_glints(const Image& test_xyz, const Image& ref_xyz, const GlintOptions& o) {
  require_same_size(test_xyz, ref_xyz, "compare_glints");
  GlintComparison c;
  c.test = glint_stats(test_xyz, o);
  c.ref = glint_stats(ref_xyz, o);
  c.density_difference_per_1000px = c.test.density_per_1000px - c.ref.density_per_1000px;
  c.emd_octaves = glint_histogram_emd_octaves(c.test, c.ref);
  c.hellinger = glint_histogram_hellinger(c.test, c.ref);
  return c;
}

}  // namespace glintlab::metrics

#include "metrics/pooled_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "metrics/error_metrics.h"

namespace glintlab::metrics {

namespace {
double safe_ratio(double num, double den) {
  if (den > 0.0) return num / den;
  if (num == 0.0) return 0.0;
  return std::isnan(num) ? num : std::numeric_limits<double>::infinity();
}
}  // namespace

const std::vector<int>& default_pool_block_sizes() {
  static const std::vector<int> s = {2, 4, 8, 16, 32, 64};
  return s;
}

namespace {

// Sums of one channel over the full s x s blocks (bx x by of them, row-major).
struct BlockSums {
  int s = 0, bx = 0, by = 0;
  std::vector<double> test, ref;
};

BlockSums sums_from_pixels(const Image& test, const Image& ref, int channel, int s) {
  BlockSums b{s, test.width / s, test.height / s, {}, {}};
  b.test.assign(size_t(b.bx) * size_t(b.by), 0.0);
  b.ref.assign(b.test.size(), 0.0);
  for (int y = 0; y < b.by * s; ++y)
    for (int x = 0; x < b.bx * s; ++x) {
      const size_t k = size_t(y / s) * size_t(b.bx) + size_t(x / s);
      b.test[k] += test.at(x, y, channel);
      b.ref[k] += ref.at(x, y, channel);
    }
  return b;
}

// The 2s blocks from the s ones: each the sum of its four quarters.
BlockSums doubled(const BlockSums& f) {
  BlockSums b{2 * f.s, f.bx / 2, f.by / 2, {}, {}};
  b.test.resize(size_t(b.bx) * size_t(b.by));
  b.ref.resize(b.test.size());
  for (int j = 0; j < b.by; ++j)
    for (int i = 0; i < b.bx; ++i) {
      const size_t a = size_t(2 * j) * size_t(f.bx) + size_t(2 * i), c = a + size_t(f.bx);
      const size_t k = size_t(j) * size_t(b.bx) + size_t(i);
      b.test[k] = (f.test[a] + f.test[a + 1]) + (f.test[c] + f.test[c + 1]);
      b.ref[k] = (f.ref[a] + f.ref[a + 1]) + (f.ref[c] + f.ref[c + 1]);
    }
  return b;
}

}  // namespace

std::vector<PooledErrorScale> pooled_error(const Image& test, const Image& ref, int channel,
                                           const std::vector<int>& block_sizes) {
  require_same_size(test, ref, "pooled_error");
  if (channel < 0 || channel >= test.channels || channel >= ref.channels)
    throw std::invalid_argument("pooled_error: channel " + std::to_string(channel) + " out of range [0, " +
                                std::to_string(std::min(test.channels, ref.channels) - 1) + "]");
  std::vector<PooledErrorScale> out;
  // One pass over the pixels for the first size; a size twice the one before is summed from its
  // blocks (the same sums, added in another order: equal to rounding), any other from the pixels.
  BlockSums sums;
  for (int s : block_sizes) {
    if (s < 1) throw std::invalid_argument("pooled_error: block size must be >= 1, got " + std::to_string(s));
    const int bx = test.width / s, by = test.height / s;
    if (bx == 0 || by == 0) continue;  // block larger than the image
    sums = sums.s > 0 && s == 2 * sums.s ? doubled(sums) : sums_from_pixels(test, ref, channel, s);
    double sum_d = 0.0, sum_d2 = 0.0, sum_r = 0.0;
    const double inv_area = 1.0 / (double(s) * s);
    for (size_t k = 0; k < sums.test.size(); ++k) {
      const double st = sums.test[k], sr = sums.ref[k];
      const double d = (st - sr) * inv_area;
      sum_d += d;
      sum_d2 += d * d;
      sum_r += sr * inv_area;
    }
    const double nb = double(bx) * by;
    PooledErrorScale p;
    p.block_size = s;
    p.blocks_x = bx;
    p.blocks_y = by;
    p.bias = sum_d / nb;
    p.rms = std::sqrt(sum_d2 / nb);
    p.ref_mean = sum_r / nb;
    p.relative_bias = safe_ratio(p.bias, p.ref_mean);
    p.relative_rms = safe_ratio(p.rms, p.ref_mean);
    out.push_back(p);
  }
  return out;
}

}  // namespace glintlab::metrics

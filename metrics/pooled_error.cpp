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

std::vector<PooledErrorScale> pooled_error(const Image& test, const Image& ref, int channel,
                                           const std::vector<int>& block_sizes) {
  require_same_size(test, ref, "pooled_error");
  if (channel < 0 || channel >= test.channels || channel >= ref.channels)
    throw std::invalid_argument("pooled_error: channel " + std::to_string(channel) + " out of range [0, " +
                                std::to_string(std::min(test.channels, ref.channels) - 1) + "]");
  std::vector<PooledErrorScale> out;
  for (int s : block_sizes) {
    if (s < 1) throw std::invalid_argument("pooled_error: block size must be >= 1, got " + std::to_string(s));
    const int bx = test.width / s, by = test.height / s;
    if (bx == 0 || by == 0) continue;  // block larger than the image
    double sum_d = 0.0, sum_d2 = 0.0, sum_r = 0.0;
    const double inv_area = 1.0 / (double(s) * s);
    for (int j = 0; j < by; ++j)
      for (int i = 0; i < bx; ++i) {
        double st = 0.0, sr = 0.0;
        for (int y = j * s; y < (j + 1) * s; ++y)
          for (int x = i * s; x < (i + 1) * s; ++x) {
            st += test.at(x, y, channel);
            sr += ref.at(x, y, channel);
          }
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

#include "metrics/flip_pooling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace glintlab::metrics {

namespace {
// First sorted value whose running sum exceeds p * total (FLIP's weighted percentile).
double weighted_percentile(const std::vector<double>& sorted, double total, double p) {
  double running = 0.0;
  for (double v : sorted) {
    running += v;
    if (running > p * total) return v;
  }
  return 0.0;  // total == 0: every error is 0
}
}  // namespace

FlipPooled flip_pooled(const Image& map) {
  FlipPooled r;
  r.pixels = map.pixel_count();
  std::vector<double> v;
  v.reserve(r.pixels);
  bool nan = false;
  for (std::size_t i = 0; i < r.pixels; ++i) {
    const float e = map.data[i * map.channels];
    nan = nan || std::isnan(e);
    v.push_back(e);
  }
  if (v.empty() || nan) {
    const double q = std::numeric_limits<double>::quiet_NaN();
    r.mean = r.weighted_median = r.weighted_quartile_1 = r.weighted_quartile_3 = r.min = r.max = q;
    return r;
  }
  double total = 0.0;
  for (double e : v) total += e;  // in pixel order, for the mean
  r.mean = total / double(v.size());
  std::sort(v.begin(), v.end());
  double sorted_total = 0.0;
  for (double e : v) sorted_total += e;  // in the order of the running sums
  r.weighted_median = weighted_percentile(v, sorted_total, 0.5);
  r.weighted_quartile_1 = weighted_percentile(v, sorted_total, 0.25);
  r.weighted_quartile_3 = weighted_percentile(v, sorted_total, 0.75);
  r.min = v.front();
  r.max = v.back();
  return r;
}

}  // namespace glintlab::metrics

#include "metrics/stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace glintlab::metrics {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

void Statistics::add(double x) {
  values_.push_back(x);
  if (std::isnan(x)) ++nan_;
  else if (std::isinf(x)) ++inf_;
}

double Statistics::mean() const {
  if (values_.empty() || nan_ > 0) return kNaN;
  double s = 0.0;
  for (double x : values_) s += x;  // +Inf + -Inf = NaN, as the rule says
  return s / double(values_.size());
}

double Statistics::max() const {
  if (values_.empty() || nan_ > 0) return kNaN;
  return *std::max_element(values_.begin(), values_.end());
}

double Statistics::min() const {
  if (values_.empty() || nan_ > 0) return kNaN;
  return *std::min_element(values_.begin(), values_.end());
}

double Statistics::percentile(double p) const {
  if (!(p > 0.0 && p <= 1.0)) throw std::invalid_argument("Statistics::percentile: p must be in (0, 1]");
  if (values_.empty() || nan_ > 0) return kNaN;
  std::vector<double> v = values_;
  return nearest_rank(v, p);
}

}  // namespace glintlab::metrics

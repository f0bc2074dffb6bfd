// The one statistics type for every aggregate glintlab reports (per-frame
// values of a metric or a timing over a run, in summary.json and the report).
// Its rules, the same for every aggregate:
//   - NaN inputs are counted (nan_count()) and make mean, p95 and max NaN: a
//     frame whose value could not be measured is a defect, and an aggregate
//     must never look clean because one was dropped.
//   - +Inf and -Inf take part as numbers: the mean is +Inf (-Inf) when one is
//     present ((+Inf) + (-Inf) gives NaN), p95 and max order them.
//   - Empty: count 0 and mean, p95, max NaN.
//   - p95 is the nearest-rank percentile: the ceil(0.95 n)-th smallest value
//     (always an observed value; for n < 20 it is the maximum).
// The mean is a plain running sum in double (per-frame values, not pixels).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace glintlab::metrics {

// The nearest-rank percentile of `values` (reordered in place): the ceil(p n)-th smallest value, p in
// (0, 1]. The caller has ruled out NaN and an empty vector.
template <typename T>
T nearest_rank(std::vector<T>& values, double p) {
  const std::size_t rank = std::max<std::size_t>(1, std::size_t(std::ceil(p * double(values.size()))));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank - 1), values.end());
  return values[rank - 1];
}

class Statistics {
 public:
  void add(double x);

  std::size_t count() const { return values_.size(); }
  std::size_t nan_count() const { return nan_; }
  std::size_t inf_count() const { return inf_; }
  double mean() const;
  double max() const;
  double min() const;
  // Nearest-rank percentile, p in (0, 1]; NaN if empty or any value is NaN.
  double percentile(double p) const;
  double p95() const { return percentile(0.95); }
  const std::vector<double>& values() const { return values_; }

 private:
  std::vector<double> values_;
  std::size_t nan_ = 0, inf_ = 0;
};

}  // namespace glintlab::metrics

#include "metrics/flicker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "metrics/delta_e_itp.h"
#include "metrics/error_metrics.h"

namespace glintlab::metrics {

double perceptual_luminance(double Y, double reference_nits) {
  if (std::isnan(Y)) return Y;
  return pq_inverse_eotf(std::max(Y, 0.0) * reference_nits);
}

double flicker_ratio(double mean_abs_dT, double mean_abs_dR) {
  if (std::isnan(mean_abs_dT) || std::isnan(mean_abs_dR)) return std::numeric_limits<double>::quiet_NaN();
  if (mean_abs_dR == 0.0) return mean_abs_dT == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
  return mean_abs_dT / mean_abs_dR;
}

FlickerTracker::FlickerTracker(double reference_nits) : nits_(reference_nits) {
  if (!(reference_nits > 0.0) || !std::isfinite(reference_nits))
    throw std::invalid_argument("FlickerTracker: reference_nits (cd/m^2 for Y = 1) must be finite and > 0, got " +
                                std::to_string(reference_nits));
}

std::optional<FlickerFrame> FlickerTracker::push(const Image& test_xyz, const Image& ref_xyz) {
  require_same_size(test_xyz, ref_xyz, "FlickerTracker::push");
  if (pushed_ > 0 && (test_xyz.width != width_ || test_xyz.height != height_))
    throw std::invalid_argument("FlickerTracker::push: frame " + std::to_string(pushed_) + " is " +
                                std::to_string(test_xyz.width) + "x" + std::to_string(test_xyz.height) +
                                " but the sequence is " + std::to_string(width_) + "x" + std::to_string(height_));
  const std::size_t n = test_xyz.pixel_count();
  std::vector<float> cur_t(n), cur_r(n);
  for (std::size_t i = 0; i < n; ++i) {
    cur_t[i] = float(perceptual_luminance(test_xyz.data[i * test_xyz.channels + 1], nits_));
    cur_r[i] = float(perceptual_luminance(ref_xyz.data[i * ref_xyz.channels + 1], nits_));
  }
  std::optional<FlickerFrame> result;
  if (pushed_ > 0) {
    double s_err = 0.0, s_t = 0.0, s_r = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double dT = double(cur_t[i]) - prev_t_[i];
      const double dR = double(cur_r[i]) - prev_r_[i];
      s_err += std::abs(dT - dR);
      s_t += std::abs(dT);
      s_r += std::abs(dR);
    }
    FlickerFrame f;
    const double inv = n ? 1.0 / double(n) : 0.0;
    f.temporal_error = s_err * inv;
    f.mean_abs_dT = s_t * inv;
    f.mean_abs_dR = s_r * inv;
    f.flicker_ratio = flicker_ratio(f.mean_abs_dT, f.mean_abs_dR);
    frames_.push_back(f);
    result = f;
  }
  width_ = test_xyz.width;
  height_ = test_xyz.height;
  prev_t_ = std::move(cur_t);
  prev_r_ = std::move(cur_r);
  ++pushed_;
  return result;
}

double FlickerTracker::mean_temporal_error() const {
  if (frames_.empty()) return std::numeric_limits<double>::quiet_NaN();
  double s = 0.0;
  for (const FlickerFrame& f : frames_) s += f.temporal_error;
  return s / double(frames_.size());
}

double FlickerTracker::mean_flicker_ratio() const {
  if (frames_.empty()) return std::numeric_limits<double>::quiet_NaN();
  double s = 0.0;
  for (const FlickerFrame& f : frames_) s += f.flicker_ratio;
  return s / double(frames_.size());
}

double FlickerTracker::ratio_of_sums() const {
  if (frames_.empty()) return std::numeric_limits<double>::quiet_NaN();
  double st = 0.0, sr = 0.0;
  for (const FlickerFrame& f : frames_) {
    st += f.mean_abs_dT;
    sr += f.mean_abs_dR;
  }
  return flicker_ratio(st, sr);
}

void FlickerTracker::reset() {
  pushed_ = 0;
  width_ = height_ = 0;
  prev_t_.clear();
  prev_r_.clear();
  frames_.clear();
}

}  // namespace glintlab::metrics

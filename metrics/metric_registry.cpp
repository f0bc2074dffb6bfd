#include "metrics/metric_registry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "metrics/ciede2000.h"
#include "metrics/delta_e_itp.h"
#include "metrics/error_metrics.h"
#include "metrics/flip.h"
#include "metrics/pooled_error.h"
#include "metrics/stats.h"

namespace glintlab::metrics {

double map_percentile(const Image& m, double p) {
  std::vector<float> v(m.data.begin(), m.data.end());
  if (v.empty() || std::any_of(v.begin(), v.end(), [](float x) { return std::isnan(x); }))
    return std::numeric_limits<double>::quiet_NaN();
  return nearest_rank(v, p);
}

// Mean (in double) and max of a 1-channel map; NaN anywhere gives NaN for both.
void map_mean_max(const Image& m, double* mean, double* max) {
  double s = 0.0, mx = -std::numeric_limits<double>::infinity();
  bool nan = false;
  for (float v : m.data) {
    if (std::isnan(v)) nan = true;
    s += v;
    if (v > mx) mx = v;
  }
  const double q = std::numeric_limits<double>::quiet_NaN();
  if (m.data.empty()) {
    *mean = q;
    *max = q;
    return;
  }
  *mean = nan ? q : s / double(m.data.size());
  *max = nan ? q : mx;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr ValueRange kNonNegative{0.0, kInf, "a finite number >= 0"};
constexpr ValueRange kUnit{0.0, 1.0, "a number in [0, 1]"};
constexpr ValueRange kAnyFinite{-kInf, kInf, "a finite number"};

struct PerPixelMetric {
  const char* name;
  ValueRange range;  // of the mean and the max over pixels
};

// One row per per-pixel metric (evaluate_metric computes each).
const PerPixelMetric kPerPixel[] = {
    {"deltaE2000", kNonNegative}, {"deltaEITP", kNonNegative}, {"flip", kUnit},
    {"psnr", kAnyFinite},  // dB: below 0 when the error exceeds the peak
    {"relative", kNonNegative},
};

}  // namespace

std::vector<std::string> metric_names() {
  std::vector<std::string> n;
  for (const PerPixelMetric& m : kPerPixel) n.emplace_back(m.name);
  return n;
}

const std::vector<FrameStatistic>& frame_statistics() {
  static const std::vector<FrameStatistic> s = {
      {"flicker_ratio", "flicker", kNonNegative},        {"temporal_error", "flicker", kNonNegative},
      {"temporal_error_mc", "flicker", kNonNegative},    {"frame_diff_ratio", "flicker", kNonNegative},
      {"flicker_contrast", "flicker", kNonNegative},     {"flicker_excess", "flicker", kNonNegative},
      {"temporal_lag", "flicker", kNonNegative},         {"flicker_excess_fixed", "flicker", kNonNegative},
      {"flicker_valid_px", "flicker", kNonNegative},     {"flicker_disoccluded_px", "flicker", kNonNegative},
      {"glint_density_test", "glints", kNonNegative},    {"glint_density_ref", "glints", kNonNegative},
      {"glint_hist_emd_oct", "glints", kNonNegative},    {"nonfinite_pixels", "pixels", kNonNegative},
      {"negative_pixels", "pixels", kNonNegative},
  };
  return s;
}

std::optional<ValueRange> value_range(const std::string& name) {
  for (const PerPixelMetric& m : kPerPixel)
    if (name == m.name || name == std::string(m.name) + "_max") return m.range;
  for (const FrameStatistic& s : frame_statistics())
    if (name == s.name) return s.range;
  if (name == "pooled_error") return kNonNegative;
  for (int b : default_pool_block_sizes()) {
    if (name == "pooled_rms_" + std::to_string(b)) return kNonNegative;
    if (name == "pooled_bias_" + std::to_string(b)) return kAnyFinite;
  }
  return std::nullopt;
}

std::vector<std::string> metric_group_names() { return {"flicker", "glints", "pooled"}; }

std::vector<std::string> select_metrics(const std::vector<std::string>& list, MetricOptions& options) {
  const std::vector<std::string> metrics = metric_names(), groups = metric_group_names();
  auto in = [](const std::vector<std::string>& v, const std::string& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  std::vector<std::string> per_pixel, named_groups;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string& m = list[i];
    if (!in(metrics, m) && !in(groups, m)) {
      std::string msg = "'" + m + "' is neither a metric nor a group of metrics; allowed:";
      for (std::size_t k = 0; k < metrics.size(); ++k) msg += (k ? ", " : " ") + metrics[k];
      msg += " (per-pixel metrics) and";
      for (std::size_t k = 0; k < groups.size(); ++k) msg += (k ? ", " : " ") + groups[k];
      throw std::invalid_argument(msg + " (groups)");
    }
    if (std::find(list.begin(), list.begin() + std::ptrdiff_t(i), m) != list.begin() + std::ptrdiff_t(i))
      throw std::invalid_argument("'" + m + "' is given twice");
    (in(metrics, m) ? per_pixel : named_groups).push_back(m);
  }
  options.glints = named_groups.empty() || in(named_groups, "glints");
  options.pooled = named_groups.empty() || in(named_groups, "pooled");
  return per_pixel;
}

MetricResult evaluate_metric(const std::string& name, const Image& test_xyz, const Image& ref_xyz,
                             const MetricOptions& opt) {
  const std::vector<std::string> names = metric_names();
  bool known = false;
  for (const std::string& n : names) known = known || n == name;
  if (!known) {
    std::string msg = "unknown metric '" + name + "'; allowed:";
    for (std::size_t i = 0; i < names.size(); ++i) msg += (i ? ", " : " ") + names[i];
    throw std::invalid_argument(msg);
  }
  require_same_size(test_xyz, ref_xyz, ("evaluate_metric(" + name + ")").c_str());

  MetricResult r;
  r.name = name;
  if (name == "deltaE2000") {
    r.unit = "ΔE00";
    r.map = ciede2000_map(test_xyz, ref_xyz);
  } else if (name == "deltaEITP") {
    r.unit = "ΔE_ITP";
    r.map = delta_e_itp_map(test_xyz, ref_xyz, opt.itp_luminance_nits);
  } else if (name == "flip") {
    r.unit = "FLIP";
    r.map = opt.flip_hdr ? hdr_flip_map(test_xyz, ref_xyz, opt.flip_ppd) : ldr_flip_map(test_xyz, ref_xyz, opt.flip_ppd);
  } else if (name == "psnr") {
    r.unit = "dB";
    r.map = squared_error_map(test_xyz, ref_xyz);
    double mse_f = 0.0, worst_sq = 0.0;
    map_mean_max(r.map, &mse_f, &worst_sq);
    r.mean = psnr_from_mse(mean_squared_error_y(test_xyz, ref_xyz), opt.psnr_peak);  // MSE in double
    // In dB like the mean: the PSNR of the worst pixel (the lowest per-pixel PSNR).
    r.max = psnr_from_mse(worst_sq, opt.psnr_peak);
    return r;
  } else {  // "relative"
    r.unit = "relative";
    r.map = relative_error_map(test_xyz, ref_xyz);
  }
  map_mean_max(r.map, &r.mean, &r.max);
  return r;
}

}  // namespace glintlab::metrics

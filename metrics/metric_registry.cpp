#include "metrics/metric_registry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "metrics/ciede2000.h"
#include "metrics/delta_e_itp.h"
#include "metrics/error_metrics.h"
#include "metrics/flip.h"

namespace glintlab::metrics {

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

std::vector<std::string> metric_names() { return {"deltaE2000", "deltaEITP", "flip", "psnr", "relative"}; }

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

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

constexpr double kNotGated = std::numeric_limits<double>::quiet_NaN();

// The metrics, in their order in FrameMetrics::names() within each group. Built on first use (a
// function's static, not a namespace-scope one: other files' static initialisers read it).
const std::vector<MetricInfo>& metrics_rows() {
  static const std::vector<MetricInfo> kMetrics = {
    // ---- per pixel (evaluate_metric); the mean and the max over pixels
    {"deltaE2000", "per-pixel", "ΔE00 (CIEDE2000)", "ΔE00", "min", false, true, 0.02, kNonNegative,
     "CIEDE2000 colour difference of each pixel against the reference, averaged over the frame. About 1 is a "
     "just-noticeable difference between flat patches side by side; lower is better."},
    {"deltaEITP", "per-pixel", "ΔE_ITP (BT.2124, Y = 1 at 100 cd/m²)", "ΔE_ITP", "min", false, true, kNotGated,
     kNonNegative,
     "ITU-R BT.2124 colour difference, built for HDR (scene Y = 1 is shown at 100 cd/m²); 1 is about one "
     "just-noticeable step. Lower is better."},
    {"flip", "per-pixel", "FLIP error in [0, 1]", "FLIP", "min", false, true, 0.02, kUnit,
     "How different the frame looks from the reference when one flips between them (HDR-FLIP, Andersson et al. "
     "2020/2021), per-pixel mean in [0, 1]; 0 = indistinguishable. Lower is better."},
    {"psnr", "per-pixel", "dB (luminance, peak 1)", "PSNR", "max", false, false, kNotGated,
     kAnyFinite,  // below 0 when the error exceeds the peak
     "Peak signal-to-noise ratio of luminance (peak 1) in dB. Higher is better; it rewards blur more than the "
     "perceptual metrics do."},
    {"relative", "per-pixel", "|Yt − Yr| / (Yr + 0.01)", "relative error", "min", false, false, kNotGated,
     kNonNegative, "Mean |Y_test − Y_ref| / (Y_ref + 0.01): luminance error relative to the reference. Lower is better."},
    // ---- flicker along the motion (metrics/flicker.h)
    {"flicker_ratio", "flicker", "ratio (mean Weber contrast of change along the motion, test / reference)",
     "flicker ratio", "one", true, false, 0.02, kNonNegative,
     "How much the frame changes between consecutive frames, along the motion, compared with how much the "
     "reference changes: 1 = as stable as the truth, above 1 = flickers more than the truth (aliasing), below 1 = "
     "changes less (blur, ghosting, history lag). Best is closest to 1; the plots rank |ln(ratio)|, so 0.5 and 2 "
     "count as equally far off."},
    {"temporal_error", "flicker", "PQ code value (mean |e_t − e_{t−1}|, e = PQ(T) − PQ(R), fixed pixel)",
     "temporal error", "min", true, true, 0.02, kNonNegative,
     "Mean |e_t − e_(t−1)| with e = PQ(test) − PQ(reference) at a fixed pixel: the part of the frame-to-frame "
     "change that the reference does not have. 0 = the error is constant over time. Lower is better."},
    {"temporal_error_mc", "flicker", "PQ code value (the same along the motion)",
     "temporal error (motion-compensated)", "min", true, true, 0.02, kNonNegative,
     "The temporal error measured along the motion instead of at a fixed pixel: the change that does not match "
     "the truth's, as an eye that follows the surface sees it. Lower is better."},
    {"frame_diff_ratio", "flicker", "ratio (mean |ΔT| / mean |ΔR| at a fixed pixel, PQ)", "frame-difference ratio",
     "one", true, false, kNotGated, kNonNegative,
     "Mean |ΔT| / mean |ΔR| between consecutive frames at a fixed pixel (PQ): like the flicker ratio but without "
     "following the motion. Best is closest to 1."},
    {"flicker_contrast", "flicker", "Weber contrast (mean |ΔT| along the motion / the test's own low-passed Y)",
     "flicker contrast", "min", true, false, 0.02, kNonNegative,
     "The test's own change along the motion as Weber contrast against its own low-passed luminance; needs no "
     "reference (what `measure` gives without one). Lower is steadier."},
    {"flicker_excess", "flicker",
     "Weber contrast (mean max(0, |ΔT| − |ΔR|) along the motion, both low-passed at σ = 2 px)", "flicker excess",
     "min", true, true, kNotGated, kNonNegative,
     "The change along the motion the test has beyond the truth's, per pixel and one-sided, both frames "
     "low-passed at the eye's resolution (σ = 2 px) first, as Weber contrast: 0 = no added flicker. “Twinkles too "
     "much”. Lower is better."},
    {"temporal_lag", "flicker",
     "Weber contrast (mean max(0, |ΔR| − |ΔT|) along the motion, both low-passed at σ = 2 px)", "temporal lag",
     "min", true, true, kNotGated, kNonNegative,
     "The truth's change along the motion that the test lacks (one-sided, low-passed as flicker excess): history "
     "lag and ghosting. “Smooth but wrong”. Lower is better."},
    {"flicker_excess_fixed", "flicker", "Weber contrast (the excess at a fixed pixel: fixed gaze)",
     "flicker excess (fixed gaze)", "min", true, true, kNotGated, kNonNegative,
     "Flicker excess at a fixed pixel instead of along the motion: what an eye that does not follow the surface "
     "sees. Screen-fixed artefacts have excess along the motion only. Lower is better."},
    {"temporal_score", "flicker",
     "ΔL* (CIE lightness; Minkowski p = 4 of the displayed error's change at a fixed pixel)", "temporal score", "min",
     true, true, 0.05, kNonNegative,
     "How much the error changes from frame to frame where the eye rests, on the image as displayed (through "
     "the OCIO view of the previews), in CIE lightness L*: |ΔL*(test) − ΔL*(truth)| per pixel, pooled with "
     "exponent 4 so that a few strong changes count more than many faint ones. Flicker and lag both raise it; "
     "it ranks the variants as ColorVideoVDP's temporal channel does (metrics/README.md). This report ranks "
     "temporal stability by it. Lower is steadier."},
    {"flicker_valid_px", "flicker", "pixels", "pixels followed", "none", true, false, kNotGated, kNonNegative,
     "Pixels whose motion was followed to the previous frame (not off-screen, not disoccluded)."},
    {"flicker_disoccluded_px", "flicker", "pixels", "disoccluded pixels", "none", true, false, kNotGated,
     kNonNegative, "Pixels left out of the temporal metrics: what they show was hidden in the previous frame."},
    // ---- glint statistics (metrics/glint_stats.h)
    {"glint_density_test", "glints", "glints per 1000 px", "glint density", "ref", false, false, kNotGated,
     kNonNegative,
     "Pixels brighter than 4× their local 15×15 mean, per 1000 pixels. Compare with the reference's density "
     "(next column): best is closest to it."},
    {"glint_density_ref", "glints", "glints per 1000 px", "glint density of the reference", "none", false, false,
     kNotGated, kNonNegative, "The same count in the reference frames."},
    {"glint_hist_emd_oct", "glints", "octaves", "glint histogram EMD", "min", false, true, kNotGated, kNonNegative,
     "Earth mover's distance between the glint-intensity histograms of test and reference, in octaves (factors "
     "of 2 of intensity). Lower is better."},
    // ---- the runner's counts of the test frame's bad pixels
    {"nonfinite_pixels", "pixels", "pixels (NaN or Inf)", "NaN/Inf pixels", "min", false, false, 0.0, kNonNegative,
     "Pixels that are NaN or infinite (a defect: should be 0)."},
    {"negative_pixels", "pixels", "pixels (finite < 0)", "negative pixels", "min", false, false, 0.0, kNonNegative,
     "Pixels with a finite negative value (a defect: should be 0)."},
    // ---- pooled error (metrics/pooled_error.h), one row per kind
    {"pooled_bias_", "pooled", "Y (block means)", "pooled bias", "none", false, false, kNotGated, kAnyFinite,
     "Mean signed difference of block means of luminance at one block size (test − reference)."},
    {"pooled_rms_", "pooled", "Y (block means)", "pooled RMS", "min", false, true, kNotGated, kNonNegative,
     "RMS difference of block means of luminance at one block size. Lower is better."},
    {"pooled_error", "pooled", "Y (RMS of 8×8-pixel block means)", "pooled error", "min", false, true, 0.05,
     kNonNegative,
     "RMS difference of 8×8-pixel block means of luminance: the error that survives spatial averaging "
     "(brightness bias, missing or extra glint energy), blind to per-pixel noise. Lower is better."},
    // ---- `measure`'s check of the motion vectors, and the reference frame's bad pixels
    {"motion_explained", "motion", "ratio (mean |ΔR| along the motion / at a fixed pixel, PQ; 0 = all explained)",
     "motion explained", "none", true, false, kNotGated, kNonNegative,
     "How much of the reference's change the vectors explain: 0 all of it, 1 no more than no motion."},
    {"motion_explained_negated", "motion", "ratio (the same with the vectors negated)", "motion explained, negated",
     "none", true, false, kNotGated, kNonNegative, "The same with the vectors negated."},
    {"motion_explained_flip_y", "motion", "ratio (the same with y flipped)", "motion explained, y flipped", "none",
     true, false, kNotGated, kNonNegative, "The same with the vectors' y flipped."},
    {"motion_explained_flip_x", "motion", "ratio (the same with x flipped)", "motion explained, x flipped", "none",
     true, false, kNotGated, kNonNegative, "The same with the vectors' x flipped."},
    {"motion_nonfinite_px", "motion", "pixels (NaN or Inf motion vectors)", "NaN/Inf vectors", "none", false, false,
     kNotGated, kNonNegative, "Pixels whose motion vector is NaN or infinite (left out of the temporal metrics)."},
    {"reference_nonfinite_px", "pixels", "pixels of the reference frame (NaN or Inf)", "reference NaN/Inf pixels",
     "min", false, false, kNotGated, kNonNegative, "NaN or infinite pixels of the reference frame (a defect)."},
    {"reference_negative_px", "pixels", "pixels of the reference frame (finite < 0)", "reference negative pixels",
     "min", false, false, kNotGated, kNonNegative, "Negative pixels of the reference frame (a defect)."},
    // ---- made from two means where the means are (summary, report, tune)
    {"glint_density_ratio", "summary", "ratio (glint density, test / reference)", "glint density ratio", "one",
     false, false, kNotGated, kNonNegative,
     "The test's mean glint density over the reference's (means over the frames): 1 keeps the truth's sparkle, "
     "below 1 erases glints, above 1 adds them. Best is closest to 1."},
  };
  return kMetrics;
}

bool is_per_frame_statistic(const MetricInfo& m) {
  const std::string g = m.group;
  return g == "flicker" || g == "glints" || (g == "pixels" && std::string(m.name).rfind("reference_", 0) != 0);
}

}  // namespace

const std::vector<MetricInfo>& metric_table() { return metrics_rows(); }

const MetricInfo* metric_info(const std::string& name) {
  for (const MetricInfo& m : metric_table())
    if (name == m.name) return &m;
  if (name.size() > 4 && name.compare(name.size() - 4, 4, "_max") == 0) {
    const MetricInfo* m = metric_info(name.substr(0, name.size() - 4));
    return m && std::string(m->group) == "per-pixel" ? m : nullptr;
  }
  for (int b : default_pool_block_sizes())
    for (const char* kind : {"pooled_bias_", "pooled_rms_"})
      if (name == kind + std::to_string(b)) return metric_info(kind);
  return nullptr;
}

std::vector<std::string> metric_names() {
  std::vector<std::string> n;
  for (const MetricInfo& m : metric_table())
    if (std::string(m.group) == "per-pixel") n.emplace_back(m.name);
  return n;
}

const std::vector<FrameStatistic>& frame_statistics() {
  static const std::vector<FrameStatistic> s = [] {
    std::vector<FrameStatistic> out;
    for (const MetricInfo& m : metric_table())
      if (is_per_frame_statistic(m)) out.push_back({m.name, m.group, m.range});
    return out;
  }();
  return s;
}

std::optional<ValueRange> value_range(const std::string& name) {
  const MetricInfo* m = metric_info(name);
  if (!m) return std::nullopt;
  const std::string g = m->group;  // not in records' metrics: measure's own check, the summary's ratios
  if (g == "motion" || g == "summary" || std::string(m->name).rfind("reference_", 0) == 0) return std::nullopt;
  return m->range;
}

bool has_noise_floor(const std::string& name) {
  const MetricInfo* m = metric_info(name);
  const bool max = name.size() > 4 && name.compare(name.size() - 4, 4, "_max") == 0;  // a maximum, not a mean
  return m && m->floor && !max;
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

// Name -> per-pixel metric, the one entry point the `compare` command and the experiment runner use.
// Inputs are relative CIE XYZ (D65, Y = 1 diffuse white), >= 3 channels, same size.
//   "deltaE2000"  ΔE00 (Sharma et al. 2005) per pixel; unit "ΔE00"; mean/max over pixels.
//   "deltaEITP"   ΔE_ITP (ITU-R BT.2124), Y = 1 -> itp_luminance_nits cd/m^2; unit "ΔE_ITP".
//   "flip"        HDR-FLIP (flip_hdr, default) or LDR-FLIP at flip_ppd px/deg; unit "FLIP" in [0, 1].
//   "psnr"        map = per-pixel squared error of Y; mean = PSNR of Y in dB with peak psnr_peak (+inf for
//                 identical images); max = PSNR of the worst pixel (the lowest per-pixel PSNR, so
//                 mean and max are both dB); unit "dB".
//   "relative"    |Y_t - Y_r| / (max(Y_r, 0) + 0.01) per pixel; unit "relative" (dimensionless).
// mean and max propagate NaN (a NaN anywhere in the map makes them NaN).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/util/image.h"
#include "metrics/flip.h"

namespace glintlab::metrics {

std::vector<std::string> metric_names();  // {"deltaE2000", "deltaEITP", "flip", "psnr", "relative"}

// What a metric's value (a frame's, or a mean over frames) may be when it is a number: finite and in
// [lo, hi]. `allowed` says it in words for messages ("a finite number >= 0").
struct ValueRange {
  double lo, hi;
  const char* allowed;
  bool contains(double x) const { return x >= lo && x <= hi; }  // false for NaN and +-inf
};

// Which value of a metric is best: "min" lower, "max" higher, "one" closest to 1 (a ratio: ranked as
// |ln ratio|), "ref" closest to the reference's own value, "none" not ranked (a count of what was
// measured, a diagnostic of the vectors).
// One row per metric: everything glintlab says about it. The schema (units), summary.json
// ("metric_info", which the report reads: label, direction, description), `check` (its default
// tolerance), `tune` (what it may minimise) and the spec (a floor target) read this table; a metric
// is its code and its row.
struct MetricInfo {
  const char* name;
  const char* group;        // "per-pixel" (evaluate_metric), "flicker", "glints", "pooled", "pixels"
                            // (FrameMetrics and the runner's counts), "motion" (measure's vector check),
                            // "summary" (a ratio of two means, made where the means are)
  const char* unit;         // one wording, as frames.csv and summary.json "units" give it
  const char* label;        // the report's name for it
  const char* direction;    // "min", "max", "one", "ref" or "none"
  bool temporal;            // a change between frames (undefined at a sequence's start)
  bool floor;               // a mean of differences from the truth: the truth's noise gives it a floor
  double check_tolerance;   // `check`'s default allowed relative worsening; NaN: not gated by default
  ValueRange range;
  const char* description;  // what it measures, for the report
};
// Every row, per-pixel metrics first, then the frame statistics in FrameMetrics::names() order. The
// pooled metrics are one row per kind ("pooled_bias_<s>", "pooled_rms_<s>", "pooled_error"): their
// block sizes are default_pool_block_sizes().
const std::vector<MetricInfo>& metric_table();
// The row of a metric as summary.json and records.jsonl name it (its "_max" and pooled_*_<s> included),
// or nullptr.
const MetricInfo* metric_info(const std::string& name);

// A statistic of a frame beside the per-pixel metrics, with its range: FrameMetrics gives the groups
// "flicker" and "glints"; "pixels" are the runner's counts of the test frame's bad pixels.
struct FrameStatistic {
  const char* name;
  const char* group;
  ValueRange range;
};
// In FrameMetrics::names() order. The group "pooled" (pooled_bias_<s>, any sign; pooled_rms_<s> and
// pooled_error, >= 0; s in default_pool_block_sizes()) is named by block size, not listed here.
const std::vector<FrameStatistic>& frame_statistics();

// The range of a value as summary.json and records.jsonl name it: a per-pixel metric or its "_max",
// a frame statistic, a pooled scale; nullopt for any other name.
std::optional<ValueRange> value_range(const std::string& name);

// Whether the truth's noise gives `name` a floor (its row's `floor`): a metric whose value is a mean
// of differences between test and truth. The truth's halves A and B, each of half its samples, differ
// by sqrt(2) x sqrt(2) = 2 times the noise of the whole truth, so the whole truth's floor is half
// their metric (noise_floor in metrics/frame_metrics.h). Ratios, densities and counts have none.
bool has_noise_floor(const std::string& name);

// The groups of frame statistics (FrameMetrics) that a metrics list may name beside the per-pixel
// metrics: "flicker" (flicker along the motion), "glints" (glint statistics), "pooled" (pooled error).
// A list that names no group measures every group, as before groups could be named; a list that names
// any measures flicker (always: the temporal metrics are what runs and `measure` are for) and the
// groups it names, so `deltaE2000,flicker` measures just those two.
std::vector<std::string> metric_group_names();  // {"flicker", "glints", "pooled"}

struct MetricOptions {
  double itp_luminance_nits = 100;
  double flip_ppd = kFlipDefaultPpd;  // FLIP v1.6 default: 67.0206 px per degree
  bool flip_hdr = true;
  double psnr_peak = 1.0;
  // Where per-pixel metrics are measured: "" = scene-referred (CIE XYZ D65 of the scene values);
  // "DISPLAY/VIEW" (e.g. "sRGB/Standard") = display-referred, as that OCIO view shows the images
  // (see metric_xyz in metrics/color/measurement_space.h).
  std::string display_view;
  // The "DISPLAY/VIEW" temporal_score is measured through (what a viewer sees; metrics/flicker.h): the run
  // sets it to the view of its previews (or display_view when that is set); "" = no temporal_score.
  std::string temporal_view = "sRGB/ACES 1.0 SDR-video";
  // The statistics groups measured besides flicker (set from the metrics list by select_metrics).
  bool glints = true;
  bool pooled = true;
};

// Splits a metrics list into its per-pixel metrics (in order) and the groups it selects (into
// `options`). Throws std::invalid_argument naming an entry that is neither a metric nor a group, or is
// given twice, with every allowed name.
std::vector<std::string> select_metrics(const std::vector<std::string>& list, MetricOptions& options);

struct MetricResult {
  std::string name;
  std::string unit;
  double mean;
  double max;
  Image map;  // 1 channel, same size as the inputs
};

// Mean (in double) and max of a 1-channel map; NaN anywhere gives NaN for both.
void map_mean_max(const Image& map, double* mean, double* max);

// The nearest-rank percentile p in (0, 1] of a 1-channel map (metrics/stats.h); NaN when the map is
// empty or holds a NaN.
double map_percentile(const Image& map, double p);

// Throws std::invalid_argument for an unknown name (the message lists the allowed names) and for
// mismatched sizes (the message states both sizes).
MetricResult evaluate_metric(const std::string& name, const Image& test_xyz, const Image& ref_xyz,
                             const MetricOptions& = {});

}  // namespace glintlab::metrics

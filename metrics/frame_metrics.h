// Every metric of one rendered frame against its reference frame: the one
// place the runner (and the benchmark) measure a frame. Inputs are
// scene-linear images in the run's working space; names are those of the
// runner's schema (experiments/runner/schema.h).
//
//   <m>, <m>_max           per-pixel metric m of the registry: mean and max over pixels
//   flicker_ratio, temporal_error, temporal_error_mc, frame_diff_ratio, flicker_contrast,
//   flicker_excess, temporal_lag, flicker_excess_fixed, temporal_score,
//   flicker_valid_px, flicker_disoccluded_px     (metrics/flicker.h; from the second frame on)
//   glint_density_test, glint_density_ref, glint_hist_emd_oct   (metrics/glint_stats.h; when
//                                                  MetricOptions::glints, the group "glints")
//   pooled_bias_<s>, pooled_rms_<s> for s = 2 ... 64, and pooled_error = pooled_rms_8
//                                                  (metrics/pooled_error.h, luminance Y; when
//                                                  MetricOptions::pooled, the group "pooled")
// A frame with NaN, Inf or negative pixels is a defect: every value above is
// NaN for it (the pixel counts are reported by the runner), so no aggregate
// can turn it into a clean-looking number.
#pragma once

#include "core/util/image.h"
#include "metrics/color/color_manager.h"
#include "metrics/ciede2000.h"
#include "metrics/delta_e_itp.h"
#include "metrics/flicker.h"
#include "metrics/flip.h"
#include "metrics/metric_registry.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace glintlab::metrics {

constexpr int kPooledErrorBlock = 8;  // pooled_error = pooled_rms at 8x8 px blocks

using NamedValues = std::vector<std::pair<std::string, double>>;

// The truth's noise floor of each metric that has one (has_noise_floor in metrics/metric_registry.h),
// from the metrics of its half B measured against its half A: half their value.
NamedValues noise_floor(const NamedValues& halves);

class FrameMetrics {
 public:
  FrameMetrics(const ColorManager& cm, std::string working_space, std::vector<std::string> per_pixel,
               MetricOptions options);

  // The reference of a frame, converted once and shared by every variant.
  struct Reference {
    // Shared, not copied: with the working space XYZ D65 and no display view, both are the frame given.
    std::shared_ptr<const Image> xyz;         // scene-referred XYZ D65
    std::shared_ptr<const Image> metric_xyz;  // what per-pixel metrics compare (display-referred when a view is set)
    std::shared_ptr<const FlickerReference> flicker;  // the flicker metric's view of it (trackers keep it)
    std::optional<HdrFlipReference> flip;   // HDR-FLIP's per-exposure state, when FLIP is measured
    std::optional<LabImage> lab;            // L*a*b* of metric_xyz, when ΔE00 is measured and shared
    std::optional<ICtCpImage> ictcp;        // ICtCp of metric_xyz, when ΔE_ITP is measured
  };
  // `shared`: more than one test will be measured against this reference. Then its L*a*b* (ΔE00's
  // side of it) is converted once here and kept; for one test ΔE00 converts it block by block beside
  // the test's (the same values, without three frame-sized planes of doubles).
  Reference prepare(const Image& ref_linear, bool shared = true) const;
  Reference prepare(std::shared_ptr<const Image> ref_linear, bool shared = true) const;  // without a copy of the frame

  // All values of `test_linear` against `ref`; feeds `flicker` (the variant's
  // tracker) with the frame's motion target. `cost_ms`, if given, receives the
  // wall time of each metric group ("convert", each per-pixel metric,
  // "flicker", "glints", "pooled").
  NamedValues measure(const Image& test_linear, const Reference& ref, const Image& motion, FlickerTracker& flicker,
                      NamedValues* cost_ms = nullptr) const;

  // The names measure() returns, in order.
  std::vector<std::string> names() const;

 private:
  // CIE XYZ D65 of an image in the working space: the image itself when the working space is XYZ (as
  // for `measure`, which converts every file once when it reads it), else `storage`, converted.
  const Image& xyz_of(const Image& img, Image& storage) const;
  // The image as temporal_score sees it (display-referred through options_.temporal_view): `metric`
  // when that is already the view's, else `storage`, converted; nullptr without a temporal view.
  const Image* temporal_display(const Image& linear, const Image& metric, Image& storage) const;
  const ColorManager& cm_;
  std::string space_;
  std::vector<std::string> per_pixel_;
  MetricOptions options_;
};

}  // namespace glintlab::metrics

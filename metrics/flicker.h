// Temporal stability (DESIGN.md "Flicker"). Frames are encoded perceptually as
//   X = PQ(max(Y, 0) * L_ref),  L_ref = 100 cd/m^2 for Y = 1 (the ΔE_ITP convention),
// i.e. the SMPTE ST 2084 code value of the pixel's absolute luminance, so that equal steps are roughly
// equally visible from dark to HDR highlights (a log or gamma encoding would over- or under-weight glints).
// With ΔX_t = X_t - X_{t-1} per pixel:
//   temporal_error_t = mean |ΔT_t - ΔR_t|
//   flicker_ratio_t  = mean |ΔT_t| / mean |ΔR_t|   (1: as stable as the truth; > 1 flickers; < 1 over-smooths)
// Ratio when the reference does not change: both means 0 -> 1; only mean|ΔR_t| == 0 -> +inf (never NaN
// unless the inputs are NaN).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "core/util/image.h"

namespace glintlab::metrics {

constexpr double kFlickerReferenceNits = 100.0;  // cd/m^2 for Y = 1

// PQ(max(Y, 0) * reference_nits): the per-pixel perceptual luminance used for flicker.
double perceptual_luminance(double Y, double reference_nits = kFlickerReferenceNits);

// mean|ΔT| / mean|ΔR| with the sentinels above.
double flicker_ratio(double mean_abs_dT, double mean_abs_dR);

struct FlickerFrame {
  double temporal_error = 0.0;  // mean |ΔT_t - ΔR_t| (PQ code values)
  double flicker_ratio = 1.0;   // mean |ΔT_t| / mean |ΔR_t|
  double mean_abs_dT = 0.0;     // mean |ΔT_t|
  double mean_abs_dR = 0.0;     // mean |ΔR_t|
};

// Feed (test, reference) XYZ frame pairs in order; every frame after the first yields a FlickerFrame.
class FlickerTracker {
 public:
  explicit FlickerTracker(double reference_nits = kFlickerReferenceNits);

  // Throws std::invalid_argument when test and reference differ in size, or the size changes.
  std::optional<FlickerFrame> push(const Image& test_xyz, const Image& ref_xyz);

  const std::vector<FlickerFrame>& frames() const { return frames_; }  // one per frame after the first
  std::size_t frames_pushed() const { return pushed_; }

  // Sequence aggregates; NaN when no frame has been measured yet (fewer than two frames pushed).
  double mean_temporal_error() const;  // mean over frames of temporal_error_t
  double mean_flicker_ratio() const;   // mean over frames of flicker_ratio_t (+inf if any frame is +inf)
  double ratio_of_sums() const;        // sum_t mean|ΔT_t| / sum_t mean|ΔR_t| (same sentinels)

  void reset();

 private:
  double nits_;
  std::size_t pushed_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<float> prev_t_, prev_r_;
  std::vector<FlickerFrame> frames_;
};

}  // namespace glintlab::metrics

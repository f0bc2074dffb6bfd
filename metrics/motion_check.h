// Do a sequence's motion vectors explain its own change? A vector convention
// is a fact to verify, not to trust: on every measured frame pair,
//   motion_explained = mean_p |P_t(p) − P_{t−1}(p − v(p))| / mean_p |P_t(p) − P_{t−1}(p)|
// with P the PQ-encoded luminance (Y = 1 at 100 cd/m², as temporal_error) of
// the reference (or of the test where there is none), the previous frame
// resampled bilinearly (edges clamped), over the pixels the vectors do not
// mask (a surface, not disoccluded, on screen), on the lattice of every second
// pixel of every second row (kMotionCheckStride). 0: the vectors explain all of
// the change; 1: no more than no motion at all; above 1: less.
// The same for the vectors' three mirror images — negated (−x, −y), y flipped
// (x, −y) and x flipped (−x, y) — over the same pixels: when a mirror image
// explains the change better than the vectors as given, the convention is
// almost surely wrong. On slow camera motion a wrong sign can still explain a
// little more than no motion (both shift a smooth image roughly the right
// amount), so comparing with the mirrors is what catches it.
#pragma once

#include "core/util/image.h"
#include "core/util/no_fill_vector.h"

#include <cstddef>
#include <string>
#include <vector>

namespace glintlab::metrics {

struct MotionExplained {
  double given = 0, negated = 0, flip_y = 0, flip_x = 0;  // ratios as above (NaN: no pixel or no change)
  std::size_t pixels = 0;                                // pixels the ratios are over
};

constexpr int kMotionCheckStride = 2;

// pq_prev, pq_now: the PQ-encoded luminance planes (w·h) of the two frames,
// as FlickerReference::pq holds them; motion: the 4-channel image of
// metrics/flicker.h (xy = v, z <= 0 no surface, w < 0 masked).
MotionExplained motion_explained(const NoFillVector<double>& pq_prev, const NoFillVector<double>& pq_now, int width,
                                 int height, const Image& motion);

// The relative margin a mirror image must win by before the vectors are
// called wrong: 2 % less unexplained change.
constexpr double kMotionMirrorMargin = 0.02;

// "" when the vectors look right, else a warning that names the likely
// mistake (sign, y axis, x axis, units or the other frame), from the means
// over the run's frames.
std::string motion_warning(const MotionExplained& mean_over_frames);

}  // namespace glintlab::metrics

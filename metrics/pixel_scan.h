// NaN / Inf / negative scan of a frame (the counts go into frames.csv: a bad pixel is counted, never averaged).
// A pixel counts at most once per category, if any of its scanned channels qualifies; one pixel can be
// in several categories (e.g. NaN in R and -Inf in G).
#pragma once

#include <cstddef>

#include "core/util/image.h"

namespace glintlab::metrics {

struct PixelScan {
  std::size_t pixels = 0;    // pixels scanned
  std::size_t nan = 0;       // any channel NaN
  std::size_t pos_inf = 0;   // any channel +Inf
  std::size_t neg_inf = 0;   // any channel -Inf
  std::size_t infinite = 0;  // any channel +Inf or -Inf
  std::size_t negative = 0;  // any channel finite and < 0 (-0.0 is not negative; -Inf is counted in neg_inf)
  bool clean() const { return nan == 0 && infinite == 0 && negative == 0; }
};

// channels: how many leading channels to scan; <= 0 or more than the image has means all channels.
PixelScan scan_pixels(const Image& image, int channels = 0);

}  // namespace glintlab::metrics

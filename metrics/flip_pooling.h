// Pooled statistics of a FLIP error map, as NVIDIA FLIP v1.6's tool prints them (its pooling rules,
// src/cpp/tool/pooling.h, read for the definitions):
//   mean             arithmetic mean of the per-pixel errors;
//   weighted median, 1st and 3rd weighted quartile
//                    percentiles of the error distribution where each pixel weighs its own error: with
//                    the errors sorted ascending, the first error e_k whose running sum e_1 + ... + e_k
//                    exceeds p times the total (p = 0.5, 0.25, 0.75); 0 when every error is 0;
//   min, max         smallest and largest error.
// glintlab sums in double (FLIP in float), so means agree with FLIP's printed 6 decimals on ordinary
// images and are closer to the exact mean on large ones.
#pragma once

#include <cstddef>

#include "core/util/image.h"

namespace glintlab::metrics {

struct FlipPooled {
  std::size_t pixels = 0;
  double mean = 0.0;
  double weighted_median = 0.0;
  double weighted_quartile_1 = 0.0;
  double weighted_quartile_3 = 0.0;
  double min = 0.0;
  double max = 0.0;
};

// Statistics of the first channel of `map`. Every field is NaN when the map is empty or holds a NaN
// (a NaN error is never pooled into a number).
FlipPooled flip_pooled(const Image& map);

}  // namespace glintlab::metrics

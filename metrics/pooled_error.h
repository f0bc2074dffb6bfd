// Error of pooled means at several scales: a stochastic estimator compared with the truth scale by scale.
// A stochastic glint estimator can realise different glints than the truth yet match it on average over
// blocks; bias and energy of block means tell the two apart.
//
// For each block size s, the image is tiled from the top-left corner into full s x s blocks (the
// W mod s right columns and H mod s bottom rows are left out; an s larger than the image is skipped).
// P_t(b), P_r(b) = mean over block b of one channel (default: Y, channel 1 of an XYZ image).
//   bias         = mean_b (P_t - P_r)
//   rms          = sqrt(mean_b (P_t - P_r)^2)        (energy error of the pooled difference)
//   ref_mean     = mean_b P_r
//   relative_bias = bias / ref_mean, relative_rms = rms / ref_mean; when ref_mean <= 0 these are 0 if
//   the numerator is 0 and +inf otherwise (never NaN from the division).
// For i.i.d. zero-mean noise of std sigma, rms ≈ sigma / s.
#pragma once

#include <vector>

#include "core/util/image.h"

namespace glintlab::metrics {

struct PooledErrorScale {
  int block_size = 0;
  int blocks_x = 0;
  int blocks_y = 0;
  double bias = 0.0;
  double rms = 0.0;
  double ref_mean = 0.0;
  double relative_bias = 0.0;
  double relative_rms = 0.0;
};

// {2, 4, 8, 16, 32, 64}
const std::vector<int>& default_pool_block_sizes();

// channel: which channel to pool (0..channels-1; 1 = Y of XYZ). Block sizes must be >= 1.
std::vector<PooledErrorScale> pooled_error(const Image& test, const Image& ref, int channel = 1,
                                           const std::vector<int>& block_sizes = default_pool_block_sizes());

}  // namespace glintlab::metrics

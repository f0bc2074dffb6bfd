// Glint statistics: how many glints, and how bright relative to their surroundings, compared between a
// test and a reference image (a stochastic estimator must match the truth in
// distribution, not per pixel).
//
// Luminance Y = channel 1 of an XYZ image; negative and NaN luminances count as 0 here (scan_pixels
// reports them). Local mean m(p) = mean of Y over the window x window box centred on p, clipped to the
// image (only in-image pixels are averaged), the pixel itself included; computed with a summed-area table.
// A pixel is a glint when Y(p) > k m(p) (defaults k = 4, window = 15 px).
// Density = glints per 1000 pixels.
// Intensity histogram: glint ratios Y/m in `bins` log2-spaced bins from k to window^2 (the largest ratio
// possible: the pixel is inside its own window), the top bin closed; as fractions of the glint count.
#pragma once

#include <cstddef>
#include <vector>

#include "core/util/image.h"

namespace glintlab::metrics {

struct GlintOptions {
  double k = 4.0;   // threshold on luminance / local mean, > 1
  int window = 15;  // odd box size in pixels, >= 3
  int bins = 12;    // histogram bins, >= 1
};

struct GlintStats {
  std::size_t pixels = 0;
  std::size_t glints = 0;
  double density_per_1000px = 0.0;
  std::vector<double> bin_edges;  // bins + 1 ratio values, log2-spaced from k to window^2
  std::vector<double> histogram;  // fraction of glints per bin (all 0 when there is no glint)
};

// Box mean of Y (clipped window), 1 channel; exposed for tests and visualisation.
Image local_mean_luminance(const Image& xyz, int window);

GlintStats glint_stats(const Image& xyz, const GlintOptions& options = {});

// Earth mover's distance (1-D Wasserstein-1) between the two normalised intensity histograms, in octaves
// of the ratio Y/m: sum_i |CDF_t(i) - CDF_r(i)| * bin width (log2). Both without glints: 0; exactly one
// without glints: +inf. Histograms must have the same edges (std::invalid_argument otherwise).
double glint_histogram_emd_octaves(const GlintStats& test, const GlintStats& ref);
// Hellinger distance sqrt(1 - sum_i sqrt(p_i q_i)) in [0, 1]. Both without glints: 0; exactly one: 1.
double glint_histogram_hellinger(const GlintStats& test, const GlintStats& ref);

struct GlintComparison {
  GlintStats test, ref;
  double density_difference_per_1000px = 0.0;  // test - ref
  double emd_octaves = 0.0;
  double hellinger = 0.0;
};
GlintComparison compare_glints(const Image& test_xyz, const Image& ref_xyz, const GlintOptions& options = {});

}  // namespace glintlab::metrics

// FLIP, the perceptual difference evaluator for alternating images:
//   LDR-FLIP: P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström, M. D. Fairchild,
//     "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM CGIT (HPG) 3(2), 2020;
//   HDR-FLIP: P. Andersson, J. Nilsson, P. Shirley, T. Akenine-Möller, "Visualizing Errors in Rendered
//     High Dynamic Range Images", Eurographics 2021 short papers (and the 2021 Ray Tracing Gems II chapter
//     "Visualizing and Communicating Errors in Rendered Images").
// Per-pixel error in [0, 1]. Inputs are relative CIE XYZ (Y = 1 diffuse white); they are converted to
// linear sRGB / Rec.709 with the inverse of the Rec.709 normalised primary matrix (SMPTE RP 177 from the
// Rec.709 primaries and the D65 white x = 0.3127, y = 0.3290; linear Rec.709 white (1, 1, 1) <-> XYZ
// (0.950456, 1, 1.089058)). The same matrix is used inside FLIP for linear RGB <-> XYZ, and its white
// is FLIP's reference illuminant for YCxCz and L*a*b*.
// Borders are replicated (as the reference implementation). Separable convolutions throughout.
#pragma once

#include "core/util/image.h"

namespace glintlab::metrics {

// 0.7 m from a 0.7 m wide, 3840 px wide monitor: 3840 / 0.7 * 0.7 * pi / 180 = 67.02 px per degree.
constexpr double kFlipDefaultPpd = 67.0;

// Pixels per degree of visual angle, FLIP 2020 sec. 3: d * (r / w) * pi / 180.
double flip_pixels_per_degree(double distance_m, double monitor_width_m, double monitor_width_px);

// ACES filmic fit (Narkowicz 2016) with FLIP's 0.6 pre-exposure folded in, clamped to [0, 1]:
// (0.6^2 2.51 x^2 + 0.6 0.03 x) / (0.6^2 2.43 x^2 + 0.6 0.59 x + 0.14). Negative x -> 0, +inf -> 1.
double flip_aces_tonemap(double x);

// HDR-FLIP exposure range (Andersson et al. 2021 sec. 3): x_max solves tonemap(x) = 0.85;
// c_start = log2(x_max / Y_max), c_stop = log2(x_max / Y_median) over the reference luminance (from
// linear sRGB with negatives clamped to 0; non-finite pixels skipped); count = max(2, ceil(c_stop - c_start)).
// Y_max == 0 gives c_start = c_stop = 0. glintlab addition: when Y_median == 0 (more than half the reference
// is black) the median of the positive luminances is used instead of producing c_stop = +inf.
struct HdrFlipExposures {
  double start = 0.0;
  double stop = 0.0;
  int count = 2;
};
HdrFlipExposures hdr_flip_exposures(const Image& ref_xyz);

// Relative CIE XYZ -> linear sRGB / Rec.709 (3 channels, no clamping).
Image xyz_to_linear_srgb(const Image& xyz);

// LDR-FLIP between two images given in linear sRGB (first three channels; clamped to [0, 1] first).
Image ldr_flip_map_linear_srgb(const Image& test_rgb, const Image& ref_rgb, double ppd = kFlipDefaultPpd);
// LDR-FLIP between two relative XYZ images (linear sRGB clamped to [0, 1]; values above white clip).
Image ldr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd = kFlipDefaultPpd);
// HDR-FLIP: per-pixel maximum of LDR-FLIP over the exposures of hdr_flip_exposures(ref), each image
// exposure-scaled by 2^c and tone mapped per channel with flip_aces_tonemap.
Image hdr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd = kFlipDefaultPpd);

}  // namespace glintlab::metrics

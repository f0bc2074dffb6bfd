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
// Defaults, exposure range and tone mappers follow NVIDIA FLIP v1.6's C++ code (github.com/NVlabs/flip,
// read for the facts, not copied); on the images of tests/data/flip/ the error maps' pooled values agree
// with its tool within 1.1e-5 (tests/metrics/flip.cpp, FlipReference). Pooled statistics: flip_pooling.h.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/util/image.h"
#include "core/util/named_enum.h"

namespace glintlab::metrics {

// FLIP's default observer (FLIP 2020 sec. 3, and NVIDIA FLIP v1.6's FLIP::Parameters): 0.7 m from a
// 0.7 m wide monitor that is 3840 px wide.
// Limits where a number becomes a size or a count: a kernel radius grows with the pixels per degree
// (about 3 px per 1 ppd), the work with the number of HDR exposures. Beyond them is bad input.
inline constexpr double kFlipMaxPpd = 1000.0;
inline constexpr int kFlipMaxExposures = 256;
inline constexpr double kFlipDefaultMonitorDistance = 0.7;     // m
inline constexpr double kFlipDefaultMonitorWidth = 0.7;        // m
inline constexpr double kFlipDefaultMonitorWidthPixels = 3840;  // px

// Pixels per degree of visual angle, FLIP 2020 sec. 3 (FLIP's calculatePPD): d * (r / w) * pi / 180,
// d = distance to the monitor, w its width (same unit as d), r its width in pixels. (FLIP's
// small-angle formula, kept as FLIP has it so that settings carry over.)
constexpr double flip_pixels_per_degree(double distance_m, double monitor_width_m, double monitor_width_px) {
  return distance_m * (monitor_width_px / monitor_width_m) * 3.14159265358979323846 / 180.0;
}

// FLIP's default: 3840 pi / 180 = 67.0206 px per degree.
inline constexpr double kFlipDefaultPpd =
    flip_pixels_per_degree(kFlipDefaultMonitorDistance, kFlipDefaultMonitorWidth, kFlipDefaultMonitorWidthPixels);

// HDR-FLIP tone mappers (FLIP's --tone-mapper). Before tone mapping, negative channel values are
// taken as 0 (glintlab's rule: FLIP's rational fits map large negative values to bright colours),
// and every result is clamped to [0, 1] as in FLIP.
//   aces      Narkowicz 2016 ACES fit with FLIP's 0.6 pre-exposure folded in, per channel:
//             (0.6^2 2.51 x^2 + 0.6 0.03 x) / (0.6^2 2.43 x^2 + 0.6 0.59 x + 0.14)   (FLIP's default)
//   hable     Hable's filmic curve as FLIP's rational fit, per channel:
//             (0.231683 x^2 + 0.013791 x) / (0.18 x^2 + 0.3 x + 0.018)
//   reinhard  Reinhard on luminance: rgb / (1 + L), L = 0.2126 r + 0.7152 g + 0.0722 b
enum class FlipToneMapper { Aces, Hable, Reinhard };
inline constexpr EnumTable<FlipToneMapper, 3> kFlipToneMapperNames{
    {{FlipToneMapper::Aces, "aces"}, {FlipToneMapper::Hable, "hable"}, {FlipToneMapper::Reinhard, "reinhard"}}};

// ACES as above for one value: negative x -> 0, +inf -> 1, NaN stays NaN.
double flip_aces_tonemap(double x);
// Tone maps one linear sRGB colour in place with `tm` (as above; NaN stays NaN).
void flip_tonemap(FlipToneMapper tm, double rgb[3]);

// HDR-FLIP exposure range (Andersson et al. 2021 sec. 3, as NVIDIA FLIP v1.6 computes it):
// x_max is the larger root of tonemap(x) = 0.85 (for Reinhard, x / (1 + x) = 0.85);
// start = log2(x_max / Y_max), stop = log2(x_max / Y_median), count = max(2, ceil(stop - start)), where
// Y = 0.2126 R + 0.7152 G + 0.0722 B of the reference in linear sRGB (not clamped; non-finite pixels
// skipped) and Y_median is FLIP's median: the element n/2 (0-based) of the n sorted luminances (the
// upper of the two middle ones when n is even). A range within 1e-5 stop above an integer counts as
// that integer (rounding in the inputs otherwise decides between n and n + 1 exposures).
// Where FLIP's result is not a number, glintlab has its own rule (FLIP v1.6 itself prints an infinite
// stop exposure and, for Y_median = 0, returns an all-zero error map):
//   - Y_max <= 0 (a black reference): start = stop = 0;
//   - Y_median <= 0 (half the reference or more is black): Y_median is the same median of the
//     positive luminances, so that stop stays finite.
struct HdrFlipExposures {
  double start = 0.0;
  double stop = 0.0;
  int count = 2;
};
HdrFlipExposures hdr_flip_exposures(const Image& ref_xyz, FlipToneMapper tm = FlipToneMapper::Aces);

// HDR-FLIP settings, as FLIP's --tone-mapper, --start-exposure, --stop-exposure, --num-exposures.
// A NaN exposure or a count of 0 is computed from the reference (hdr_flip_exposures); a count given
// without both exposures still takes the missing ones from the reference, as in FLIP.
struct HdrFlipOptions {
  FlipToneMapper tone_mapper = FlipToneMapper::Aces;
  double start_exposure = NAN;
  double stop_exposure = NAN;
  int num_exposures = 0;  // 0 = max(2, ceil(stop - start)); 1 = the start exposure alone
};

// The exposures HDR-FLIP will use for `ref_xyz` with `options`. Throws std::invalid_argument when a
// given exposure is not finite, the count is negative, or start > stop (the message names which
// came from the reference).
HdrFlipExposures resolve_hdr_flip_exposures(const Image& ref_xyz, const HdrFlipOptions& options);

// Relative CIE XYZ -> linear sRGB / Rec.709 (3 channels, no clamping).
Image xyz_to_linear_srgb(const Image& xyz);

// LDR-FLIP between two images given in linear sRGB (first three channels; clamped to [0, 1] first).
Image ldr_flip_map_linear_srgb(const Image& test_rgb, const Image& ref_rgb, double ppd = kFlipDefaultPpd);
// LDR-FLIP between two relative XYZ images (linear sRGB clamped to [0, 1]; values above white clip).
Image ldr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd = kFlipDefaultPpd);
// HDR-FLIP: per-pixel maximum of LDR-FLIP over `count` exposures c_i = start + i (stop - start) /
// (count - 1) (exposures of resolve_hdr_flip_exposures(ref, options)), each image scaled by 2^c_i and
// tone mapped with options.tone_mapper. `used`, if given, receives the exposures.
Image hdr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd, const HdrFlipOptions& options,
                   HdrFlipExposures* used = nullptr);
// HDR-FLIP against one reference, for many test images: the reference's
// per-exposure state (tone mapped, filtered, features) is computed once, so
// each test costs half of hdr_flip_map. map(test) equals hdr_flip_map(test,
// ref, ppd, options) exactly. Copies share the state.
class HdrFlipReference {
 public:
  HdrFlipReference(const Image& ref_xyz, double ppd = kFlipDefaultPpd, const HdrFlipOptions& options = {});
  Image map(const Image& test_xyz) const;
  const HdrFlipExposures& exposures() const { return exposures_; }

 private:
  struct State;
  std::shared_ptr<const State> state_;
  HdrFlipExposures exposures_;
  int width_ = 0, height_ = 0;
};

// HDR-FLIP with FLIP's defaults (ACES, exposures from the reference).
Image hdr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd = kFlipDefaultPpd);

}  // namespace glintlab::metrics

// Temporal stability (flicker) of a test sequence against its reference, along
// the motion.
//
// Flicker is change along the motion that the truth does not have, seen as
// contrast. With the renderer's exact motion vectors v_t (not estimated
// optical flow) and a disocclusion mask, in linear luminance Y:
//   ΔX_t(p) = X_t(p) - X_{t-1}(p - v_t(p))      (previous frame resampled bilinearly at the
//                                                reprojected position: the warping error of
//                                                Lai et al. 2018, "Learning Blind Video Temporal
//                                                Consistency", with exact vectors)
//   c_t(p)  = |ΔX_t(p)| / (Y_a(p) + ε)          (Weber contrast against the local adaptation
//                                                luminance: Y_a = the *reference* frame's
//                                                luminance low-passed by a Gaussian of
//                                                σ = 2 px, about the eye's resolution at the
//                                                default viewing distance; ε = 0.01, 1 % of
//                                                diffuse white, keeps black regions finite)
//   flicker_ratio_t = mean c_t(T) / mean c_t(R) over unmasked pixels
//                     (1: as stable as the truth; > 1 flickers; < 1 over-smooths)
// Contrast against a low-passed adaptation level is how perceptual metrics
// treat a small bright feature: the eye integrates it over its receptive field
// before its response compresses (a per-pixel compressive code such as PQ
// before differencing flattens exactly the sub-pixel pops that flicker, and
// mis-ranks one sample per pixel against 2x2 supersampling on glinting sand).
//
// Masked (left out of every along-the-motion mean, and counted):
//   background: no surface at p in frame t (the sky);
//   disoccluded: p - v_t lies outside the image, the point was behind the
//     previous camera, one of the bilinear taps at p - v_t saw no surface, or
//     the previous frame's *inverse* distance interpolated there differs from
//     the point's own in frame t-1 by more than 5 % (relative). The inverse
//     distance of a plane is nearly affine on the screen (exactly so for
//     depth), so on one surface its interpolation is the point's at any angle
//     of view, however fast the distance grows toward a horizon; where another
//     surface was in front, or taps straddle a silhouette, it misses by the
//     other surface's weight times the jump (the sample would mix in that
//     surface).
// Also reported:
//   temporal_error    = mean |e_t - e_{t-1}| per pixel (all pixels, no motion), e = PQ(Y_T) - PQ(Y_R)
//                       in PQ code values (Y = 1 at 100 cd/m^2): the error's change at a fixed pixel
//   temporal_error_mc = the same along the motion (unmasked pixels): mean |e_t(p) - e_{t-1}(p - v)|
//   frame_diff_ratio  = mean |ΔT| / mean |ΔR| at a fixed pixel in PQ (a ratio at a fixed pixel:
//                       content moving across pixels counts as change; a diagnostic)
// One-sided, at the eye's resolution (what a viewer agreed with; the ratio above is kept as a
// diagnostic). The ratio differences full-resolution frames, and bilinear resampling of the previous
// frame blurs a sub-pixel feature, so a sparkle moving exactly with the surface "changes" (a ratio of
// 2.4 for perfectly coherent sparkles). Here both frames are first low-passed by the adaptation's
// Gaussian (σ = 2 px, the spatial channel perceptual metrics apply anyway): X̃ = G_σ * Y, and
//   ΔX̃_t(p) = X̃_t(p) − X̃_{t−1}(p − v)       (bilinear; the blurred plane is band-limited, so the
//                                              interpolation error of a coherent feature is small:
//                                              tests/metrics/temporal.cpp states its bound)
//   flicker_excess_t = mean_p max(0, |ΔT̃| − |ΔR̃|) / (Y_a(p) + ε)   change the test has beyond the
//                                              truth's (>= 0; 0 = no added flicker)
//   temporal_lag_t   = mean_p max(0, |ΔR̃| − |ΔT̃|) / (Y_a(p) + ε)   the truth's change the test lacks
//                                              (>= 0; TAA's lag and ghosting)
// over the unmasked pixels, so "twinkles too much" and "smooth but wrong" read apart; a method whose
// changes are as large as the truth's but elsewhere has both. Gaze: the above assume the eye tracks
// the surface; the fixed-gaze counterpart
//   flicker_excess_fixed_t = mean over every pixel of max(0, |T̃_t(p) − T̃_{t−1}(p)| − |R̃_t(p) − R̃_{t−1}(p)|)
//                            / (Y_a(p) + ε)
// tells screen-fixed artefacts (a dot stuck on the screen flickers for a tracking eye, not for a
// fixed one) from twinkling ones (excess in both).
//   flicker_contrast  = mean |ΔT_t(p)| / (Y_a,T(p) + ε) over unmasked pixels: the test's own flicker,
//                       its change along the motion as Weber contrast against its *own* low-passed
//                       luminance (the same σ and ε), needing no reference: what a CI job gates on
//                       when it has only last night's value of its renderer's output
//
// What a viewer's eye sees change, as ColorVideoVDP (a fixed-gaze model) ranks it
// (metrics/README.md, "Does it rank what a viewer sees?", has the evidence): on the *displayed* image
// (display-referred through an OCIO view, white Y = 1; where the view clips a glint, it compares as
// clipped), in CIE 1976 lightness L* = 116 f(Y) − 16 (a perceptually uniform scale: a change of 1 is about
// as visible in the shadows as in the highlights), at a fixed pixel and at full resolution,
//   c_t(p) = |(L*T_t(p) − L*T_{t−1}(p)) − (L*R_t(p) − L*R_{t−1}(p))|   (the error's change)
//   temporal_score_t = (mean_p c_t(p)^4)^(1/4)   (Minkowski pooling: a few strong changes count more
//                                                 than many faint ones)
// over every pixel, in L* units: 0 = the error does not change (a truth against itself, or a constant
// error); lower = steadier. It counts what a steady gaze sees change, flicker and lag alike (a history
// that lags behind moving texture changes where the truth does not); flicker_excess and temporal_lag
// tell the two apart along the motion.
//
// Motion input: RGBA per pixel as the renderer's surface pass writes it
// (shaders/common/motion.glsl): xy = v_t in pixels (p_t - p_{t-1}), z = the
// surface's distance to the eye in frame t (0 = no surface), w = its distance
// in frame t-1 (< 0: behind the previous camera).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "core/util/image.h"
#include "core/util/no_fill_vector.h"

namespace glintlab::metrics {

constexpr double kFlickerReferenceNits = 100.0;  // cd/m^2 for Y = 1 (PQ encodings)
constexpr double kAdaptationSigmaPx = 2.0;
constexpr double kContrastEpsilon = 0.01;
constexpr double kDisocclusionTolerance = 0.05;  // interpolated inverse distance vs the point's
constexpr double kTemporalScorePower = 4.0;      // temporal_score's Minkowski exponent

// PQ(max(Y, 0) * reference_nits): the perceptual luminance of temporal_error.
double perceptual_luminance(double Y, double reference_nits = kFlickerReferenceNits);
// The same for n values (NaN stays NaN; the scalar function is this with n = 1). In-place allowed.
void perceptual_luminance_n(const double* Y, double* out, std::size_t n,
                            double reference_nits = kFlickerReferenceNits);

// a / b with the sentinels of a ratio of non-negative means: 0/0 -> 1 (both
// still: as stable as the truth), x/0 -> +inf, NaN in -> NaN.
double flicker_ratio(double mean_test, double mean_ref);

struct FlickerFrame {
  double flicker_ratio = 1.0;        // mean c(T) / mean c(R)
  double mean_contrast_test = 0.0;   // mean c_t(T) over unmasked pixels
  double mean_contrast_ref = 0.0;    // mean c_t(R)
  double temporal_error = 0.0;       // mean |e_t - e_{t-1}|, all pixels, PQ
  double temporal_error_mc = 0.0;    // along the motion, unmasked pixels, PQ
  double frame_diff_ratio = 1.0;     // mean|ΔT| / mean|ΔR| at fixed pixels, PQ
  double flicker_contrast = 0.0;     // mean |ΔT| / (Y_a,T + ε): the test's own, no reference
  double flicker_excess = 0.0;       // mean max(0, |ΔT̃| − |ΔR̃|) / (Y_a + ε), along the motion
  double temporal_lag = 0.0;         // mean max(0, |ΔR̃| − |ΔT̃|) / (Y_a + ε), along the motion
  double flicker_excess_fixed = 0.0; // the excess at a fixed pixel (fixed gaze), every pixel
  double temporal_score = 0.0;       // the displayed error's change, Minkowski-pooled (NaN: no display planes)
  std::size_t valid_px = 0;          // pixels in the along-the-motion means
  std::size_t disoccluded_px = 0;    // masked: hidden or off-screen in frame t-1
  std::size_t background_px = 0;     // masked: no surface
};

// The Gaussian low-pass of the luminance (channel 1 of XYZ) with σ in pixels,
// truncated at 3σ, edges clamped: the adaptation luminance Y_a.
NoFillVector<float> adaptation_luminance(const Image& xyz, double sigma_px = kAdaptationSigmaPx);

// Where each pixel of frame t was in frame t-1 (the renderer's motion image of
// frame t and the distances of frame t-1's motion image): either masked, or
// the four bilinear taps into the previous frame and their weights.
struct Reprojected {
  enum State : unsigned char { kValid, kBackground, kDisoccluded };
  State state = kDisoccluded;
  unsigned idx[4] = {0, 0, 0, 0};  // pixel indices into frame t-1
  float weight[4] = {0, 0, 0, 0};
  // The bilinear value of a per-pixel quantity of frame t-1 at this position.
  template <typename Plane>  // a vector of floats, one per pixel
  double sample(const Plane& prev) const {
    double v = 0.0;
    for (int k = 0; k < 4; ++k) v += double(weight[k]) * prev[idx[k]];
    return v;
  }
};
// prev_distance: channel 2 of frame t-1's motion image (0 = no surface).
std::vector<Reprojected> reproject(const Image& motion, const std::vector<float>& prev_distance,
                                   double tolerance = kDisocclusionTolerance);

// What the flicker metric needs of a reference frame: its luminance, PQ
// encoding and adaptation luminance, computed once per frame and shared by
// every variant measured against it.
struct FlickerReference {
  int width = 0, height = 0;
  NoFillVector<float> y, adaptation;
  NoFillVector<double> pq;
  NoFillVector<float> display_lightness;  // temporal_score's: L* of the reference as displayed (may be empty)
};
// display_xyz: the reference as displayed (display-referred XYZ, white Y = 1), for temporal_score; without
// it the frames have no temporal_score (NaN).
FlickerReference flicker_reference(const Image& ref_xyz, const Image* display_xyz = nullptr);

// Feed (test, reference, motion) frames in order; every frame after the first
// yields a FlickerFrame. Test and reference are CIE XYZ (Y = 1 diffuse white).
class FlickerTracker {
 public:
  // Throws std::invalid_argument when sizes differ, the motion image has fewer
  // than 4 channels, or the size changes between frames.
  // The tracker keeps the reference for the next frame: shared, not copied (a 1080p one is 33 MB).
  // test_display_xyz: the test as displayed (temporal_score; with the reference's display planes).
  std::optional<FlickerFrame> push(const Image& test_xyz, std::shared_ptr<const FlickerReference> ref,
                                   const Image& motion, const Image* test_display_xyz = nullptr);
  std::optional<FlickerFrame> push(const Image& test_xyz, const FlickerReference& ref, const Image& motion) {
    return push(test_xyz, std::make_shared<const FlickerReference>(ref), motion);
  }
  std::optional<FlickerFrame> push(const Image& test_xyz, const Image& ref_xyz, const Image& motion) {
    return push(test_xyz, std::make_shared<const FlickerReference>(flicker_reference(ref_xyz)), motion);
  }

  const std::vector<FlickerFrame>& frames() const { return frames_; }
  std::size_t frames_pushed() const { return pushed_; }
  // Starts a new sequence (a camera cut: the next frame has no predecessor).
  void reset();

 private:
  std::size_t pushed_ = 0;
  int width_ = 0, height_ = 0;
  NoFillVector<float> prev_yt_, prev_dist_, prev_ya_test_, prev_display_lt_;
  NoFillVector<double> prev_pqt_;
  std::shared_ptr<const FlickerReference> prev_ref_;
  std::vector<FlickerFrame> frames_;
};

}  // namespace glintlab::metrics

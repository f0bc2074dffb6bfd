// Estimated motion for image sequences that come without motion vectors: dense
// optical flow by OpenCV's DIS (Dense Inverse Search: Kroeger, Timofte, Dai &
// Van Gool 2016, "Fast Optical Flow using Dense Inverse Search", ECCV;
// cv::DISOpticalFlow of OpenCV 4.6, module video), not a flow of our own.
//
// Convention (glintlab's, the renderer's motion images, metrics/flicker.h):
// the motion of frame t against frame t-1 per pixel p of frame t is
//   v(p) = p_t - p_{t-1}  in pixels, +x right, +y down (pixel indices, the
//   top row first), so the previous frame's point of pixel p is p - v:
//   frame_{t-1}(p - v(p)) ≈ frame_t(p).
// OpenCV's calc(I0, I1, flow) gives flow on I0's grid with I0(x) ≈ I1(x + flow(x)),
// so v = -flow of calc(frame_t, frame_{t-1}): a flow on frame t's own grid,
// no resampling.
//
// Input: scene-linear luminance in one channel (FlowOptions::channel, 0 by
// default; channel 1 of a CIE XYZ image is Y) of two images of equal size.
// NaN and ±Inf pixels are read as 0 (callers that care scan frames anyway).
// DIS needs 8-bit single-channel images; both frames go through the SAME
// compressive curve, with one exposure m for the pair:
//   m      = the median of the pair's positive finite luminances together
//            (every pixel of both frames, or an even subsample of at most
//            2^18 of them; 1 where there is none)
//   x      = max(Y, 0) / m
//   code   = round(255 · min(1, ln(1 + x/toe) / ln(1 + encode_max/toe)))
// a logarithm with a linear toe: with the defaults (toe = 1/256,
// encode_max = 256) the median lands on code 128, every stop above the toe
// gets 16 codes (a 4.4 % change of luminance is one code) and x >= 256 clips
// to 255. Brightness constancy then holds along the motion wherever the
// luminance does, and contrast on the log scale is the same in shadow and
// highlight, which is what the patch matching of DIS compares.
//
// Output: a 4-channel Image laid out as the renderer's motion images are:
//   x, y = v in pixels; z = 1 (a surface, distance unknown); w = 1 (a
//   surface in frame t-1, distance unknown), or w = -1 where the
//   forward-backward check (FlowOptions::forward_backward) finds the flow
//   inconsistent (disoccluded or mismatched: FlickerTracker and reproject()
//   then mask the pixel, as behind the previous camera).
// Forward-backward consistency (Sundaram, Brox & Keutzer 2010, "Dense Point
// Trajectories by GPU-Accelerated Large Displacement Optical Flow", ECCV):
// with w_b = the flow from frame t to frame t-1 on frame t's grid
// (= -v) and w_f = the flow from frame t-1 to frame t on frame t-1's grid,
// sampled bilinearly at p + w_b(p) (= p - v), pixel p is inconsistent when
//   |w_b + w_f(p + w_b)|² > 0.01 (|w_b|² + |w_f(p + w_b)|²) + 0.5
// or when p + w_b lies outside the image (nothing to compare with: content
// that came in at an edge). The paper's second test (motion boundaries,
// |∇u|² + |∇v|² > 0.01|w|² + 0.002) is not applied. DIS smooths the flow some
// 6 px across a motion boundary (the medium preset), the same way in both
// directions, so the check finds a revealed strip only beyond that: about a
// quarter of a 6 px strip, 70 % of an 8 px one, all of a 12 px one (on the
// test's moving square).
//
// Cost: one DIS call, two with forward_backward (1920x1080 on a 2-core machine:
// medium 0.20-0.25 s, with forward_backward 0.37-0.40 s; fast 0.06 s, ultrafast
// 0.05 s; the pair's exposure and tone curve take ~15 ms of that). DIS runs on
// OpenCV's own thread pool (Debian's OpenCV: TBB, all cores by default;
// OPENCV_FOR_THREADS_NUM or cv::setNumThreads caps it). GLINTLAB_METRIC_THREADS,
// where set, is passed to cv::setNumThreads once, at the first call. The flow
// does not depend on the thread count (bit-identical for cv::setNumThreads(1)
// to (16) at 960x540 on a 2-core machine).
#pragma once

#include <cstdint>
#include <vector>

#include "core/util/image.h"

namespace glintlab::metrics {

// cv::DISOpticalFlow::PRESET_ULTRAFAST, PRESET_FAST, PRESET_MEDIUM (the same values).
enum class FlowPreset : int { kUltrafast = 0, kFast = 1, kMedium = 2 };

struct FlowOptions {
  FlowPreset preset = FlowPreset::kMedium;
  int channel = 0;                   // the luminance channel of both images
  double encode_max = 256.0;         // x = Y / m that maps to code 255 (the curve's top)
  double encode_toe = 1.0 / 256.0;   // x below which the curve is about linear
  bool forward_backward = false;     // also compute the flow t-1 -> t and mark w = -1 where inconsistent
};

// The motion of luminance_now (frame t) against luminance_prev (frame t-1), as above.
// Throws std::invalid_argument when the sizes differ, an image is empty, the channel is
// not in both, the encoding options are not finite with 0 < encode_toe < encode_max, or
// the images are smaller than DIS's pyramid needs for the preset (OpenCV 4.6 reads out of
// bounds there: medium needs >= 16 px on the short side and >= 46 on the long one, fast
// and ultrafast >= 32 and >= 91).
Image estimate_motion(const Image& luminance_prev, const Image& luminance_now, const FlowOptions& options = {});

// The building blocks, for tests and tools.
// m of the pair: the median of their positive finite values in `channel` (1 if none).
double flow_exposure(const Image& a, const Image& b, int channel);
// The 8-bit code of every pixel of `channel`, row-major, with exposure m (> 0).
std::vector<std::uint8_t> encode_for_flow(const Image& luminance, int channel, double exposure,
                                          const FlowOptions& options = {});

}  // namespace glintlab::metrics

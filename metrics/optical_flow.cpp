#include "metrics/optical_flow.h"

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#include "metrics/parallel.h"

namespace glintlab::metrics {

namespace {

std::string size_text(const Image& im) { return std::to_string(im.width) + "x" + std::to_string(im.height); }

void check_channel(const Image& im, int channel, const char* what) {
  if (channel < 0 || channel >= im.channels)
    throw std::invalid_argument(std::string("estimate_motion: channel ") + std::to_string(channel) + " is not in " +
                                what + " (" + std::to_string(im.channels) + " channels)");
}

void check_encoding(const FlowOptions& o) {
  if (!(std::isfinite(o.encode_toe) && std::isfinite(o.encode_max) && o.encode_toe > 0.0 &&
        o.encode_max > o.encode_toe))
    throw std::invalid_argument("estimate_motion: encode_toe and encode_max must be finite with 0 < encode_toe < "
                                "encode_max (got " + std::to_string(o.encode_toe) + ", " +
                                std::to_string(o.encode_max) + ")");
}

int cv_preset(FlowPreset p) {
  switch (p) {
    case FlowPreset::kUltrafast: return cv::DISOpticalFlow::PRESET_ULTRAFAST;
    case FlowPreset::kFast: return cv::DISOpticalFlow::PRESET_FAST;
    case FlowPreset::kMedium: return cv::DISOpticalFlow::PRESET_MEDIUM;
  }
  throw std::invalid_argument("estimate_motion: unknown preset " + std::to_string(int(p)));
}

// OpenCV 4.6's DISOpticalFlowImpl::calc picks the coarsest pyramid level as
//   min(int(log2(max(w, h) / (4 patch)) + 0.5), int(log2(min(w, h) / patch)))   (integer division)
// and where that is below the finest level it re-derives the levels from the width alone, which
// for a wide, short image makes levels shorter than a patch: it then reads out of bounds (a crash
// at 100x8 with every preset, at 600x20 with fast and ultrafast). Images for which it stays at or
// above the finest level are safe (checked in child processes for the three presets over sizes up to
// 120 px on the short side and 2000 on the long one).
bool dis_size_ok(int w, int h, int patch, int finest) {
  const int lo = std::min(w, h), hi = std::max(w, h);
  if (lo < patch) return false;
  const int by_hi = int(std::log(hi / (4.0 * patch)) / std::log(2.0) + 0.5);
  const int by_lo = int(std::log(double(lo / patch)) / std::log(2.0));
  return std::min(by_hi, by_lo) >= finest;
}

// GLINTLAB_METRIC_THREADS caps OpenCV's pool too (once; OpenCV's setting is process-wide).
void apply_thread_cap() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (std::getenv("GLINTLAB_METRIC_THREADS")) cv::setNumThreads(int(metric_threads()));
  });
}

inline float finite_or_zero(float v) { return std::isfinite(v) ? v : 0.0f; }

// Bilinear sample of a CV_32FC2 flow at (x, y), 0 <= x <= w-1, 0 <= y <= h-1.
cv::Vec2f sample_flow(const cv::Mat& flow, double x, double y) {
  const int w = flow.cols, h = flow.rows;
  const int x0 = std::min(int(x), w - 1), y0 = std::min(int(y), h - 1);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const float fx = float(x - x0), fy = float(y - y0);
  const cv::Vec2f* r0 = flow.ptr<cv::Vec2f>(y0);
  const cv::Vec2f* r1 = flow.ptr<cv::Vec2f>(y1);
  return (r0[x0] * (1 - fx) + r0[x1] * fx) * (1 - fy) + (r1[x0] * (1 - fx) + r1[x1] * fx) * fy;
}

}  // namespace

double flow_exposure(const Image& a, const Image& b, int channel) {
  check_channel(a, channel, "the previous image");
  check_channel(b, channel, "the current image");
  constexpr std::size_t kMaxSamples = std::size_t(1) << 18;
  const std::size_t n = a.pixel_count() + b.pixel_count();
  const std::size_t stride = std::max<std::size_t>(1, (n + kMaxSamples - 1) / kMaxSamples);
  std::vector<float> v;
  v.reserve(std::min(n, kMaxSamples));
  for (std::size_t i = 0; i < n; i += stride) {
    const float y = i < a.pixel_count() ? a.data[i * a.channels + channel]
                                        : b.data[(i - a.pixel_count()) * b.channels + channel];
    if (std::isfinite(y) && y > 0.0f) v.push_back(y);
  }
  if (v.empty()) return 1.0;
  auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  double m = *mid;
  if (v.size() % 2 == 0) m = 0.5 * (m + double(*std::max_element(v.begin(), mid)));
  return m;
}

std::vector<std::uint8_t> encode_for_flow(const Image& luminance, int channel, double exposure,
                                          const FlowOptions& options) {
  check_channel(luminance, channel, "the image");
  check_encoding(options);
  if (!(std::isfinite(exposure) && exposure > 0.0))
    throw std::invalid_argument("encode_for_flow: the exposure must be finite and > 0, got " + std::to_string(exposure));
  const double k = 1.0 / (exposure * options.encode_toe);      // Y -> x / toe
  const double scale = 255.0 / std::log1p(options.encode_max / options.encode_toe);
  const int w = luminance.width, c = luminance.channels;
  std::vector<std::uint8_t> out(luminance.pixel_count());
  parallel_for(luminance.height, [&](long y) {
    const float* row = luminance.data.data() + std::size_t(y) * w * c;
    std::uint8_t* o = out.data() + std::size_t(y) * w;
    for (int x = 0; x < w; ++x) {
      const double Y = std::max(0.0f, finite_or_zero(row[std::size_t(x) * c + channel]));
      const double code = std::min(255.0, std::log1p(Y * k) * scale);
      o[x] = std::uint8_t(code + 0.5);
    }
  });
  return out;
}

Image estimate_motion(const Image& luminance_prev, const Image& luminance_now, const FlowOptions& options) {
  if (luminance_prev.empty() || luminance_now.empty())
    throw std::invalid_argument("estimate_motion: empty image (previous " + size_text(luminance_prev) + ", current " +
                                size_text(luminance_now) + ")");
  if (!luminance_prev.same_size(luminance_now))
    throw std::invalid_argument("estimate_motion: the images differ in size (previous " + size_text(luminance_prev) +
                                ", current " + size_text(luminance_now) + ")");
  check_channel(luminance_prev, options.channel, "the previous image");
  check_channel(luminance_now, options.channel, "the current image");
  check_encoding(options);
  const int w = luminance_now.width, h = luminance_now.height;

  cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv_preset(options.preset));
  if (!dis_size_ok(w, h, dis->getPatchSize(), dis->getFinestScale())) {
    const int need_lo = dis->getPatchSize() << dis->getFinestScale();
    const int need_hi = int(std::ceil(4.0 * dis->getPatchSize() * std::pow(2.0, dis->getFinestScale() - 0.5)));
    throw std::invalid_argument("estimate_motion: " + size_text(luminance_now) +
                                " is too small for DIS optical flow with this preset (needs >= " +
                                std::to_string(need_lo) + " px on the short side and >= " + std::to_string(need_hi) +
                                " on the long side)");
  }
  apply_thread_cap();

  const double m = flow_exposure(luminance_prev, luminance_now, options.channel);
  std::vector<std::uint8_t> prev8 = encode_for_flow(luminance_prev, options.channel, m, options);
  std::vector<std::uint8_t> now8 = encode_for_flow(luminance_now, options.channel, m, options);
  const cv::Mat I_prev(h, w, CV_8UC1, prev8.data()), I_now(h, w, CV_8UC1, now8.data());

  // back: on frame t's grid, I_now(p) ≈ I_prev(p + back(p)), so v = -back.
  cv::Mat back, fwd;
  try {
    dis->calc(I_now, I_prev, back);
    if (options.forward_backward) dis->calc(I_prev, I_now, fwd);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(std::string("estimate_motion: OpenCV DIS optical flow failed: ") + e.what());
  }

  Image motion(w, h, 4, 1.0f);
  parallel_for(h, [&](long yl) {
    const int y = int(yl);
    const cv::Vec2f* b = back.ptr<cv::Vec2f>(y);
    float* out = motion.px(0, y);
    for (int x = 0; x < w; ++x, out += 4) {
      const cv::Vec2f wb = b[x];
      out[0] = -wb[0];
      out[1] = -wb[1];
      if (!options.forward_backward) continue;
      const double qx = x + double(wb[0]), qy = y + double(wb[1]);
      bool consistent = std::isfinite(qx) && std::isfinite(qy) && qx >= 0.0 && qy >= 0.0 && qx <= w - 1.0 &&
                        qy <= h - 1.0;
      if (consistent) {
        const cv::Vec2f wf = sample_flow(fwd, qx, qy);
        const double sx = double(wb[0]) + wf[0], sy = double(wb[1]) + wf[1];
        const double lhs = sx * sx + sy * sy;
        const double rhs = 0.01 * (double(wb.dot(wb)) + double(wf.dot(wf))) + 0.5;
        consistent = lhs <= rhs;
      }
      if (!consistent) out[3] = -1.0f;
    }
  });
  return motion;
}

}  // namespace glintlab::metrics

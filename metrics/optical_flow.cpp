#include "metrics/optical_flow.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/util/flow_plugin.h"
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

// OpenCV's PRESET_ULTRAFAST, PRESET_FAST, PRESET_MEDIUM (core/util/flow_plugin.h).
int cv_preset(FlowPreset p) {
  switch (p) {
    case FlowPreset::kUltrafast: return 0;
    case FlowPreset::kFast: return 1;
    case FlowPreset::kMedium: return 2;
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
    if (std::getenv("GLINTLAB_METRIC_THREADS")) flow::api().set_threads(int(metric_threads()));
  });
}

inline float finite_or_zero(float v) { return std::isfinite(v) ? v : 0.0f; }

// A flow image: 2 floats (x, y) a pixel, rows top first.
struct Flow2 {
  float x, y;
};

// Bilinear sample of a w x h flow at (x, y), 0 <= x <= w-1, 0 <= y <= h-1, in float as OpenCV's Vec2f
// arithmetic does it (component by component, the same operations in the same order).
Flow2 sample_flow(const std::vector<float>& flow, int w, int h, double x, double y) {
  const int x0 = std::min(int(x), w - 1), y0 = std::min(int(y), h - 1);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const float fx = float(x - x0), fy = float(y - y0);
  auto at = [&](int xx, int yy, int c) { return flow[(std::size_t(yy) * w + xx) * 2 + c]; };
  Flow2 r{};
  float* out[2] = {&r.x, &r.y};
  for (int c = 0; c < 2; ++c)
    *out[c] = (at(x0, y0, c) * (1 - fx) + at(x1, y0, c) * fx) * (1 - fy) + (at(x0, y1, c) * (1 - fx) + at(x1, y1, c) * fx) * fy;
  return r;
}

// a . a in float, as cv::Vec2f::dot.
float dot(Flow2 a) {
  float s = 0.0f;
  s += a.x * a.x;
  s += a.y * a.y;
  return s;
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

  const flow::Api& dis = flow::api();
  int patch = 0, finest = 0;
  dis.geometry(cv_preset(options.preset), &patch, &finest);
  if (!dis_size_ok(w, h, patch, finest)) {
    const int need_lo = patch << finest;
    const int need_hi = int(std::ceil(4.0 * patch * std::pow(2.0, finest - 0.5)));
    throw std::invalid_argument("estimate_motion: " + size_text(luminance_now) +
                                " is too small for DIS optical flow with this preset (needs >= " +
                                std::to_string(need_lo) + " px on the short side and >= " + std::to_string(need_hi) +
                                " on the long side)");
  }
  apply_thread_cap();

  const double m = flow_exposure(luminance_prev, luminance_now, options.channel);
  std::vector<std::uint8_t> prev8 = encode_for_flow(luminance_prev, options.channel, m, options);
  std::vector<std::uint8_t> now8 = encode_for_flow(luminance_now, options.channel, m, options);

  // back: on frame t's grid, I_now(p) ≈ I_prev(p + back(p)), so v = -back.
  std::vector<float> back(std::size_t(w) * h * 2), fwd(options.forward_backward ? back.size() : 0);
  dis.calc(cv_preset(options.preset), now8.data(), prev8.data(), w, h, back.data(),
          options.forward_backward ? fwd.data() : nullptr);

  Image motion(w, h, 4, 1.0f);
  parallel_for(h, [&](long yl) {
    const int y = int(yl);
    const float* b = back.data() + std::size_t(y) * w * 2;
    float* out = motion.px(0, y);
    for (int x = 0; x < w; ++x, out += 4) {
      const Flow2 wb{b[2 * x], b[2 * x + 1]};
      out[0] = -wb.x;
      out[1] = -wb.y;
      if (!options.forward_backward) continue;
      const double qx = x + double(wb.x), qy = y + double(wb.y);
      bool consistent = std::isfinite(qx) && std::isfinite(qy) && qx >= 0.0 && qy >= 0.0 && qx <= w - 1.0 &&
                        qy <= h - 1.0;
      if (consistent) {
        const Flow2 wf = sample_flow(fwd, w, h, qx, qy);
        const double sx = double(wb.x) + wf.x, sy = double(wb.y) + wf.y;
        const double lhs = sx * sx + sy * sy;
        const double rhs = 0.01 * (double(dot(wb)) + double(dot(wf))) + 0.5;
        consistent = lhs <= rhs;
      }
      if (!consistent) out[3] = -1.0f;
    }
  });
  return motion;
}

}  // namespace glintlab::metrics

#include "metrics/pixel_scan.h"

#include "metrics/simd_clones.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace glintlab::metrics {

namespace {

// The per-pixel count over pixels [begin, end).
void count_pixels(const Image& image, int nc, std::size_t begin, std::size_t end, PixelScan& s) {
  for (std::size_t i = begin; i < end; ++i) {
    const float* p = image.data.data() + i * image.channels;
    bool nan = false, pinf = false, ninf = false, neg = false;
    for (int c = 0; c < nc; ++c) {
      const float v = p[c];
      if (std::isnan(v)) nan = true;
      else if (std::isinf(v)) (v > 0 ? pinf : ninf) = true;
      else if (v < 0.0f) neg = true;
    }
    s.nan += nan;
    s.pos_inf += pinf;
    s.neg_inf += ninf;
    s.infinite += (pinf || ninf);
    s.negative += neg;
  }
}

// Whether any of v[0 .. n) is NaN, infinite or below zero (-0 is not): on the bits, +0 up to the largest
// finite float are the patterns below +Inf's 0x7f800000, and -0 is 0x80000000.
GLINTLAB_AVX2_CLONES bool any_unclean(const float* v, std::size_t n) {
  unsigned bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t u;
    std::memcpy(&u, v + i, 4);
    bad |= unsigned(u >= 0x7f800000u) & unsigned(u != 0x80000000u);
  }
  return bad != 0;
}

}  // namespace

PixelScan scan_pixels(const Image& image, int channels) {
  const int nc = (channels <= 0 || channels > image.channels) ? image.channels : channels;
  PixelScan s;
  s.pixels = image.pixel_count();
  // A block of pixels whose every value (all channels, the unscanned ones too) is finite and not below
  // zero adds nothing: one test on the bits, which vectorises. Only a block where some value fails it
  // is counted pixel by pixel.
  constexpr std::size_t kBlock = 256;
  const std::size_t stride = std::size_t(image.channels);
  for (std::size_t b = 0; b < s.pixels; b += kBlock) {
    const std::size_t end = std::min(s.pixels, b + kBlock);
    if (any_unclean(image.data.data() + b * stride, (end - b) * stride)) count_pixels(image, nc, b, end, s);
  }
  return s;
}

}  // namespace glintlab::metrics

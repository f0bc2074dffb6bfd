#include "metrics/pixel_scan.h"

#include <cmath>

namespace glintlab::metrics {

PixelScan scan_pixels(const Image& image, int channels) {
  const int nc = (channels <= 0 || channels > image.channels) ? image.channels : channels;
  PixelScan s;
  s.pixels = image.pixel_count();
  for (std::size_t i = 0; i < s.pixels; ++i) {
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
  return s;
}

}  // namespace glintlab::metrics

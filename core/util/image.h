// A CPU float image (no Vulkan, no metrics): the one currency between the renderer's readback, image
// files and every metric. Scene-linear RGBA unless a function says otherwise.
#pragma once

#include "core/util/no_fill_vector.h"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace glintlab {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 4;
  NoFillVector<float> data;  // row-major, top row first, interleaved channels

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c), data(static_cast<std::size_t>(w) * h * c, fill) {
    if (w < 0 || h < 0 || c <= 0) throw std::invalid_argument("Image: negative size or no channels");
  }

  // Every value left as the memory held it: for an image the next loop writes all of.
  static Image unfilled(int w, int h, int c) {
    if (w < 0 || h < 0 || c <= 0) throw std::invalid_argument("Image: negative size or no channels");
    Image im;
    im.width = w;
    im.height = h;
    im.channels = c;
    im.data.resize(static_cast<std::size_t>(w) * h * c);
    return im;
  }

  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * height; }
  bool empty() const { return data.empty(); }
  float* px(int x, int y) { return data.data() + (static_cast<std::size_t>(y) * width + x) * channels; }
  const float* px(int x, int y) const {
    return data.data() + (static_cast<std::size_t>(y) * width + x) * channels;
  }
  float& at(int x, int y, int c) { return px(x, y)[c]; }
  float at(int x, int y, int c) const { return px(x, y)[c]; }
  bool same_size(const Image& o) const { return width == o.width && height == o.height; }
};

}  // namespace glintlab

// glintlab's use of OpenCV (DIS optical flow, metrics/optical_flow.h) lives in a shared library of
// its own, libglintlab_flow.so (experiments/flow_plugin/), loaded as core/util/plugin.h says the
// first time a function below is called: OpenCV's modules and what they link (protobuf, LAPACK,
// TBB, X11: about 20 shared libraries) are loaded only by a measurement that estimates motion.
#pragma once

#include <cstdint>

namespace glintlab::flow {

constexpr int kApiVersion = 1;

struct Api {
  int version;
  // The patch size and finest pyramid scale of cv::DISOpticalFlow::create(preset) (0 ultrafast, 1 fast,
  // 2 medium: OpenCV's PRESET_* values).
  void (*geometry)(int preset, int* patch_size, int* finest_scale);
  // One DIS object of `preset`: back = calc(now, prev) and, where `fwd` is not null, fwd = calc(prev,
  // now); flows on their first image's grid, 2 floats (x, y) a pixel, rows top first, first(p) ≈
  // second(p + flow(p)). Both images 8-bit, w x h. std::runtime_error with OpenCV's message on failure.
  void (*calc)(int preset, const std::uint8_t* now, const std::uint8_t* prev, int w, int h, float* back, float* fwd);
  // cv::setNumThreads.
  void (*set_threads)(int n);
};

// The library's functions, loaded on first use (thread-safe). Throws IoError when it cannot be loaded.
const Api& api();

// Whether this process has loaded the library (for the tests of the paths that must not).
bool loaded();

}  // namespace glintlab::flow

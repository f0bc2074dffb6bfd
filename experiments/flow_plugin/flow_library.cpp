// libglintlab_flow.so: every call glintlab makes into OpenCV (core/util/flow_plugin.h), DIS optical
// flow for metrics/optical_flow.cpp. Only glintlab_flow_api is exported (the rest is hidden).
#include "core/util/flow_plugin.h"

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include <cstring>
#include <stdexcept>
#include <string>

namespace glintlab::flow {

namespace {

int cv_preset(int p) {
  switch (p) {
    case 0: return cv::DISOpticalFlow::PRESET_ULTRAFAST;
    case 1: return cv::DISOpticalFlow::PRESET_FAST;
    case 2: return cv::DISOpticalFlow::PRESET_MEDIUM;
  }
  throw std::invalid_argument("optical flow: unknown DIS preset " + std::to_string(p));
}

void geometry(int preset, int* patch_size, int* finest_scale) {
  cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv_preset(preset));
  *patch_size = dis->getPatchSize();
  *finest_scale = dis->getFinestScale();
}

void copy_flow(const cv::Mat& flow, int w, int h, float* out) {
  for (int y = 0; y < h; ++y) std::memcpy(out + std::size_t(y) * w * 2, flow.ptr<float>(y), std::size_t(w) * 2 * sizeof(float));
}

void calc(int preset, const std::uint8_t* now, const std::uint8_t* prev, int w, int h, float* back, float* fwd) {
  cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv_preset(preset));
  const cv::Mat I_now(h, w, CV_8UC1, const_cast<std::uint8_t*>(now));
  const cv::Mat I_prev(h, w, CV_8UC1, const_cast<std::uint8_t*>(prev));
  cv::Mat b, f;
  try {
    dis->calc(I_now, I_prev, b);
    if (fwd) dis->calc(I_prev, I_now, f);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(std::string("estimate_motion: OpenCV DIS optical flow failed: ") + e.what());
  }
  copy_flow(b, w, h, back);
  if (fwd) copy_flow(f, w, h, fwd);
}

void set_threads(int n) { cv::setNumThreads(n); }

}  // namespace

}  // namespace glintlab::flow

// The table, untyped: load_plugin (core/util/plugin.h) calls every plugin's function as const void* ().
extern "C" __attribute__((visibility("default"))) const void* glintlab_flow_api() {
  using namespace glintlab::flow;
  static const Api api{kApiVersion, &geometry, &calc, &set_threads};
  return &api;
}

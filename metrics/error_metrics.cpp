#include "metrics/error_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace glintlab::metrics {

namespace {
std::string size_str(const Image& im) {
  return std::to_string(im.width) + "x" + std::to_string(im.height) + "x" + std::to_string(im.channels);
}
}  // namespace

void require_same_size(const Image& test, const Image& ref, const char* who) {
  if (!test.same_size(ref))
    throw std::invalid_argument(std::string(who) + ": test image is " + size_str(test) +
                                " (width x height x channels) but reference is " + size_str(ref) +
                                "; they must have the same width and height");
  if (test.channels < 3 || ref.channels < 3)
    throw std::invalid_argument(std::string(who) + ": images need >= 3 channels (X, Y, Z); test is " +
                                size_str(test) + ", reference is " + size_str(ref));
}

void require_reference_size(const Image& test, int ref_width, int ref_height, const char* who) {
  if (test.width != ref_width || test.height != ref_height || test.channels < 3)
    throw std::invalid_argument(std::string(who) + ": test image is " + size_str(test) + " but the reference is " +
                                std::to_string(ref_width) + "x" + std::to_string(ref_height) +
                                " (width x height; the test needs >= 3 channels)");
}

Image luminance(const Image& xyz) {
  if (xyz.channels < 3) throw std::invalid_argument("luminance: image needs >= 3 channels (X, Y, Z)");
  Image y(xyz.width, xyz.height, 1);
  for (std::size_t i = 0; i < xyz.pixel_count(); ++i) y.data[i] = xyz.data[i * xyz.channels + 1];
  return y;
}

Image squared_error_map(const Image& test_xyz, const Image& ref_xyz) {
  require_same_size(test_xyz, ref_xyz, "squared_error_map");
  Image m(test_xyz.width, test_xyz.height, 1);
  for (std::size_t i = 0; i < m.pixel_count(); ++i) {
    const double d = double(test_xyz.data[i * test_xyz.channels + 1]) - ref_xyz.data[i * ref_xyz.channels + 1];
    m.data[i] = float(d * d);
  }
  return m;
}

double mean_squared_error_y(const Image& test_xyz, const Image& ref_xyz) {
  require_same_size(test_xyz, ref_xyz, "mean_squared_error_y");
  double s = 0.0;
  const std::size_t n = test_xyz.pixel_count();
  for (std::size_t i = 0; i < n; ++i) {
    const double d = double(test_xyz.data[i * test_xyz.channels + 1]) - ref_xyz.data[i * ref_xyz.channels + 1];
    s += d * d;
  }
  return n ? s / double(n) : 0.0;
}

double mean_absolute_error_channels(const Image& test, const Image& ref) {
  require_same_size(test, ref, "mean_absolute_error_channels");
  double s = 0.0;
  const std::size_t n = test.pixel_count();
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) s += std::abs(double(test.data[i * test.channels + c]) - ref.data[i * ref.channels + c]);
  return n ? s / (3.0 * double(n)) : 0.0;
}

double psnr_from_mse(double mse, double peak) {
  if (!(peak > 0.0)) throw std::invalid_argument("psnr: peak must be > 0, got " + std::to_string(peak));
  if (mse == 0.0) return std::numeric_limits<double>::infinity();  // identical images
  return 10.0 * std::log10(peak * peak / mse);                     // NaN mse stays NaN
}

double psnr_y(const Image& test_xyz, const Image& ref_xyz, double peak) {
  return psnr_from_mse(mean_squared_error_y(test_xyz, ref_xyz), peak);
}

Image relative_error_map(const Image& test_xyz, const Image& ref_xyz, double eps) {
  require_same_size(test_xyz, ref_xyz, "relative_error_map");
  if (!(eps > 0.0)) throw std::invalid_argument("relative_error_map: eps must be > 0");
  Image m(test_xyz.width, test_xyz.height, 1);
  for (std::size_t i = 0; i < m.pixel_count(); ++i) {
    const double yt = test_xyz.data[i * test_xyz.channels + 1];
    const double yr = ref_xyz.data[i * ref_xyz.channels + 1];
    m.data[i] = float(std::abs(yt - yr) / (std::max(yr, 0.0) + eps));
  }
  return m;
}

Image relative_error_channels_map(const Image& test, const Image& ref, double eps) {
  require_same_size(test, ref, "relative_error_channels_map");
  if (!(eps > 0.0)) throw std::invalid_argument("relative_error_channels_map: eps must be > 0");
  Image m(test.width, test.height, 1);
  for (std::size_t i = 0; i < m.pixel_count(); ++i) {
    double s = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double t = test.data[i * test.channels + c];
      const double r = ref.data[i * ref.channels + c];
      s += std::abs(t - r) / (std::max(r, 0.0) + eps);
    }
    m.data[i] = float(s / 3.0);
  }
  return m;
}

}  // namespace glintlab::metrics

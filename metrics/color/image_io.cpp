#include "metrics/color/image_io.h"

#include "core/util/atomic_file.h"
#include "core/util/io_error.h"
#include "core/util/oiio_plugin.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <vector>


namespace glintlab::metrics {

namespace fs = std::filesystem;

namespace {

void check_image(const std::string& path, const Image& img) {
  if (img.width <= 0 || img.height <= 0 || img.channels <= 0 ||
      img.data.size() != img.pixel_count() * static_cast<std::size_t>(img.channels))
    throw std::invalid_argument("cannot write '" + path + "': invalid image (" + std::to_string(img.width) + "x" +
                                std::to_string(img.height) + "x" + std::to_string(img.channels) + ", " +
                                std::to_string(img.data.size()) + " values)");
}

void write_exr_impl(const std::string& path, const Image& img, const std::array<float, 8>* chromaticities,
                    bool half, const std::vector<std::string>& names = {}) {
  check_image(path, img);
  if (!names.empty() && names.size() != std::size_t(img.channels))
    throw std::invalid_argument("'" + path + "': " + std::to_string(names.size()) + " channel names for an image of " +
                                std::to_string(img.channels) + " channels");
  const oiio::Api& api = oiio::api();
  // Atomically (core/util/atomic_file.h): on any failure the existing file at path is untouched.
  write_file_atomic(path, [&](const fs::path& tmp) {
    api.write_exr(tmp.string(), path, img, chromaticities ? chromaticities->data() : nullptr, half, names);
  });
}

}  // namespace

void check_image_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int e = errno;  // a path that names no file is bad input; any other reason is the system's
    if (e == ENOENT || e == ENOTDIR || e == ENAMETOOLONG || e == ELOOP)
      throw std::invalid_argument("cannot read image '" + path + "': " + std::strerror(e));
    throw IoError("cannot read image '" + path + "': " + std::strerror(e));
  }
  if (!S_ISREG(st.st_mode))
    throw std::invalid_argument("'" + path + "' is not a regular file (only regular files are read as images)");
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw IoError("cannot read image '" + path + "': " + std::strerror(errno));
  ::close(fd);
}

Image read_image(const std::string& path, std::string* colorspace_tag, int* file_channels) {
  check_image_file(path);
  return oiio::api().read_image(path, colorspace_tag, file_channels);
}

void write_exr(const std::string& path, const Image& img, const std::array<float, 8>& chromaticities, bool half) {
  write_exr_impl(path, img, &chromaticities, half);
}

void write_exr_data(const std::string& path, const Image& img, bool half, const std::vector<std::string>& names) {
  write_exr_impl(path, img, nullptr, half, names);
}

void write_png(const std::string& path, const Image& display_encoded) {
  const Image& img = display_encoded;
  check_image(path, img);
  if (img.channels > 4)
    throw std::invalid_argument("cannot write '" + path + "': PNG takes 1 to 4 channels, image has " +
                                std::to_string(img.channels));
  std::vector<std::uint8_t> q(img.data.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    const float v = img.data[i];
    const float c = (v > 0.0f) ? std::min(v, 1.0f) : 0.0f;  // NaN -> 0
    q[i] = static_cast<std::uint8_t>(std::lround(c * 255.0f));
  }
  const oiio::Api& api = oiio::api();
  write_file_atomic(path, [&](const fs::path& tmp) {
    api.write_png(tmp.string(), path, img.width, img.height, img.channels, q.data());
  });
}

}  // namespace glintlab::metrics

#include "metrics/color/image_io.h"

#include "core/util/atomic_file.h"
#include "core/util/io_error.h"

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


#include <OpenImageIO/imageio.h>

namespace glintlab::metrics {

namespace fs = std::filesystem;

namespace {

std::string oiio_error(const OIIO::ImageOutput* out) {
  std::string e = out ? out->geterror() : std::string();
  if (e.empty()) e = OIIO::geterror();
  return e.empty() ? std::string("unknown OpenImageIO error") : e;
}

void check_image(const std::string& path, const Image& img) {
  if (img.width <= 0 || img.height <= 0 || img.channels <= 0 ||
      img.data.size() != img.pixel_count() * static_cast<std::size_t>(img.channels))
    throw std::invalid_argument("cannot write '" + path + "': invalid image (" + std::to_string(img.width) + "x" +
                                std::to_string(img.height) + "x" + std::to_string(img.channels) + ", " +
                                std::to_string(img.data.size()) + " values)");
}

std::vector<std::string> channel_names(int channels) {
  switch (channels) {
    case 1: return {"Y"};
    case 2: return {"Y", "A"};
    case 3: return {"R", "G", "B"};
    case 4: return {"R", "G", "B", "A"};
    default: {
      std::vector<std::string> n = {"R", "G", "B", "A"};
      for (int c = 4; c < channels; ++c) n.push_back("channel" + std::to_string(c));
      return n;
    }
  }
}

// Writes through `format` atomically (core/util/atomic_file.h): on any failure the existing file at
// path is untouched.
void write_atomic(const std::string& path, const char* format, OIIO::ImageSpec spec, OIIO::TypeDesc data_type,
                  const void* data) {
  write_file_atomic(path, [&](const fs::path& tmp) {
    auto fail = [&](const std::string& why) { throw IoError("cannot write '" + path + "': " + why); };
    auto out = OIIO::ImageOutput::create(format);
    if (!out) fail(std::string("no OpenImageIO writer for ") + format + ": " + oiio_error(nullptr));
    if (!out->open(tmp.string(), spec)) fail(oiio_error(out.get()));
    if (!out->write_image(data_type, data)) {
      std::string e = oiio_error(out.get());
      out->close();
      fail(e);
    }
    if (!out->close()) fail(oiio_error(out.get()));
  });
}

void write_exr_impl(const std::string& path, const Image& img, const std::array<float, 8>* chromaticities,
                    bool half, const std::vector<std::string>& names = {}) {
  check_image(path, img);
  if (!names.empty() && names.size() != std::size_t(img.channels))
    throw std::invalid_argument("'" + path + "': " + std::to_string(names.size()) + " channel names for an image of " +
                                std::to_string(img.channels) + " channels");
  OIIO::ImageSpec spec(img.width, img.height, img.channels, half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  spec.channelnames = names.empty() ? channel_names(img.channels) : names;
  spec.alpha_channel = !names.empty() ? -1 : (img.channels == 2) ? 1 : (img.channels >= 4 ? 3 : -1);
  spec.attribute("compression", "zip");
  if (chromaticities)
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chromaticities->data());
  write_atomic(path, "exr", spec, OIIO::TypeDesc::FLOAT, img.data.data());
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
  // Values as stored: no premultiplication of unassociated (PNG, TIFF) alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    std::string e = OIIO::geterror();
    throw std::runtime_error("cannot read image '" + path + "': " + (e.empty() ? "unknown error" : e));
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, n = spec.nchannels;
  if (w <= 0 || h <= 0 || n <= 0) throw std::runtime_error("cannot read image '" + path + "': empty image");
  if ((long long)w * h > kMaxImagePixels || n > 1024)
    throw std::invalid_argument("'" + path + "': its header claims " + std::to_string(w) + "x" + std::to_string(h) +
                                " pixels and " + std::to_string(n) + " channels; allowed: at most " +
                                std::to_string(kMaxImagePixels) + " pixels and 1024 channels");
  std::vector<float> raw(static_cast<std::size_t>(w) * h * n);
  if (!in->read_image(0, 0, 0, n, OIIO::TypeDesc::FLOAT, raw.data())) {
    std::string e = in->geterror();
    throw std::runtime_error("cannot read image '" + path + "': " + (e.empty() ? "read failed" : e));
  }
  if (colorspace_tag) *colorspace_tag = spec.get_string_attribute("oiio:ColorSpace");
  if (file_channels) *file_channels = n;
  in->close();

  int alpha = spec.alpha_channel;
  if (alpha < 0 && n == 2) alpha = 1;  // grey + alpha
  if (alpha < 0 && n >= 4) alpha = 3;
  Image img(w, h, 4, 1.0f);
  for (std::size_t i = 0; i < img.pixel_count(); ++i) {
    const float* s = raw.data() + i * n;
    float* d = img.data.data() + i * 4;
    if (n >= 3) {
      d[0] = s[0], d[1] = s[1], d[2] = s[2];
    } else {
      d[0] = d[1] = d[2] = s[0];
    }
    if (alpha > 0 && alpha < n) d[3] = s[alpha];
  }
  return img;
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
  OIIO::ImageSpec spec(img.width, img.height, img.channels, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = (img.channels == 2) ? 1 : (img.channels == 4 ? 3 : -1);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // values as given: no un-premultiplication
  // zlib level 3, the strongest of its fast (non-lazy) levels, instead of OpenImageIO's default 6: the
  // default experiment with a warm cache and without its report 8.6, 9.5, 10.1 -> 7.6, 7.9, 8.1 s (three
  // interleaved runs), its PNGs 10.8 -> 11.4 MB.
  spec.attribute("png:compressionLevel", 3);
  write_atomic(path, "png", spec, OIIO::TypeDesc::UINT8, q.data());
}

}  // namespace glintlab::metrics

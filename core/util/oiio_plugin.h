// glintlab's use of OpenImageIO lives in a shared library of its own, libglintlab_oiio.so
// (experiments/oiio_plugin/), loaded with dlopen the first time a function below is called. OpenImageIO
// links about 260 shared libraries (its format plugins: ffmpeg, libheif, libraw, OpenVDB, ...), whose
// loading and relocation is most of a process's start-up; commands that read no image through it
// (`check`, `list`, `--help`, `compare` and `measure --no-report` of plain OpenEXR files, which the
// OpenEXR core library reads: experiments/sources/exr_scanlines.h) never load them.
//
// The library is found and loaded as core/util/plugin.h says. A library that cannot be loaded is an
// IoError naming it and dlerror()'s reason. Each function has the
// behaviour, messages and exceptions of the code it came from (named beside it).
#pragma once

#include "core/util/image.h"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace glintlab {

struct SheetTile;

namespace oiio {

// One subimage (part) of a file as OpenImageIO describes it.
struct Part {
  int width = 0, height = 0, channels = 0;
  std::vector<std::string> names;  // channel names, in OpenImageIO's order
  std::string colorspace;          // oiio:ColorSpace ("" if none)
};

// What an environment map's header says (core/scene/environment.cpp).
struct EnvironmentInfo {
  int width = 0, height = 0, channels = 0;
  bool has_chromaticities = false;
  std::array<float, 8> chromaticities{};
  std::string colorspace;  // oiio:ColorSpace
};

constexpr int kApiVersion = 1;

struct Api {
  int version;
  // metrics::read_image after check_image_file: the first subimage, RGBA float (metrics/color/image_io.h).
  Image (*read_image)(const std::string& path, std::string* colorspace_tag, int* file_channels);
  // OpenEXR of `img` into `tmp` (`path` in messages): with chromaticities (8 floats) when given, half or
  // float, channel names as metrics::write_exr_data says. Throws IoError / std::invalid_argument.
  void (*write_exr)(const std::string& tmp, const std::string& path, const Image& img, const float* chromaticities,
                    bool half, const std::vector<std::string>& names);
  // 8-bit PNG of already quantised values (img.channels of them a pixel) into `tmp`.
  void (*write_png)(const std::string& tmp, const std::string& path, int width, int height, int channels,
                    const unsigned char* values);
  // Every part of a frame file, up to max_parts (experiments/sources/sequence.cpp read_frame_header):
  // ConfigError when OpenImageIO cannot open it.
  std::vector<Part> (*frame_parts)(const std::string& path, int max_parts);
  // The named channels of a frame from the parts of size width x height into `out` (its channel k from
  // channels[k]), `done[k]` set for each found (sequence.cpp read_frame_channels). ConfigError.
  void (*read_frame_channels)(const std::string& path, const std::vector<std::string>& channels, int width,
                              int height, int max_parts, Image& out, std::vector<bool>& done);
  // An environment map's first subimage: `check(info)` runs on the header before any pixel is read,
  // then every channel as float into `pixels` (core/scene/environment.cpp read_latlong). ConfigError.
  void (*read_environment)(const std::string& path, const std::function<void(const EnvironmentInfo&)>& check,
                           std::vector<float>& pixels);
  // experiments/runner/contact_sheet.h.
  Image (*make_contact_sheet)(const std::vector<std::vector<SheetTile>>& rows, int max_tile_width, int label_height);
  bool (*contact_sheet_has_font)();
};

// The library's functions, loaded on first use (thread-safe). Throws IoError when it cannot be loaded.
const Api& api();

// Whether this process has loaded the library (for the tests of the paths that must not).
bool loaded();

}  // namespace oiio
}  // namespace glintlab

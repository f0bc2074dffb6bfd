// glintlab's use of OpenColorIO lives in a shared library of its own, libglintlab_ocio.so
// (experiments/ocio_plugin/), loaded with dlopen when the first colour configuration is loaded
// (metrics::ColorManager, the one user of this interface). Loading and relocating OpenColorIO and
// what it links (yaml-cpp, expat, pystring) is most of the start-up of a short command; commands that
// convert no colour (`check`, `list`, `--help`) never load them.
//
// The library is found and loaded as core/util/plugin.h says. A library that cannot be loaded is an
// IoError naming it, dlerror()'s reason and the Debian package to install.
#pragma once

#include "core/util/image.h"

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace glintlab::ocio {

// An OpenColorIO CPU processor.
class Processor {
 public:
  virtual ~Processor() = default;
  // Converts the RGB channels of an interleaved float image (3 or 4 channels) in place; alpha is never
  // changed.
  virtual void apply_rgb(Image& img) const = 0;
};

// One matrix step of an OpenColorIO processor, as OpenColorIO holds it: out = m (r, g, b, a) + offset,
// m row-major.
struct MatrixStep {
  std::array<double, 16> m{};
  std::array<double, 4> offset{};
};

// One loaded and validated OpenColorIO config.
class Config {
 public:
  virtual ~Config() = default;
  // The canonical name of a colour space, alias or role (OCIO's lookup: case-insensitive); "" when the
  // config has none of that name.
  virtual std::string canonical_name(const std::string& name) const = 0;
  virtual std::vector<std::string> spaces() const = 0;  // every active colour space, scene and display
  virtual std::vector<std::string> displays() const = 0;
  virtual std::vector<std::string> views(const std::string& display) const = 0;
  // The colour space display/view encodes into ("" when it names none).
  virtual std::string display_view_space(const std::string& display, const std::string& view) const = 0;
  // The processor from one space to another (canonical names), or from a space through display/view:
  // to the view's encoded values, or with decode_to, on to that space (one processor: OpenColorIO drops
  // the encoding and its inverse). std::runtime_error with OpenColorIO's reason.
  virtual std::shared_ptr<const Processor> processor(const std::string& src, const std::string& dst) const = 0;
  virtual std::shared_ptr<const Processor> display_processor(const std::string& src, const std::string& display,
                                                             const std::string& view,
                                                             const std::string& decode_to = "") const = 0;
  // Every name canonical_name() knows (colour spaces, their aliases, roles) with its canonical name.
  virtual std::vector<std::pair<std::string, std::string>> names() const = 0;
  // The steps of processor(src, dst) after OpenColorIO's default optimisation, when they are all
  // matrices: true and the steps in order (none: the processor changes nothing). False when any step is
  // something else (a curve, a LUT). std::runtime_error with OpenColorIO's reason.
  virtual bool matrix_steps(const std::string& src, const std::string& dst, std::vector<MatrixStep>& steps) const = 0;
};

constexpr int kApiVersion = 2;

struct Api {
  int version;
  // Loads and validates the config file at `path`; std::runtime_error with OpenColorIO's reason.
  std::unique_ptr<Config> (*load)(const std::string& path);
};

// The library's functions, loaded on first use (thread-safe). Throws IoError when it cannot be loaded.
const Api& api();

// Whether this process has loaded the library (for the tests of the paths that must not).
bool loaded();

}  // namespace glintlab::ocio

#include "metrics/color/color_manager.h"
#include "core/util/strings.h"

#include "core/util/data_dir.h"
#include "core/util/ocio_plugin.h"
#include "metrics/color/color_bake.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace glintlab::metrics {

// The config and one processor per (from, to) or (from, display, view): conversions happen every frame.
// Where the config's bake is valid (metrics/color/color_bake.h), OpenColorIO is loaded only for what the
// bake does not hold.
struct ColorManager::Impl {
  std::string path;
  const BakedConfig* bake = nullptr;  // the compiled bake, where it is this config's
  mutable std::once_flag once;
  mutable std::unique_ptr<ocio::Config> loaded;
  mutable std::mutex mutex;
  mutable std::map<std::string, std::shared_ptr<const ocio::Processor>> processors;

  // The config through OpenColorIO, loaded by the first call (libglintlab_ocio.so: IoError when it
  // cannot be loaded; std::runtime_error naming the file when OpenColorIO rejects it).
  const ocio::Config& config() const {
    std::call_once(once, [this] {
      const ocio::Api& api = ocio::api();
      try {
        loaded = api.load(path);
      } catch (const std::runtime_error& e) {
        throw std::runtime_error("OCIO config '" + path + "' cannot be loaded: " + e.what());
      }
    });
    return *loaded;
  }

  // The canonical name of `name` as the bake knows it, else as OpenColorIO does ("" for none).
  std::string lookup(const std::string& name) const {
    if (bake)
      if (const char* canonical = bake->canonical(name)) return canonical;
    return name.empty() ? "" : config().canonical_name(name);
  }

  // The processor under `key`, made by `make` the first time.
  template <class Make>
  std::shared_ptr<const ocio::Processor> cached(const std::string& key, Make make) const {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = processors.find(key);
    if (it == processors.end()) it = processors.emplace(key, make()).first;
    return it->second;
  }
};

namespace {

void require_rgb(const Image& img, const char* what) {
  if (img.channels != 3 && img.channels != 4)
    throw std::invalid_argument(std::string("ColorManager::") + what + ": image has " +
                                std::to_string(img.channels) + " channels; 3 (RGB) or 4 (RGBA) allowed");
  if (img.data.size() != img.pixel_count() * static_cast<std::size_t>(img.channels))
    throw std::invalid_argument(std::string("ColorManager::") + what + ": image data size does not match " +
                                std::to_string(img.width) + "x" + std::to_string(img.height) + "x" +
                                std::to_string(img.channels));
}

}  // namespace

std::string ColorManager::default_config_path() {
  const char* env = std::getenv("OCIO");
  if (env && *env) return env;
  return data_path("metrics/color/ocio/config.ocio");
}

ColorManager::ColorManager() : ColorManager(default_config_path()) {}

ColorManager::ColorManager(const std::string& config_path)
    : config_path_(config_path), impl_(std::make_unique<Impl>()) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(config_path, ec))
    throw std::runtime_error("OCIO config '" + config_path + "': no such file" +
                             (std::getenv("OCIO") ? " (from $OCIO)" : ""));
  impl_->path = config_path;
  impl_->bake = bake_for(config_path);
  if (!impl_->bake) impl_->config();  // no bake: OpenColorIO loads and validates the config now
}

ColorManager::~ColorManager() = default;

bool ColorManager::has_space(const std::string& name) const { return !impl_->lookup(name).empty(); }

std::vector<std::string> ColorManager::spaces() const { return impl_->config().spaces(); }

std::string ColorManager::canonical_name(const std::string& name) const {
  std::string canonical = impl_->lookup(name);
  if (canonical.empty())
    throw std::invalid_argument("unknown colour space '" + name + "' in OCIO config '" + config_path_ +
                                "'; allowed: " + join(spaces()));
  return canonical;
}

std::vector<std::string> ColorManager::displays() const { return impl_->config().displays(); }

std::vector<std::string> ColorManager::views(const std::string& display) const {
  return impl_->config().views(display);
}

void ColorManager::convert(Image& img, const std::string& from, const std::string& to) const {
  require_rgb(img, "convert");
  const std::string src = canonical_name(from);
  const std::string dst = canonical_name(to);
  if (src == dst) return;
  const auto cpu = impl_->cached(src + '\x1f' + dst, [&] {
    if (impl_->bake)
      if (const BakedConversion* baked = impl_->bake->conversion(src, dst)) return baked_processor(*baked);
    try {
      return impl_->config().processor(src, dst);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error("OCIO config '" + config_path_ + "': no conversion '" + src + "' -> '" + dst +
                               "': " + e.what());
    }
  });
  cpu->apply_rgb(img);
}

Image ColorManager::to_xyz_d65(const Image& img, const std::string& from) const {
  Image out = img;
  convert(out, from, kXyzD65Space);
  return out;
}

glm::vec3 ColorManager::convert_color(const glm::vec3& rgb, const std::string& from, const std::string& to) const {
  Image px(1, 1, 3);
  px.data = {rgb.x, rgb.y, rgb.z};
  convert(px, from, to);
  return {px.data[0], px.data[1], px.data[2]};
}

Image ColorManager::display(const Image& scene, const std::string& from_space, const std::string& display,
                            const std::string& view) const {
  return through_view(scene, from_space, display, view, "");
}

Image ColorManager::display_referred_xyz(const Image& scene, const std::string& from_space, const std::string& display,
                                         const std::string& view) const {
  return through_view(scene, from_space, display, view, kXyzD65DisplaySpace);
}

Image ColorManager::through_view(const Image& scene, const std::string& from_space, const std::string& display,
                                 const std::string& view, const std::string& decode_to) const {
  require_rgb(scene, "display");
  const std::string src = canonical_name(from_space);
  const auto ds = displays();
  if (std::find(ds.begin(), ds.end(), display) == ds.end())
    throw std::invalid_argument("unknown display '" + display + "' in OCIO config '" + config_path_ +
                                "'; allowed: " + join(ds));
  const auto vs = views(display);
  if (std::find(vs.begin(), vs.end(), view) == vs.end())
    throw std::invalid_argument("unknown view '" + view + "' of display '" + display + "' in OCIO config '" +
                                config_path_ + "'; allowed: " + join(vs));
  if (!decode_to.empty() && impl_->config().display_view_space(display, view).empty())
    throw std::invalid_argument("view '" + view + "' of display '" + display + "' in OCIO config '" + config_path_ +
                                "' names no display colour space to decode");
  // The view and the decoding as one processor: at 1920x1080 through ACES 1.0 SDR-video 265 ms against
  // 309 + 68 for the two (one thread, OpenColorIO 2.1), the sRGB encoding and its inverse dropped.
  const auto cpu = impl_->cached("display\x1f" + src + '\x1f' + display + '\x1f' + view + '\x1f' + decode_to, [&] {
    try {
      return impl_->config().display_processor(src, display, view, decode_to);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error("OCIO config '" + config_path_ + "': no display transform '" + src + "' -> '" +
                               display + "' / '" + view + "': " + e.what());
    }
  });
  Image out = scene;
  cpu->apply_rgb(out);
  return out;
}

std::array<float, 8> ColorManager::chromaticities(const std::string& space) const {
  const std::string name = canonical_name(space);
  // ITU-R BT.709-6 table 1 (primaries, D65).
  if (name == "lin_rec709") return {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  // ACES AP1, SMPTE S-2014-004 (ACEScg), ACES white.
  if (name == "ACEScg") return {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  // ACES AP0, SMPTE ST 2065-1, ACES white.
  if (name == "ACES2065-1") return {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f};
  throw std::invalid_argument("no EXR chromaticities known for colour space '" + name +
                              "'; known: lin_rec709, ACEScg, ACES2065-1");
}

}  // namespace glintlab::metrics

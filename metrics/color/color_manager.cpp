#include "metrics/color/color_manager.h"
#include "core/util/strings.h"

#include "core/util/data_dir.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <OpenColorIO/OpenColorIO.h>

namespace OCIO = OCIO_NAMESPACE;

namespace glintlab::metrics {

struct ColorManager::Impl {
  OCIO::ConstConfigRcPtr config;
  mutable std::mutex mutex;
  // One CPU processor per (from, to) or (from, display, view): conversions happen every frame.
  mutable std::map<std::string, OCIO::ConstCPUProcessorRcPtr> processors;
};

namespace {

// Applies a CPU processor to the RGB channels of an interleaved float image (3 or 4 channels);
// alpha is never changed.
// RGBA goes through OCIO's own RGBA path, two and a half times faster than RGB with strides that skip
// alpha (1080p lin_rec709 to CIE-XYZ-D65: 2.3–2.7 ms against 6.0–6.9), with the same colours to the
// bit. That path may write alpha (a matrix's zero times an infinite colour is NaN), so it runs over
// bands of rows that stay in the cache, each band's alpha kept aside and put back.
void apply_rgb(const OCIO::ConstCPUProcessorRcPtr& cpu, Image& img) {
  if (img.empty()) return;
  if (img.channels == 4) {
    constexpr int kBandRows = 16;
    const std::size_t w = std::size_t(img.width);
    std::vector<float> alpha(kBandRows * w);
    for (int y0 = 0; y0 < img.height; y0 += kBandRows) {
      const int rows = std::min(kBandRows, img.height - y0);
      float* band = img.px(0, y0);
      const std::size_t n = std::size_t(rows) * w;
      for (std::size_t i = 0; i < n; ++i) alpha[i] = band[4 * i + 3];
      OCIO::PackedImageDesc desc(band, img.width, rows, 4);
      cpu->apply(desc);
      for (std::size_t i = 0; i < n; ++i) band[4 * i + 3] = alpha[i];
    }
    return;
  }
  const std::ptrdiff_t c = sizeof(float);
  const std::ptrdiff_t x = c * img.channels;
  const std::ptrdiff_t y = x * img.width;
  OCIO::PackedImageDesc desc(img.data.data(), img.width, img.height, 3, OCIO::BIT_DEPTH_F32, c, x, y);
  cpu->apply(desc);
}

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
  try {
    impl_->config = OCIO::Config::CreateFromFile(config_path.c_str());
    impl_->config->validate();
  } catch (const OCIO::Exception& e) {
    throw std::runtime_error("OCIO config '" + config_path + "' cannot be loaded: " + e.what());
  }
}

ColorManager::~ColorManager() = default;

bool ColorManager::has_space(const std::string& name) const {
  return !name.empty() && impl_->config->getColorSpace(name.c_str()) != nullptr;
}

std::vector<std::string> ColorManager::spaces() const {
  std::vector<std::string> out;
  const auto& cfg = impl_->config;
  const int n = cfg->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ACTIVE);
  for (int i = 0; i < n; ++i)
    out.emplace_back(cfg->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ACTIVE, i));
  return out;
}

std::string ColorManager::canonical_name(const std::string& name) const {
  OCIO::ConstColorSpaceRcPtr cs = name.empty() ? nullptr : impl_->config->getColorSpace(name.c_str());
  if (!cs)
    throw std::invalid_argument("unknown colour space '" + name + "' in OCIO config '" + config_path_ +
                                "'; allowed: " + join(spaces()));
  return cs->getName();
}

std::vector<std::string> ColorManager::displays() const {
  std::vector<std::string> out;
  for (int i = 0; i < impl_->config->getNumDisplays(); ++i) out.emplace_back(impl_->config->getDisplay(i));
  return out;
}

std::vector<std::string> ColorManager::views(const std::string& display) const {
  std::vector<std::string> out;
  const int n = impl_->config->getNumViews(display.c_str());
  for (int i = 0; i < n; ++i) out.emplace_back(impl_->config->getView(display.c_str(), i));
  return out;
}

void ColorManager::convert(Image& img, const std::string& from, const std::string& to) const {
  require_rgb(img, "convert");
  const std::string src = canonical_name(from);
  const std::string dst = canonical_name(to);
  if (src == dst) return;
  const std::string key = src + '\x1f' + dst;
  OCIO::ConstCPUProcessorRcPtr cpu;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->processors.find(key);
    if (it == impl_->processors.end()) {
      try {
        cpu = impl_->config->getProcessor(src.c_str(), dst.c_str())->getDefaultCPUProcessor();
      } catch (const OCIO::Exception& e) {
        throw std::runtime_error("OCIO config '" + config_path_ + "': no conversion '" + src + "' -> '" +
                                 dst + "': " + e.what());
      }
      impl_->processors.emplace(key, cpu);
    } else {
      cpu = it->second;
    }
  }
  apply_rgb(cpu, img);
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
  const std::string key = "display\x1f" + src + '\x1f' + display + '\x1f' + view;
  OCIO::ConstCPUProcessorRcPtr cpu;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->processors.find(key);
    if (it == impl_->processors.end()) {
      try {
        auto dvt = OCIO::DisplayViewTransform::Create();
        dvt->setSrc(src.c_str());
        dvt->setDisplay(display.c_str());
        dvt->setView(view.c_str());
        cpu = impl_->config->getProcessor(dvt)->getDefaultCPUProcessor();
      } catch (const OCIO::Exception& e) {
        throw std::runtime_error("OCIO config '" + config_path_ + "': no display transform '" + src +
                                 "' -> '" + display + "' / '" + view + "': " + e.what());
      }
      impl_->processors.emplace(key, cpu);
    } else {
      cpu = it->second;
    }
  }
  Image out = scene;
  apply_rgb(cpu, out);
  return out;
}

Image ColorManager::display_referred_xyz(const Image& scene, const std::string& from_space, const std::string& display,
                                         const std::string& view) const {
  Image out = this->display(scene, from_space, display, view);  // validates display and view
  const char* encoded = impl_->config->getDisplayViewColorSpaceName(display.c_str(), view.c_str());
  if (!encoded || !*encoded)
    throw std::invalid_argument("view '" + view + "' of display '" + display + "' in OCIO config '" + config_path_ +
                                "' names no display colour space to decode");
  convert(out, encoded, kXyzD65DisplaySpace);
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

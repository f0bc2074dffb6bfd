// libglintlab_ocio.so: every call glintlab makes into OpenColorIO (core/util/ocio_plugin.h), loaded when
// the first colour configuration is, so that a process that converts no colour never loads OpenColorIO.
// Only glintlab_ocio_api is exported (the rest is hidden).
#include "core/util/ocio_plugin.h"
#include "metrics/parallel.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;

namespace glintlab::ocio {
namespace {

class CpuProcessor final : public Processor {
 public:
  explicit CpuProcessor(OCIO::ConstCPUProcessorRcPtr cpu) : cpu_(std::move(cpu)) {}

  // RGBA goes through OCIO's own RGBA path, two and a half times faster than RGB with strides that skip
  // alpha (1080p lin_rec709 to CIE-XYZ-D65: 2.3–2.7 ms against 6.0–6.9), with the same colours to the
  // bit. That path may write alpha (a matrix's zero times an infinite colour is NaN), so it runs over
  // bands of rows that stay in the cache, each band's alpha kept aside and put back. The bands go to the
  // metric threads (a CPU processor is thread-safe): each is the same call as on one thread, so the
  // colours are the same to the bit; a display transform (ACES 1.0 SDR-video, about 190 ns a pixel) is
  // what this saves most on.
  void apply_rgb(Image& img) const override {
    if (img.empty()) return;
    if (img.channels == 4) {
      constexpr int kBandRows = 16;
      const std::size_t w = std::size_t(img.width);
      metrics::parallel_for((img.height + kBandRows - 1) / kBandRows, [&](long b) {
        const int y0 = int(b) * kBandRows;
        const int rows = std::min(kBandRows, img.height - y0);
        float* band = img.px(0, y0);
        const std::size_t n = std::size_t(rows) * w;
        std::vector<float> alpha(n);
        for (std::size_t i = 0; i < n; ++i) alpha[i] = band[4 * i + 3];
        OCIO::PackedImageDesc desc(band, img.width, rows, 4);
        cpu_->apply(desc);
        for (std::size_t i = 0; i < n; ++i) band[4 * i + 3] = alpha[i];
      }, 1);
      return;
    }
    const std::ptrdiff_t c = sizeof(float);
    const std::ptrdiff_t x = c * img.channels;
    const std::ptrdiff_t y = x * img.width;
    constexpr int kBandRows = 16;  // bands of rows on the metric threads, as above
    metrics::parallel_for((img.height + kBandRows - 1) / kBandRows, [&](long b) {
      const int y0 = int(b) * kBandRows;
      OCIO::PackedImageDesc desc(img.px(0, y0), img.width, std::min(kBandRows, img.height - y0), 3,
                                 OCIO::BIT_DEPTH_F32, c, x, y);
      cpu_->apply(desc);
    }, 1);
  }

 private:
  OCIO::ConstCPUProcessorRcPtr cpu_;
};

class OcioConfig final : public Config {
 public:
  explicit OcioConfig(OCIO::ConstConfigRcPtr config) : config_(std::move(config)) {}

  std::string canonical_name(const std::string& name) const override {
    OCIO::ConstColorSpaceRcPtr cs = name.empty() ? nullptr : config_->getColorSpace(name.c_str());
    return cs ? cs->getName() : "";
  }
  std::vector<std::string> spaces() const override {
    std::vector<std::string> out;
    const int n = config_->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ACTIVE);
    for (int i = 0; i < n; ++i)
      out.emplace_back(config_->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ACTIVE, i));
    return out;
  }
  std::vector<std::string> displays() const override {
    std::vector<std::string> out;
    for (int i = 0; i < config_->getNumDisplays(); ++i) out.emplace_back(config_->getDisplay(i));
    return out;
  }
  std::vector<std::string> views(const std::string& display) const override {
    std::vector<std::string> out;
    const int n = config_->getNumViews(display.c_str());
    for (int i = 0; i < n; ++i) out.emplace_back(config_->getView(display.c_str(), i));
    return out;
  }
  std::string display_view_space(const std::string& display, const std::string& view) const override {
    const char* s = config_->getDisplayViewColorSpaceName(display.c_str(), view.c_str());
    return s ? s : "";
  }
  std::shared_ptr<const Processor> processor(const std::string& src, const std::string& dst) const override {
    try {
      return std::make_shared<CpuProcessor>(config_->getProcessor(src.c_str(), dst.c_str())->getDefaultCPUProcessor());
    } catch (const OCIO::Exception& e) {
      throw std::runtime_error(e.what());
    }
  }
  std::shared_ptr<const Processor> display_processor(const std::string& src, const std::string& display,
                                                     const std::string& view, const std::string& decode_to) const override {
    try {
      auto dvt = OCIO::DisplayViewTransform::Create();
      dvt->setSrc(src.c_str());
      dvt->setDisplay(display.c_str());
      dvt->setView(view.c_str());
      if (decode_to.empty())
        return std::make_shared<CpuProcessor>(config_->getProcessor(dvt)->getDefaultCPUProcessor());
      auto decode = OCIO::ColorSpaceTransform::Create();
      decode->setSrc(display_view_space(display, view).c_str());
      decode->setDst(decode_to.c_str());
      auto group = OCIO::GroupTransform::Create();
      group->appendTransform(dvt);
      group->appendTransform(decode);
      return std::make_shared<CpuProcessor>(config_->getProcessor(group)->getDefaultCPUProcessor());
    } catch (const OCIO::Exception& e) {
      throw std::runtime_error(e.what());
    }
  }
  std::vector<std::pair<std::string, std::string>> names() const override {
    std::vector<std::pair<std::string, std::string>> out;
    const int n = config_->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
    for (int i = 0; i < n; ++i) {
      const char* name = config_->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i);
      OCIO::ConstColorSpaceRcPtr cs = config_->getColorSpace(name);
      out.emplace_back(name, name);
      for (size_t a = 0; a < cs->getNumAliases(); ++a) out.emplace_back(cs->getAlias(a), name);
    }
    for (int i = 0; i < config_->getNumRoles(); ++i) {
      const char* role = config_->getRoleName(i);
      if (std::string c = canonical_name(role); !c.empty()) out.emplace_back(role, c);
    }
    return out;
  }
  bool matrix_steps(const std::string& src, const std::string& dst, std::vector<MatrixStep>& steps) const override {
    try {
      // The steps getDefaultCPUProcessor() renders: the default optimisation of the same processor.
      OCIO::ConstProcessorRcPtr p =
          config_->getProcessor(src.c_str(), dst.c_str())->getOptimizedProcessor(OCIO::OPTIMIZATION_DEFAULT);
      OCIO::GroupTransformRcPtr group = p->createGroupTransform();
      steps.clear();
      for (int i = 0; i < group->getNumTransforms(); ++i) {
        auto m = OCIO::DynamicPtrCast<const OCIO::MatrixTransform>(group->getTransform(i));
        if (!m || m->getDirection() != OCIO::TRANSFORM_DIR_FORWARD) return false;
        MatrixStep step;
        m->getMatrix(step.m.data());
        m->getOffset(step.offset.data());
        steps.push_back(step);
      }
      return true;
    } catch (const OCIO::Exception& e) {
      throw std::runtime_error(e.what());
    }
  }

 private:
  OCIO::ConstConfigRcPtr config_;
};

std::unique_ptr<Config> load(const std::string& path) {
  try {
    OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
    config->validate();
    return std::make_unique<OcioConfig>(std::move(config));
  } catch (const OCIO::Exception& e) {
    throw std::runtime_error(e.what());
  }
}

}  // namespace
}  // namespace glintlab::ocio

// The table, untyped: load_plugin (core/util/plugin.h) calls every plugin's function as const void* ().
extern "C" __attribute__((visibility("default"))) const void* glintlab_ocio_api() {
  static const glintlab::ocio::Api api{glintlab::ocio::kApiVersion, &glintlab::ocio::load};
  return &api;
}

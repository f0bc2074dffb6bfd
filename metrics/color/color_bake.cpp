#include "metrics/color/color_bake.h"

#include "core/util/content_hash.h"
#include "core/util/strings.h"

#include <cstring>
#include <optional>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

extern char** environ;

namespace glintlab::metrics {

namespace {

// One matrix step as OpenColorIO's CPU renderer holds it (ops/matrix/MatrixOpCPU.cpp): each column of
// the 4x4 matrix and the offset rounded to float; a diagonal matrix scales each channel alone, an
// offset of zeros is not added (adding +0 would turn a -0 into +0).
struct RenderedStep {
  alignas(16) float col[4][4];  // col[j][i] = m[i][j]
  alignas(16) float offset[4];
  alignas(16) float scale[4];   // the diagonal
  bool diagonal, has_offset;

  explicit RenderedStep(const ocio::MatrixStep& s) {
    diagonal = true;
    has_offset = false;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        col[j][i] = float(s.m[std::size_t(4 * i + j)]);
        if (i != j && s.m[std::size_t(4 * i + j)] != 0.0) diagonal = false;
      }
      scale[i] = col[i][i];
      offset[i] = float(s.offset[std::size_t(i)]);
      if (s.offset[std::size_t(i)] != 0.0) has_offset = true;
    }
  }

#if defined(__SSE2__)
  // One RGBA pixel, the four channels at once as OpenColorIO's renderer computes them: r m0 + g m1 and
  // b m2 + a m3 added, then the offset; a scale alone for a diagonal matrix. The same single-precision
  // operations in the same order, so the same bits.
  __m128 apply(__m128 v) const {
    if (diagonal) {
      v = _mm_mul_ps(v, _mm_load_ps(scale));
    } else {
      const __m128 r = _mm_shuffle_ps(v, v, 0x00), g = _mm_shuffle_ps(v, v, 0x55), b = _mm_shuffle_ps(v, v, 0xaa),
                   a = _mm_shuffle_ps(v, v, 0xff);
      v = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_load_ps(col[0]), r), _mm_mul_ps(_mm_load_ps(col[1]), g)),
                     _mm_add_ps(_mm_mul_ps(_mm_load_ps(col[2]), b), _mm_mul_ps(_mm_load_ps(col[3]), a)));
    }
    return has_offset ? _mm_add_ps(v, _mm_load_ps(offset)) : v;
  }
#else
  void apply(float p[4]) const {  // the same, a channel at a time
    float out[4];
    for (int i = 0; i < 4; ++i)
      out[i] = diagonal ? p[i] * scale[i]
                        : (p[0] * col[0][i] + p[1] * col[1][i]) + (p[2] * col[2][i] + p[3] * col[3][i]);
    if (has_offset)
      for (int i = 0; i < 4; ++i) out[i] += offset[i];
    std::memcpy(p, out, sizeof out);
  }
#endif
};

class BakedProcessor final : public ocio::Processor {
 public:
  BakedProcessor(const ocio::MatrixStep* steps, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) steps_.emplace_back(steps[i]);
  }
  // OpenColorIO reads an RGB pixel as RGBA with alpha 0 (ImagePacking.cpp) and runs every step on all four
  // channels; glintlab keeps an image's alpha as it was (ocio_plugin.h).
  void apply_rgb(Image& img) const override {
    if (steps_.empty() || img.empty()) return;
    const std::size_t n = img.pixel_count(), c = std::size_t(img.channels);
    float* d = img.data.data();
#if defined(__SSE2__)
    if (steps_.size() == 1 && c == 4) {  // the common case: one matrix, RGBA
      const RenderedStep step = steps_[0];
      for (std::size_t k = 0; k < n; ++k) {
        float* px = d + 4 * k;
        const float alpha = px[3];
        _mm_storeu_ps(px, step.apply(_mm_loadu_ps(px)));
        px[3] = alpha;
      }
      return;
    }
    for (std::size_t k = 0; k < n; ++k) {
      float* px = d + k * c;
      __m128 v = _mm_setr_ps(px[0], px[1], px[2], c == 4 ? px[3] : 0.0f);
      for (const RenderedStep& s : steps_) v = s.apply(v);
      alignas(16) float p[4];
      _mm_store_ps(p, v);
      px[0] = p[0], px[1] = p[1], px[2] = p[2];
    }
#else
    for (std::size_t k = 0; k < n; ++k) {
      float* px = d + k * c;
      float p[4] = {px[0], px[1], px[2], c == 4 ? px[3] : 0.0f};
      for (const RenderedStep& s : steps_) s.apply(p);
      px[0] = p[0], px[1] = p[1], px[2] = p[2];
    }
#endif
  }

 private:
  std::vector<RenderedStep> steps_;
};

bool ocio_environment_set() {
  for (char** e = environ; e && *e; ++e)
    if (std::strncmp(*e, "OCIO_", 5) == 0) return true;
  return false;
}

}  // namespace

const char* BakedConfig::canonical(const std::string& name) const {
  const std::string key = bake_key(name);
  for (std::size_t i = 0; i < name_count; ++i)
    if (key == names[i].name) return names[i].canonical;
  return nullptr;
}

const BakedConversion* BakedConfig::conversion(const std::string& from, const std::string& to) const {
  for (std::size_t i = 0; i < conversion_count; ++i)
    if (from == conversions[i].from && to == conversions[i].to) return &conversions[i];
  return nullptr;
}

const BakedConfig* bake_for(const std::string& config_path) {
  if (ocio_environment_set()) return nullptr;
  const std::optional<std::string> bytes = read_text_file(config_path);
  const BakedConfig& bake = compiled_bake();
  return bytes && core::hash_hex(*bytes) == bake.config_hash ? &bake : nullptr;
}

std::string bake_key(const std::string& name) { return ascii_lower(name); }

std::shared_ptr<const ocio::Processor> baked_processor(const BakedConversion& conversion) {
  return std::make_shared<BakedProcessor>(conversion.steps, conversion.step_count);
}

}  // namespace glintlab::metrics

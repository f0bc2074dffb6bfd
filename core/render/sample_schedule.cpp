#include "core/render/sample_schedule.h"

#include "core/scene/camera_path.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace glintlab::core {

std::vector<glm::vec2> stratified_offsets(int n, uint32_t seed) {
  std::vector<glm::vec2> out;
  if (n <= 0) return out;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  out.reserve(size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      out.emplace_back((float(i) + u(rng)) / float(n) - 0.5f, (float(j) + u(rng)) / float(n) - 0.5f);
  return out;
}

double radical_inverse(uint32_t index, uint32_t base) {
  double inv = 1.0 / double(base), f = inv, r = 0.0;
  while (index > 0) {
    r += f * double(index % base);
    index /= base;
    f *= inv;
  }
  return r;
}

int fsr2_jitter_phases(double render_scale) {
  const double s = std::clamp(std::isfinite(render_scale) ? render_scale : 1.0, 0.01, 1.0);
  return int(std::floor(8.0 / (s * s) + 1e-9));  // 1/1.5 -> 18, 1/1.7 -> 23, 1/2 -> 32, 1/3 -> 72
}

glm::vec2 jitter_offset(JitterSequence sequence, int frame, double render_scale) {
  const uint32_t k = uint32_t(frame < 0 ? 0 : frame);
  auto halton = [&](uint32_t n) {
    const uint32_t i = k % n + 1;
    return glm::vec2(float(radical_inverse(i, 2) - 0.5), float(radical_inverse(i, 3) - 0.5));
  };
  switch (sequence) {
    case JitterSequence::None: return glm::vec2(0.0f);
    case JitterSequence::Halton8: return halton(8);
    case JitterSequence::Halton16: return halton(16);
    case JitterSequence::Halton32: return halton(32);
    case JitterSequence::HaltonFsr2: return halton(uint32_t(fsr2_jitter_phases(render_scale)));
    case JitterSequence::R2: {
      const double g = 1.32471795724474602596;  // plastic number: g^3 = g + 1
      const double a1 = 1.0 / g, a2 = 1.0 / (g * g);
      double x = 0.5 + a1 * double(k), y = 0.5 + a2 * double(k);
      return glm::vec2(float(x - std::floor(x) - 0.5), float(y - std::floor(y) - 0.5));
    }
  }
  return glm::vec2(0.0f);
}

std::vector<SamplePush> samples_for(const CameraPath& path, int frame, int width, int height,
                                    const std::vector<glm::vec2>& offsets) {
  std::vector<SamplePush> out;
  const float w = offsets.empty() ? 1.0f : 1.0f / float(offsets.size());
  for (size_t i = 0; i < offsets.size(); ++i) {
    FrameCamera cam = path.frame(frame, width, height, offsets[i]);
    out.push_back({cam.view_proj, {offsets[i].x, offsets[i].y, w, float(i)}});
  }
  return out;
}

}  // namespace glintlab::core

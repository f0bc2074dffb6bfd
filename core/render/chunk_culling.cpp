#include "core/render/chunk_culling.h"

#include <algorithm>
#include <cmath>

namespace glintlab::core {

namespace {

// Relative margin of the outside test: the GPU transforms a vertex in fp32
// (|error| ~ 1e-6 of |M| |p|); a corner closer to a plane than this is
// counted as inside.
constexpr double kMargin = 1e-5;

}  // namespace

bool box_outside_clip_volume(const glm::dmat4& clip_from_object, const glm::dvec3& lo, const glm::dvec3& hi) {
  // For each of the six planes, a bit that stays set while every corner is beyond it.
  unsigned all_outside = 0x3F;
  for (int k = 0; k < 8 && all_outside != 0; ++k) {
    const glm::dvec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    const glm::dvec4 c = clip_from_object * glm::dvec4(p, 1.0);
    const double eps = kMargin * (std::abs(c.x) + std::abs(c.y) + std::abs(c.z) + std::abs(c.w)) + 1e-30;
    unsigned outside = 0;
    if (c.x < -c.w - eps) outside |= 1u;
    if (c.x > c.w + eps) outside |= 2u;
    if (c.y < -c.w - eps) outside |= 4u;
    if (c.y > c.w + eps) outside |= 8u;
    if (c.z < -eps) outside |= 16u;
    if (c.z > c.w + eps) outside |= 32u;
    all_outside &= outside;
  }
  return all_outside != 0;
}

std::vector<DrawRange> visible_ranges(const std::vector<MeshChunk>& chunks, const glm::mat4& clip_from_object) {
  const glm::dmat4 m(clip_from_object);
  std::vector<DrawRange> out;
  for (const MeshChunk& c : chunks) {
    if (c.index_count == 0 || box_outside_clip_volume(m, glm::dvec3(c.lo), glm::dvec3(c.hi))) continue;
    if (!out.empty() && out.back().first_index + out.back().index_count == c.first_index)
      out.back().index_count += c.index_count;
    else
      out.push_back({c.first_index, c.index_count});
  }
  return out;
}

}  // namespace glintlab::core

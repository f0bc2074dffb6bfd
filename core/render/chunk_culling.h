// Which chunks of a mesh (core/scene/mesh.h, MeshChunk) a sample can see:
// the renderer draws only those. A chunk is left out when its box lies
// entirely outside one plane of the clip volume (Vulkan: -w <= x, y <= w,
// 0 <= z <= w); every point of the box is then outside that plane too (a
// half-space is convex), so none of the chunk's triangles could make a
// fragment and the image is the same with or without culling (a test
// renders both ways). The test is conservative: a corner counts as outside
// only by a margin larger than fp32's rounding of the vertex transform.
#pragma once

#include "core/scene/mesh.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace glintlab::core {

// Index range of one indexed draw.
struct DrawRange {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
};

// True when no point of the object-space box [lo, hi] lies inside the clip
// volume of `clip_from_object` (projection * view * model).
bool box_outside_clip_volume(const glm::dmat4& clip_from_object, const glm::dvec3& lo, const glm::dvec3& hi);

// The chunks not outside the clip volume, as few draws as possible: runs of
// consecutive visible chunks whose index ranges touch become one draw.
std::vector<DrawRange> visible_ranges(const std::vector<MeshChunk>& chunks, const glm::mat4& clip_from_object);

}  // namespace glintlab::core

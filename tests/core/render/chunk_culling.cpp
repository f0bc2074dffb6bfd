// Chunk culling (core/render/chunk_culling.h): a box is left out only when
// every point of it is outside the clip volume (checked on random cameras and
// boxes in fp64), the cases with a known answer, and the merging of draws.
#include "core/render/chunk_culling.h"
#include "core/scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace glintlab;
using namespace glintlab::core;

namespace {

bool point_outside(const glm::dmat4& m, const glm::dvec3& p) {
  const glm::dvec4 c = m * glm::dvec4(p, 1.0);
  return c.x < -c.w || c.x > c.w || c.y < -c.w || c.y > c.w || c.z < 0.0 || c.z > c.w;
}

glm::dmat4 camera_matrix(glm::vec3 eye, glm::vec3 target, float fov, float near, float far, int w, int h) {
  CameraState c;
  c.position = eye;
  c.target = target;
  c.fov_y_deg = fov;
  c.near = near;
  c.far = far;
  return glm::dmat4(projection(c, w, h) * view_matrix(c));
}

}  // namespace

TEST(ChunkCulling, ACulledBoxHasNoPointInsideTheClipVolume) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-20.0f, 20.0f), unit(0.0f, 1.0f);
  int culled = 0, kept = 0, kept_but_outside = 0;
  for (int cam = 0; cam < 40; ++cam) {
    const glm::vec3 eye(pos(rng), pos(rng), pos(rng));
    glm::vec3 target(pos(rng), pos(rng), pos(rng));
    if (glm::length(glm::vec2(target.x - eye.x, target.z - eye.z)) < 1e-2f) target.x += 1.0f;
    const glm::dmat4 m = camera_matrix(eye, target, 10.0f + 120.0f * unit(rng), 0.01f + unit(rng), 30.0f + 50.0f * unit(rng),
                                       64 + int(600 * unit(rng)), 64 + int(400 * unit(rng)));
    for (int b = 0; b < 200; ++b) {
      // Half of the boxes anywhere, half near the eye (where the near plane cuts).
      glm::dvec3 c(pos(rng), pos(rng), pos(rng));
      if (b % 2) c = glm::dvec3(eye) + glm::normalize(c) * double(std::exp(5.0f * unit(rng) - 3.0f));
      const glm::dvec3 half(std::exp(4.0f * unit(rng) - 3.0f), std::exp(4.0f * unit(rng) - 3.0f),
                            std::exp(4.0f * unit(rng) - 3.0f));
      const glm::dvec3 lo = c - half, hi = c + half;
      const bool out = box_outside_clip_volume(m, lo, hi);
      (out ? culled : kept) += 1;
      // Corners, the centre and random points: every one outside when culled.
      bool any_inside = !point_outside(m, c);
      for (int k = 0; k < 8; ++k)
        any_inside |= !point_outside(m, {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
      for (int s = 0; s < 64; ++s)
        any_inside |= !point_outside(m, lo + (hi - lo) * glm::dvec3(unit(rng), unit(rng), unit(rng)));
      if (out) {
        EXPECT_FALSE(any_inside) << "culled box with a point inside, camera " << cam << " box " << b;
      }
      if (!out && !any_inside) ++kept_but_outside;
    }
  }
  // Both answers occur, and boxes that are kept are mostly ones that are seen
  // (a box can be outside the volume without being beyond one plane: kept).
  EXPECT_GT(culled, 2000);
  EXPECT_GT(kept, 500);
  EXPECT_LT(kept_but_outside, kept / 2);
}

TEST(ChunkCulling, KnownCases) {
  // Camera at the origin looking down -z, 90 degrees, square, near 1, far 100.
  const glm::dmat4 m = camera_matrix({0, 0, 0}, {0, 0, -1}, 90.0f, 1.0f, 100.0f, 100, 100);
  auto out = [&](glm::dvec3 lo, glm::dvec3 hi) { return box_outside_clip_volume(m, lo, hi); };
  EXPECT_FALSE(out({-1, -1, -11}, {1, 1, -9}));       // ahead
  EXPECT_TRUE(out({-1, -1, 9}, {1, 1, 11}));          // behind
  EXPECT_FALSE(out({-1, -1, -2}, {1, 1, 2}));         // across the near plane and the eye
  EXPECT_TRUE(out({-1, -1, -0.9}, {1, 1, -0.5}));     // between the eye and the near plane
  EXPECT_FALSE(out({-0.5, -0.5, -1.2}, {0.5, 0.5, -1.1}));  // just beyond it
  EXPECT_TRUE(out({-1, -1, -120}, {1, 1, -101}));     // beyond the far plane
  EXPECT_FALSE(out({-1, -1, -120}, {1, 1, -99}));     // across it
  EXPECT_TRUE(out({11, -1, -10.5}, {12, 1, -9.5}));   // right of the 45-degree side plane at z = -10
  EXPECT_FALSE(out({10, -1, -10}, {12, 1, -10}));     // a face on that plane: kept (margin)
  EXPECT_FALSE(out({-50, -50, -10}, {50, 50, -5}));   // larger than the view
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(out({nan, 0, -10}, {1, 1, -9})) << "a NaN box is drawn, never dropped";
}

TEST(ChunkCulling, VisibleChunksMergeIntoFewDraws) {
  const glm::mat4 m(camera_matrix({0, 0, 0}, {0, 0, -1}, 90.0f, 1.0f, 100.0f, 100, 100));
  auto chunk = [](uint32_t first, uint32_t count, float z) {
    MeshChunk c;
    c.first_index = first;
    c.index_count = count;
    c.lo = {-1, -1, z - 1};
    c.hi = {1, 1, z + 1};
    return c;
  };
  // Seen, seen, behind, seen, empty, seen.
  const std::vector<MeshChunk> chunks = {chunk(0, 6, -10), chunk(6, 3, -20), chunk(9, 3, 10),
                                         chunk(12, 6, -5), chunk(18, 0, -5), chunk(18, 9, -30)};
  const std::vector<DrawRange> r = visible_ranges(chunks, m);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].first_index, 0u);
  EXPECT_EQ(r[0].index_count, 9u);
  EXPECT_EQ(r[1].first_index, 12u);
  EXPECT_EQ(r[1].index_count, 15u);
  // Turned round: only the chunk at z = +10.
  const std::vector<DrawRange> back = visible_ranges(chunks, glm::mat4(camera_matrix({0, 0, 0}, {0, 0, 1}, 30.0f, 1.0f, 50.0f, 10, 10)));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].first_index, 9u);
  EXPECT_EQ(back[0].index_count, 3u);
}

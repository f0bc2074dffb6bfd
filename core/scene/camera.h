// Pinhole camera for the headless Vulkan renderer: right-handed look-at view, Vulkan projection
// (clip depth [0, 1], Y flipped) with a sub-pixel jitter for TAA and supersampling.
//
// Pixel convention (used by jitter and by every motion vector): a point with NDC (x, y) lands at
// continuous pixel coordinates p = ((x + 1) / 2 * width, (y + 1) / 2 * height), pixel (i, j) covers
// [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5), row 0 is the top of the image, and world
// +Y (camera up) appears upwards on screen. Jitter shifts the image: a point that projected to p
// projects to p + jitter_px (so +x moves right, +y moves DOWN one row per unit).
//
// Winding: with this projection, triangles that are counter-clockwise seen from the front
// (right-handed, as core/scene/mesh.h builds them) are VK_FRONT_FACE_COUNTER_CLOCKWISE.
#pragma once

#include <glm/glm.hpp>

namespace glintlab::core {

struct CameraState {
  glm::vec3 position{0.0f, 1.0f, 5.0f};
  glm::vec3 target{0.0f};    // look-at point
  glm::vec3 up{0, 1, 0};     // need not be unit or orthogonal; must not be parallel to target - position
  float fov_y_deg = 45;      // full vertical field of view, degrees, in (0, 180)
  float near = 0.05f, far = 500;
};

// Right-handed look-at (camera looks down -Z in view space, +Y up). Throws std::invalid_argument
// for position == target, up parallel to the view direction, zero up, or non-finite input.
glm::mat4 view_matrix(const CameraState& c);

// perspectiveRH_ZO with Y flipped (see the pixel convention above), then a translation in NDC by
// (2 jitter.x / width, 2 jitter.y / height). Throws std::invalid_argument for a non-positive size,
// fov outside (0, 180), near <= 0, far <= near, or non-finite jitter.
glm::mat4 projection(const CameraState& c, int width, int height, glm::vec2 jitter_px = {0, 0});

// Continuous pixel coordinates of world point `p_world` under `view_proj` (clip.w must be > 0).
glm::vec2 project_to_pixel(const glm::mat4& view_proj, glm::vec3 p_world, int width, int height);

// Everything the renderer needs for frame `index`. TAA convention: `view_proj` (and `proj`) carry
// this frame's jitter; motion vectors are computed from the *_unjittered pair, which is exactly
// the camera motion. `prev_view_proj` is frame index-1 with the previous frame's jitter.
// Frame 0 and the first frame after a cut have no predecessor: prev_* equal this frame's own
// matrices (zero motion).
struct FrameCamera {
  int index = 0;
  double time = 0;       // seconds, = index / fps
  double prev_time = 0;  // the previous frame's time (= time in frame 0 and at a cut)
  CameraState state;
  glm::mat4 view{1.0f}, proj{1.0f}, view_proj{1.0f}, prev_view_proj{1.0f};
  glm::mat4 proj_unjittered{1.0f}, view_proj_unjittered{1.0f}, prev_view_proj_unjittered{1.0f};
  glm::vec3 position{0.0f};       // world-space eye position (= state.position)
  glm::vec3 prev_position{0.0f};  // the previous frame's eye (= position in frame 0 and at a cut)
  bool cut = false;               // a camera cut: frame `index` starts a new shot (no predecessor)
};

}  // namespace glintlab::core

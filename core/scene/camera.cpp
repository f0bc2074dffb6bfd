#include "core/scene/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace glintlab::core {

namespace {
bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

glm::mat4 view_matrix(const CameraState& c) {
  if (!finite3(c.position) || !finite3(c.target) || !finite3(c.up))
    throw std::invalid_argument("camera: position, target and up must be finite");
  glm::vec3 d = c.target - c.position;
  float dl = glm::length(d), ul = glm::length(c.up);
  if (!(dl > 1e-6f * std::max(1.0f, glm::length(c.position))))
    throw std::invalid_argument("camera: position and target coincide; the view direction is undefined");
  if (!(ul > 0.0f)) throw std::invalid_argument("camera: up vector is zero");
  // |sin(angle(d, up))| below ~1e-4 rad: the right vector would be degenerate.
  if (!(glm::length(glm::cross(d / dl, c.up / ul)) > 1e-4f))
    throw std::invalid_argument("camera: up vector is parallel to the view direction; choose another up");
  return glm::lookAtRH(c.position, c.target, c.up);
}

glm::mat4 projection(const CameraState& c, int width, int height, glm::vec2 jitter_px) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("camera: image size must be positive, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  if (!(c.fov_y_deg > 0.0f && c.fov_y_deg < 180.0f))
    throw std::invalid_argument("camera: fov_y_deg must be in (0, 180), got " + std::to_string(c.fov_y_deg));
  if (!(c.near > 0.0f) || !(c.far > c.near) || !std::isfinite(c.far))
    throw std::invalid_argument("camera: need 0 < near < far < inf");
  if (!std::isfinite(jitter_px.x) || !std::isfinite(jitter_px.y))
    throw std::invalid_argument("camera: jitter must be finite");
  glm::mat4 p = glm::perspectiveRH_ZO(glm::radians(c.fov_y_deg), float(width) / float(height), c.near, c.far);
  p[1][1] = -p[1][1];  // Vulkan: NDC y = -1 is row 0 (top); keep world up pointing up on screen
  // NDC shift of jitter_px pixels: clip.xy += delta * clip.w, i.e. ndc.xy += delta after the divide.
  glm::vec2 delta(2.0f * jitter_px.x / float(width), 2.0f * jitter_px.y / float(height));
  glm::mat4 t(1.0f);
  t[3][0] = delta.x;
  t[3][1] = delta.y;
  return t * p;
}

glm::vec2 project_to_pixel(const glm::mat4& view_proj, glm::vec3 p_world, int width, int height) {
  glm::vec4 clip = view_proj * glm::vec4(p_world, 1.0f);
  if (!(clip.w > 0.0f)) throw std::invalid_argument("project_to_pixel: point is behind the camera");
  glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {(ndc.x + 1.0f) * 0.5f * float(width), (ndc.y + 1.0f) * 0.5f * float(height)};
}

}  // namespace glintlab::core

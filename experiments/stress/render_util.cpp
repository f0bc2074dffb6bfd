#include "experiments/stress/render_util.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>

namespace glintlab::stress {

core::EnvironmentTexture constant_env(float sky) {
  core::EnvironmentTexture env;
  env.width = 8;
  env.height = 4;
  for (uint32_t w = 8, h = 4;; w = std::max(1u, w / 2), h = std::max(1u, h / 2)) {
    std::vector<float> level(size_t(w) * h * 4, sky);
    for (size_t i = 3; i < level.size(); i += 4) level[i] = 1.0f;
    env.mips_rgba.push_back(std::move(level));
    if (w == 1 && h == 1) break;
  }
  return env;
}

core::FrameUniforms frame_uniforms(const core::CameraState& cam, int width, int height, const Lighting& light,
                                   const glm::mat4& model) {
  core::FrameUniforms f;
  f.model = model;
  f.normal_matrix = glm::inverseTranspose(model);
  f.prev_model = model;
  glm::mat4 vp = core::projection(cam, width, height) * core::view_matrix(cam);
  f.view_proj = vp;
  f.prev_view_proj = vp;
  f.inv_view_proj = glm::inverse(vp);
  f.camera_pos = glm::vec4(cam.position, 0.0f);
  f.prev_camera_pos = glm::vec4(cam.position, 0.0f);
  f.sun_dir = glm::vec4(glm::normalize(light.sun_dir), light.sun_radius);
  f.sun_L = glm::vec4(light.sun_L, 0.0f);
  f.resolution = glm::vec4(float(width), float(height), 1.0f / float(width), 1.0f / float(height));
  // E(n) = env_sh[0] Y_00 for every n, and L_sky^Omega = E / pi (shaders/common/environment.glsl)
  const float k = 3.14159265358979f / 0.282094791773878f;
  f.env_sh[0] = glm::vec4(light.sky * k, 0.0f);
  f.env_params = glm::vec4(4.0f, 1.0f, 0.0f, 0.0f);  // constant_env has 4 mip levels
  return f;
}

std::vector<core::SamplePush> samples(const core::CameraState& cam, int width, int height,
                                      const std::vector<glm::vec2>& offsets) {
  std::vector<core::SamplePush> s;
  const glm::mat4 view = core::view_matrix(cam);
  for (size_t i = 0; i < offsets.size(); ++i) {
    core::SamplePush p;
    p.view_proj = core::projection(cam, width, height, offsets[i]) * view;
    p.jitter_weight = glm::vec4(offsets[i], 1.0f / float(offsets.size()), float(i));
    s.push_back(p);
  }
  return s;
}

core::Mesh plane_mesh(float size, int tess) {
  core::MeshSpec spec;
  spec.type = "plane";
  spec.size = size;
  spec.tessellation = tess;
  return core::build_mesh(spec);
}

}  // namespace glintlab::stress

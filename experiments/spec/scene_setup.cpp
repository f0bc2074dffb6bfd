#include "experiments/spec/scene_setup.h"
#include "core/util/strings.h"

#include "core/scene/mesh.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "metrics/color/measurement_space.h"

#include <algorithm>

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace glintlab {

core::Environment prepare_environment(const ExperimentSpec& spec, const metrics::ColorManager& cm) {
  core::Environment env = core::make_environment(spec.sky);
  Image sky;
  sky.width = env.sky.width;
  sky.height = env.sky.height;
  sky.channels = 3;
  sky.data.assign(env.sky.rgb.begin(), env.sky.rgb.end());
  cm.convert(sky, env.sky.color_space, spec.working_space);
  env.sky.rgb.assign(sky.data.begin(), sky.data.end());
  env.sky.color_space = spec.working_space;
  env.sun.color = cm.convert_color(env.sun.color, env.sun.color_space, spec.working_space);
  env.sun.color_space = spec.working_space;
  core::compute_sh_irradiance(env);
  return env;
}

core::EnvironmentTexture environment_texture(const core::Environment& env) {
  core::EnvironmentTexture tex;
  tex.width = uint32_t(env.sky.width);
  tex.height = uint32_t(env.sky.height);
  for (const core::LatLong& m : core::build_mips(env.sky)) {
    std::vector<float> rgba(size_t(m.width) * m.height * 4);
    for (size_t i = 0; i < size_t(m.width) * m.height; ++i) {
      rgba[4 * i + 0] = m.rgb[3 * i + 0];
      rgba[4 * i + 1] = m.rgb[3 * i + 1];
      rgba[4 * i + 2] = m.rgb[3 * i + 2];
      rgba[4 * i + 3] = 1.0f;
    }
    tex.mips_rgba.push_back(std::move(rgba));
  }
  return tex;
}

core::SandParams to_working_space(core::SandParams p, const std::string& working_space,
                                  const metrics::ColorManager& cm) {
  auto conv = [&](std::array<double, 3>& c) {
    glm::vec3 v = cm.convert_color(glm::vec3(float(c[0]), float(c[1]), float(c[2])), p.palette_space, working_space);
    c = {std::max(0.0, double(v.x)), std::max(0.0, double(v.y)), std::max(0.0, double(v.z))};
  };
  for (auto& c : p.palette) conv(c);
  conv(p.I_glints);
  p.palette_space = working_space;
  return p;
}

core::FrameUniforms frame_uniforms(const core::FrameCamera& cam, const core::Environment& env, int width, int height,
                                   size_t env_mip_levels, const core::ObjectMotion& motion) {
  core::FrameUniforms f;
  f.model = motion.model_at(cam.time);
  f.normal_matrix = glm::inverseTranspose(f.model);
  f.prev_model = motion.model_at(cam.prev_time);
  f.view_proj = cam.view_proj_unjittered;
  f.prev_view_proj = cam.prev_view_proj_unjittered;
  f.inv_view_proj = glm::inverse(cam.view_proj_unjittered);
  f.camera_pos = glm::vec4(cam.position, float(cam.time));
  f.prev_camera_pos = glm::vec4(cam.prev_position, 0.0f);
  float radius = glm::radians(env.sun.angular_diameter_deg) * 0.5f;
  f.sun_dir = glm::vec4(env.sun.direction, radius);
  f.sun_L = glm::vec4(env.sun.color * env.sun.intensity, 0.0f);
  f.resolution = glm::vec4(float(width), float(height), 1.0f / float(width), 1.0f / float(height));
  for (int i = 0; i < 9; ++i) f.env_sh[i] = glm::vec4(env.sh_irradiance[i], 0.0f);
  f.env_params = glm::vec4(float(env_mip_levels), 1.0f, 0.0f, 0.0f);
  return f;
}

core::SandFeatures distance_range(const ExperimentSpec& spec, const core::Mesh& mesh) {
  core::SandFeatures f;
  double lo = INFINITY, hi = 0;
  for (int k = 0; k < spec.frames; ++k) {
    const double t = spec.path.frame_time(k);
    glm::dvec3 e = glm::dvec3(spec.path.at(t).position);
    // The eye in the mesh's own frame (a moving mesh moves its bounds).
    if (spec.mesh.motion.moves()) e = glm::dvec3(glm::inverse(spec.mesh.motion.model_at(t)) * glm::vec4(glm::vec3(e), 1.0f));
    glm::dvec3 bmin(mesh.bounds_min), bmax(mesh.bounds_max);
    glm::dvec3 nearest = glm::clamp(e, bmin, bmax);
    lo = std::min(lo, glm::length(e - nearest));
    glm::dvec3 farthest(std::abs(e.x - bmin.x) > std::abs(e.x - bmax.x) ? bmin.x : bmax.x,
                        std::abs(e.y - bmin.y) > std::abs(e.y - bmax.y) ? bmin.y : bmax.y,
                        std::abs(e.z - bmin.z) > std::abs(e.z - bmax.z) ? bmin.z : bmax.z);
    hi = std::max(hi, glm::length(e - farthest));
  }
  f.min_distance = lo;
  f.max_distance = hi;
  return f;
}

std::string display_view_problem(const metrics::ColorManager& cm, const std::string& display, const std::string& view) {
  const auto ds = cm.displays();
  if (std::find(ds.begin(), ds.end(), display) == ds.end()) return "unknown display \"" + display + "\"; allowed: " + join(ds);
  const auto vs = cm.views(display);
  if (std::find(vs.begin(), vs.end(), view) == vs.end())
    return "display \"" + display + "\" has no view \"" + view + "\"; allowed: " + join(vs);
  return "";
}

void check_color_names(const ExperimentSpec& spec, const metrics::ColorManager& cm) {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError(spec.file + ": " + key + ": " + what + " (OCIO config " + cm.config_path() + ")");
  };
  auto space = [&](const std::string& key, const std::string& name) {
    if (!name.empty() && !cm.has_space(name)) fail(key, "unknown colour space \"" + name + "\"");
  };
  auto display_view = [&](const std::string& key, const std::string& display, const std::string& view) {
    const std::string problem = display_view_problem(cm, display, view);
    if (!problem.empty()) fail(key, problem);
  };
  display_view("output.display/view", spec.output.display, spec.output.view);
  if (!spec.metric_options.display_view.empty()) {
    const auto [d, v] = metrics::parse_display_view(spec.metric_options.display_view);
    display_view("metric_options.view", d, v);
  }
  space("scene.sky.sun_color_space", spec.sky.sun.color_space);
  space("scene.sky.hdri_color_space", spec.sky.hdri_color_space);
  for (size_t i = 0; i < spec.variants.size(); ++i)
    space("variants[" + std::to_string(i) + "].material.palette_space", spec.variants[i].material.palette_space);
}

std::vector<core::MeshView> mesh_views(const ExperimentSpec& spec, double render_scale) {
  std::vector<core::MeshView> views;
  if (!(spec.mesh.max_edge_px > 0.0f)) return views;
  // Every frame of the path, not only those this run renders (--frames, shards): one mesh per
  // experiment and resolution.
  for (int k = 0; k < spec.path.frames(); ++k) {
    const core::FrameCamera cam = spec.path.frame(k, spec.width, spec.height);
    glm::vec3 eye = cam.position;
    if (spec.mesh.motion.moves()) eye = glm::vec3(glm::inverse(spec.mesh.motion.model_at(cam.time)) * glm::vec4(eye, 1.0f));
    views.push_back({eye, float(render_scale * double(spec.height) /
                                (2.0 * std::tan(0.5 * glm::radians(double(cam.state.fov_y_deg)))))});
  }
  return views;
}

SceneData build_scene(const ExperimentSpec& spec, const metrics::ColorManager& cm) {
  SceneData d;
  d.mesh = core::build_mesh(spec.mesh, mesh_views(spec));
  if (spec.mesh.max_edge_px > 0.0f)
    for (const VariantSpec& v : spec.variants)
      if (v.frames.empty() && v.render_scale < 1.0 && v.mesh_lod == "render" && d.render_lods.count(v.render_scale) == 0)
        d.render_lods.emplace(v.render_scale, core::build_mesh(spec.mesh, mesh_views(spec, v.render_scale)));
  d.env = prepare_environment(spec, cm);
  d.env_texture = environment_texture(d.env);
  d.range = distance_range(spec, d.mesh);
  return d;
}

SceneGpus::SceneGpus(const core::VkContext& ctx, const SceneData& data)
    : display_(std::make_unique<core::SceneGpu>(ctx, data.mesh, data.env_texture)) {
  for (const auto& [scale, mesh] : data.render_lods) lods_[scale] = std::make_unique<core::SceneGpu>(ctx, mesh, *display_);
}

const core::SceneGpu& SceneGpus::of(const VariantSpec& v) const {
  const auto it = lods_.find(v.render_scale);
  return v.mesh_lod == "render" && it != lods_.end() ? *it->second : *display_;
}

core::FrameUniforms frame_uniforms(const ExperimentSpec& spec, const SceneData& scene, int k) {
  return frame_uniforms(spec.path.frame(k, spec.width, spec.height), scene.env, spec.width, spec.height,
                        scene.env_texture.mips_rgba.size(), spec.mesh.motion);
}

metrics::ColorManager load_color_manager(const std::string& ocio_config) {
  const std::string path = ocio_config.empty() ? metrics::ColorManager::default_config_path() : ocio_config;
  const char* env = std::getenv("OCIO");
  const std::string what = !ocio_config.empty()        ? "--ocio-config " + path
                           : env && *env                ? "$OCIO=" + path
                                                        : "the shipped OCIO config " + path;
  try {
    return metrics::ColorManager(path);
  } catch (const IoError&) {
    throw;  // libglintlab_ocio.so could not be loaded: the system's reason, not the config's
  } catch (const std::runtime_error& e) {
    throw ConfigError(what + ": not a usable OCIO config (" + e.what() + ")");
  }
}

}  // namespace glintlab

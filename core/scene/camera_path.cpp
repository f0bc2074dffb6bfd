#include "core/scene/camera_path.h"

#include "core/util/json_check.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace glintlab::core {

namespace {

// Built-in paths. experiments/data/paths/<name>.json hold the same text (a test checks that they agree).
// "static-close" and "orbit-close" use the thesis' render-comparison camera: distance 4 at 25°
// elevation (Kajs sec. 6, fig. 6.7): (4 cos 25°, 4 sin 25°) = (3.6252, 1.6905).
const std::map<std::string, const char*>& builtin_json() {
  static const std::map<std::string, const char*> m = {
      {"static-close", R"({
  "type": "static", "fps": 30, "frames": 30,
  "position": [-3.6252, 1.6905, 0.0], "target": [0.0, 0.0, 0.0], "fov": 40
})"},
      {"orbit-close", R"({
  "type": "orbit", "fps": 30, "frames": 60,
  "center": [0.0, 0.0, 0.0], "radius": 3.6252, "height": 1.6905,
  "start_deg": 180, "end_deg": 240, "fov": 40
})"},
      {"dolly-in", R"({
  "type": "dolly", "fps": 30, "frames": 60,
  "from": [-12.0, 4.0, 0.0], "to": [-3.0, 1.2, 0.0], "target": [0.0, 0.0, 0.0],
  "fov": 40, "easing": "smoothstep"
})"},
      {"flyover-dunes", R"({
  "type": "flyover", "fps": 30, "frames": 90,
  "start": [-15.0, -3.0], "direction": [1.0, 0.2], "speed": 3.0, "height": 5.0,
  "pitch_deg": 25, "fov": 50, "far": 1000
})"},
  };
  return m;
}

glm::vec3 vec3_of(JsonReader& r, const std::string& key) {
  auto v = r.get_numbers(key, 3, -1e7, 1e7);
  return {float(v[0]), float(v[1]), float(v[2])};
}

glm::vec3 forward_from(double yaw_deg, double pitch_deg) {
  double y = yaw_deg * M_PI / 180.0, p = pitch_deg * M_PI / 180.0;
  return {float(std::cos(p) * std::cos(y)), float(std::sin(p)), float(std::cos(p) * std::sin(y))};
}

float fov_of(JsonReader& r) { return float(r.get_number("fov", 45.0, 1e-3, 179.0)); }

}  // namespace

std::vector<std::string> CameraPath::builtin_names() {
  std::vector<std::string> names;
  for (const auto& kv : builtin_json()) names.push_back(kv.first);
  return names;
}

CameraPath CameraPath::builtin(const std::string& name) {
  auto it = builtin_json().find(name);
  if (it == builtin_json().end()) {
    std::string all;
    for (const auto& n : builtin_names()) all += (all.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown built-in camera path \"" + name + "\"; built-in paths: " + all);
  }
  nlohmann::json j = nlohmann::json::parse(it->second);
  JsonReader r(j, "<built-in camera path " + name + ">");
  return from_json(r);
}

CameraPath CameraPath::load(const std::string& file) {
  nlohmann::json j = read_json_file(file);
  JsonReader r(j, file);
  return from_json(r);
}

CameraPath CameraPath::from_json(JsonReader& r) {
  CameraPath p;
  p.type_ = r.get_enum("type", {"keyframes", "orbit", "dolly", "flyover", "static"});
  p.fps_ = r.get_number("fps", 1e-3, 1000.0);
  p.frames_ = r.get_int("frames", 1, 1000000);
  p.up_ = glm::vec3(r.has("up") ? vec3_of(r, "up") : glm::vec3(0, 1, 0));
  if (!(glm::length(p.up_) > 0.0f)) r.fail("up", "must not be the zero vector");
  p.near_ = float(r.get_number("near", 0.05, 1e-6, 1e6));
  p.far_ = float(r.get_number("far", 500.0, 1e-6, 1e9));
  if (!(p.far_ > p.near_)) r.fail("far", "must be greater than near");

  if (p.type_ == "keyframes") {
    p.catmull_rom_ = r.get_enum("interpolation", "catmull_rom", {"linear", "catmull_rom"}) == "catmull_rom";
    auto keys = r.array("keyframes", 2);
    for (size_t i = 0; i < keys.size(); ++i) {
      JsonReader& k = keys[i];
      Keyframe kf;
      kf.time = k.get_number("time", -1e9, 1e9);
      if (i > 0 && !(kf.time > p.keys_.back().time))
        k.fail("time", "keyframe times must be strictly increasing; previous time is " +
                           std::to_string(p.keys_.back().time) + ", got " + std::to_string(kf.time));
      kf.position = vec3_of(k, "position");
      bool has_target = k.has("target"), has_orient = k.has("orientation");
      if (has_target == has_orient)
        k.fail(has_target ? "orientation" : "target",
               "give exactly one of \"target\" (look-at point) or \"orientation\" ({yaw_deg, pitch_deg})");
      if (has_target) {
        kf.target = vec3_of(k, "target");
      } else {
        JsonReader o = k.child("orientation");
        double yaw = o.get_number("yaw_deg", -3600.0, 3600.0);
        double pitch = o.get_number("pitch_deg", -90.0, 90.0);
        o.finish();
        kf.target = kf.position + forward_from(yaw, pitch);
      }
      kf.fov_y_deg = fov_of(k);
      kf.cut = k.get_bool("cut", false);
      if (kf.cut && i == 0) k.fail("cut", "the first keyframe cannot be a cut (a cut starts a new shot after another)");
      k.finish();
      p.keys_.push_back(kf);
    }
  } else if (p.type_ == "orbit") {
    p.center_ = vec3_of(r, "center");
    p.radius_ = float(r.get_number("radius", 1e-6, 1e7));
    p.height_ = float(r.get_number("height", 0.0, -1e7, 1e7));
    p.start_deg_ = float(r.get_number("start_deg", -36000.0, 36000.0));
    p.end_deg_ = float(r.get_number("end_deg", -36000.0, 36000.0));
    p.fov_ = fov_of(r);
  } else if (p.type_ == "dolly") {
    p.from_ = vec3_of(r, "from");
    p.to_ = vec3_of(r, "to");
    p.target_ = vec3_of(r, "target");
    p.fov_ = fov_of(r);
    p.smoothstep_ = r.get_enum("easing", "linear", {"linear", "smoothstep"}) == "smoothstep";
  } else if (p.type_ == "flyover") {
    auto s = r.get_numbers("start", 2, -1e7, 1e7);
    auto d = r.get_numbers("direction", 2, -1e7, 1e7);
    p.start2_ = glm::vec2(float(s[0]), float(s[1]));
    glm::dvec2 dd(d[0], d[1]);
    if (!(glm::length(dd) > 1e-9)) r.fail("direction", "must not be the zero vector");
    p.dir2_ = glm::vec2(glm::normalize(dd));
    p.speed_ = float(r.get_number("speed", 0.0, 1e6));
    p.height_ = float(r.get_number("height", -1e7, 1e7));
    bool has_pitch = r.has("pitch_deg"), has_ahead = r.has("look_ahead");
    if (has_pitch && has_ahead) r.fail("look_ahead", "give either \"pitch_deg\" or \"look_ahead\", not both");
    p.use_look_ahead_ = has_ahead;
    if (has_ahead) p.look_ahead_ = float(r.get_number("look_ahead", 1e-6, 1e7));
    else p.pitch_deg_ = float(r.get_number("pitch_deg", 20.0, -89.0, 89.0));
    p.fov_ = fov_of(r);
  } else {  // static
    p.from_ = vec3_of(r, "position");
    p.target_ = vec3_of(r, "target");
    p.fov_ = fov_of(r);
  }
  r.finish();

  // Validate every frame now rather than failing mid-run.
  for (int k = 0; k < p.frames_; ++k) {
    try {
      CameraState c = p.at(p.frame_time(k));
      (void)view_matrix(c);
      (void)projection(c, 1, 1);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(r.file() + ": frame " + std::to_string(k) + " (t = " + std::to_string(p.frame_time(k)) +
                        " s): " + e.what());
    }
  }
  return p;
}

double CameraPath::param(double t) const {
  if (frames_ <= 1) return 0.0;
  return std::clamp(t / duration(), 0.0, 1.0);
}

CameraState CameraPath::at(double t) const {
  CameraState c;
  c.up = up_;
  c.near = near_;
  c.far = far_;
  c.fov_y_deg = fov_;
  if (type_ == "keyframes") {
    const auto& K = keys_;
    const size_t n = K.size();
    if (t <= K.front().time) {
      c.position = K.front().position, c.target = K.front().target, c.fov_y_deg = K.front().fov_y_deg;
      return c;
    }
    if (t >= K.back().time) {
      c.position = K.back().position, c.target = K.back().target, c.fov_y_deg = K.back().fov_y_deg;
      return c;
    }
    // Segment i with t_i <= t < t_{i+1}.
    size_t i = size_t(std::upper_bound(K.begin(), K.end(), t, [](double a, const Keyframe& k) { return a < k.time; }) -
                      K.begin()) - 1;
    if (K[i + 1].cut) {  // the shot ended at key i; the camera holds it until the cut
      c.position = K[i].position, c.target = K[i].target, c.fov_y_deg = K[i].fov_y_deg;
      return c;
    }
    const double h = K[i + 1].time - K[i].time, u = (t - K[i].time) / h;
    c.fov_y_deg = float((1.0 - u) * K[i].fov_y_deg + u * K[i + 1].fov_y_deg);
    auto interp = [&](glm::vec3 Keyframe::*member) -> glm::vec3 {
      glm::dvec3 p0(K[i].*member), p1(K[i + 1].*member);
      if (!catmull_rom_) return glm::vec3((1.0 - u) * p0 + u * p1);
      // Time-knot Catmull-Rom tangents (units per second), one-sided at the ends.
      // A cut key starts a new shot: tangents never reach across it.
      auto tangent = [&](size_t j) {
        size_t a = (j == 0 || K[j].cut) ? j : j - 1, b = (j + 1 == n || K[j + 1].cut) ? j : j + 1;
        return (glm::dvec3(K[b].*member) - glm::dvec3(K[a].*member)) / (K[b].time - K[a].time);
      };
      glm::dvec3 m0 = tangent(i), m1 = tangent(i + 1);
      // Cubic Hermite basis.
      double u2 = u * u, u3 = u2 * u;
      double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
      return glm::vec3(h00 * p0 + h10 * h * m0 + h01 * p1 + h11 * h * m1);
    };
    c.position = interp(&Keyframe::position);
    c.target = interp(&Keyframe::target);
  } else if (type_ == "orbit") {
    double s = param(t);
    double a = (start_deg_ + (end_deg_ - start_deg_) * s) * M_PI / 180.0;
    c.position = center_ + glm::vec3(float(radius_ * std::cos(a)), height_, float(radius_ * std::sin(a)));
    c.target = center_;
  } else if (type_ == "dolly") {
    double s = param(t);
    if (smoothstep_) s = s * s * (3.0 - 2.0 * s);
    c.position = glm::vec3((1.0 - s) * glm::dvec3(from_) + s * glm::dvec3(to_));
    c.target = target_;
  } else if (type_ == "flyover") {
    glm::dvec2 xz = glm::dvec2(start2_) + glm::dvec2(dir2_) * (double(speed_) * t);
    c.position = glm::vec3(float(xz.x), height_, float(xz.y));
    if (use_look_ahead_) {
      c.target = glm::vec3(c.position.x + dir2_.x * look_ahead_, 0.0f, c.position.z + dir2_.y * look_ahead_);
    } else {
      double pr = pitch_deg_ * M_PI / 180.0;
      c.target = c.position + glm::vec3(float(dir2_.x * std::cos(pr)), float(-std::sin(pr)),
                                        float(dir2_.y * std::cos(pr)));
    }
  } else {  // static
    c.position = from_;
    c.target = target_;
  }
  return c;
}

FrameCamera CameraPath::frame(int k, int width, int height, glm::vec2 jitter_px, glm::vec2 prev_jitter_px) const {
  FrameCamera f;
  f.index = k;
  f.time = frame_time(k);
  f.state = at(f.time);
  f.position = f.state.position;
  f.view = view_matrix(f.state);
  f.proj = projection(f.state, width, height, jitter_px);
  f.proj_unjittered = projection(f.state, width, height);
  f.view_proj = f.proj * f.view;
  f.view_proj_unjittered = f.proj_unjittered * f.view;
  f.cut = is_cut(k);
  if (k <= 0 || f.cut) {  // no predecessor in this shot: zero motion
    f.prev_view_proj = f.view_proj;
    f.prev_view_proj_unjittered = f.view_proj_unjittered;
    f.prev_position = f.position;
    f.prev_time = f.time;
  } else {
    f.prev_time = frame_time(k - 1);
    CameraState prev = at(frame_time(k - 1));
    f.prev_position = prev.position;
    glm::mat4 prev_view = view_matrix(prev);
    f.prev_view_proj = projection(prev, width, height, prev_jitter_px) * prev_view;
    f.prev_view_proj_unjittered = projection(prev, width, height) * prev_view;
  }
  return f;
}

bool CameraPath::is_cut(int k) const {
  if (k <= 0) return false;
  const double t0 = frame_time(k - 1), t1 = frame_time(k);
  for (const Keyframe& key : keys_)
    if (key.cut && key.time > t0 && key.time <= t1) return true;
  return false;
}

}  // namespace glintlab::core

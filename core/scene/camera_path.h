// Scripted camera paths, loaded from JSON (experiments/data/paths/*.json) or built in.
//
// Common keys:  "type": "keyframes" | "orbit" | "dolly" | "flyover" | "static"   (required)
//               "fps": frames per second (required, (0, 1000])
//               "frames": frame count (required, [1, 1000000])
//               "up": [x,y,z] camera up (default [0,1,0]), "near" (0.05), "far" (500)
// Frame k is at t_k = k / fps, computed from the integer k (no accumulated drift).
// The "path parameter" s = t / T with T = (frames - 1) / fps runs from 0 at the first frame to 1
// at the last (s = 0 for a 1-frame path); orbit angles and dolly positions are functions of s.
// Angles: azimuth is measured from +X towards +Z (the convention of core/scene/environment.h),
// elevation/pitch upwards from the XZ plane.
//
//  keyframes: "interpolation": "linear" | "catmull_rom" (default "catmull_rom"),
//             "keyframes": [{ "time": s, "position": [3], "target": [3] | "orientation":
//             {"yaw_deg", "pitch_deg"}, "fov": deg (default 45) }, ...]  (>= 2, times strictly
//             increasing). An orientation key becomes target = position + forward(yaw, pitch).
//             Catmull-Rom is the *time-knot (uniform-in-time)* variant, not centripetal: cubic
//             Hermite with tangent m_i = (p_{i+1} - p_{i-1}) / (t_{i+1} - t_{i-1}) at interior keys
//             and one-sided differences at the ends, so it passes through every key and is C1 in
//             time even for unevenly spaced keys (centripetal knots would re-time the path).
//             fov is always interpolated linearly (no overshoot). Outside [t_0, t_last] the
//             end keys hold. A key with "cut": true starts a new shot: the camera holds the
//             previous key until the cut time and jumps there; tangents never reach across a
//             cut, and the first frame of the new shot has no predecessor (zero motion,
//             FrameCamera::cut, temporal passes drop their history).
//  orbit:     "center" [3], "radius" > 0, "height" (above center, default 0), "start_deg",
//             "end_deg", "fov": position = center + (r cos a, height, r sin a), a = lerp(start, end, s),
//             looks at center.
//  dolly:     "from" [3], "to" [3], "target" [3], "fov", "easing": "linear" | "smoothstep".
//  flyover:   over the ground plane y = 0: "start" [x, z], "direction" [x, z] (non-zero),
//             "speed" (units/s), "height", and either "pitch_deg" (look down, default 20) or
//             "look_ahead" (looks at the ground point that far ahead); "fov".
//  static:    "position" [3], "target" [3], "fov".
// Every frame is validated at load (degenerate look-at -> ConfigError naming the frame).
#pragma once

#include "core/scene/camera.h"

#include <string>
#include <vector>

namespace glintlab {
class JsonReader;
}

namespace glintlab::core {

class CameraPath {
 public:
  struct Keyframe {
    double time = 0;
    glm::vec3 position{0.0f}, target{0.0f};
    float fov_y_deg = 45;
    bool cut = false;  // a camera cut: this key starts a new shot
  };

  static CameraPath from_json(JsonReader& r);  // validates; calls r.finish(); throws ConfigError
  static CameraPath load(const std::string& file);
  static std::vector<std::string> builtin_names();
  // The built-in paths; identical to experiments/data/paths/<name>.json. Throws std::invalid_argument.
  static CameraPath builtin(const std::string& name);

  const std::string& type() const { return type_; }
  double fps() const { return fps_; }
  int frames() const { return frames_; }
  double frame_time(int k) const { return double(k) / fps_; }  // t_k = k / fps
  double duration() const { return double(frames_ - 1) / fps_; }  // time of the last frame

  CameraState at(double t) const;
  // True when a cut key lies in (t_{k-1}, t_k]: frame k starts a new shot.
  bool is_cut(int k) const;
  // Camera of frame k (see FrameCamera for the jitter convention). k in [0, frames) is the path;
  // other k evaluate at k / fps with the end keys held.
  FrameCamera frame(int k, int width, int height, glm::vec2 jitter_px = {0, 0},
                    glm::vec2 prev_jitter_px = {0, 0}) const;

 private:
  std::string type_;
  double fps_ = 30;
  int frames_ = 1;
  glm::vec3 up_{0, 1, 0};
  float near_ = 0.05f, far_ = 500.0f;
  // keyframes
  bool catmull_rom_ = true;
  std::vector<Keyframe> keys_;
  // orbit / dolly / flyover / static
  glm::vec3 center_{0.0f}, from_{0.0f}, to_{0.0f}, target_{0.0f};
  float radius_ = 1, height_ = 0, start_deg_ = 0, end_deg_ = 0, fov_ = 45;
  bool smoothstep_ = false;
  glm::vec2 start2_{0.0f}, dir2_{1.0f, 0.0f};
  float speed_ = 1, pitch_deg_ = 20, look_ahead_ = 0;
  bool use_look_ahead_ = false;

  double param(double t) const;  // s in [0, 1]
};

}  // namespace glintlab::core

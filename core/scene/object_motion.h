// Rigid motion of the scene's mesh over time: the model matrix of frame time
// t, so that surface passes can write object motion vectors (the previous
// frame's model matrix moves each vertex back). JSON under "scene.mesh.motion":
//   {"type": "none"}                                                  (default)
//   {"type": "rotate", "axis": [0, 1, 0], "deg_per_s": 30, "center": [0, 0, 0]}
//   {"type": "translate", "velocity": [1, 0, 0]}                      (units per second)
// Rotation is about `axis` through `center`, counter-clockwise seen from the
// tip of the axis (right-handed), angle = deg_per_s * t.
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace glintlab {
class JsonReader;
}

namespace glintlab::core {

struct ObjectMotion {
  std::string type = "none";  // "none" | "rotate" | "translate"
  glm::vec3 axis{0.0f, 1.0f, 0.0f};
  float deg_per_s = 0.0f;
  glm::vec3 center{0.0f};
  glm::vec3 velocity{0.0f};

  static ObjectMotion from_json(JsonReader& r);  // validates; calls r.finish()
  bool moves() const { return type != "none"; }
  glm::mat4 model_at(double t) const;
};

}  // namespace glintlab::core

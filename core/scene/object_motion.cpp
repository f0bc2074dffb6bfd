#include "core/scene/object_motion.h"

#include "core/util/json_check.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace glintlab::core {

ObjectMotion ObjectMotion::from_json(JsonReader& r) {
  ObjectMotion m;
  m.type = r.get_enum("type", "none", {"none", "rotate", "translate"});
  auto vec3 = [&](const char* key, glm::vec3 def) {
    auto v = r.get_numbers(key, std::vector<double>{def.x, def.y, def.z}, -1e6, 1e6);
    return glm::vec3(float(v[0]), float(v[1]), float(v[2]));
  };
  if (m.type == "rotate") {
    m.axis = vec3("axis", m.axis);
    if (!(glm::length(m.axis) > 1e-6f)) r.fail("axis", "must not be the zero vector");
    m.axis = glm::normalize(m.axis);
    m.deg_per_s = float(r.get_number("deg_per_s", -1e5, 1e5));
    m.center = vec3("center", m.center);
  } else if (m.type == "translate") {
    m.velocity = vec3("velocity", m.velocity);
  }
  r.finish();
  return m;
}

glm::mat4 ObjectMotion::model_at(double t) const {
  if (type == "rotate") {
    // The angle is reduced in double before it becomes a float.
    const double deg = std::fmod(double(deg_per_s) * t, 360.0);
    glm::mat4 m = glm::translate(glm::mat4(1.0f), center);
    m = glm::rotate(m, float(deg * M_PI / 180.0), axis);
    return glm::translate(m, -center);
  }
  if (type == "translate") return glm::translate(glm::mat4(1.0f), glm::vec3(glm::dvec3(velocity) * t));
  return glm::mat4(1.0f);
}

}  // namespace glintlab::core

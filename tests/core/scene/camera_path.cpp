// Camera, projection/jitter conventions and scripted camera paths.
#include "core/scene/camera.h"
#include "core/scene/camera_path.h"
#include "core/util/json_check.h"
#include "core/scene/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

using namespace glintlab;
using namespace glintlab::core;

namespace {

CameraPath path_from(const nlohmann::json& j) {
  JsonReader r(j, "test.json");
  return CameraPath::from_json(r);
}

nlohmann::json keyframe_json(const std::string& interpolation) {
  // Uneven times, a sharp turn at every key (so linear has visible kinks).
  return {{"type", "keyframes"}, {"fps", 30}, {"frames", 90}, {"interpolation", interpolation},
          {"keyframes",
           {{{"time", 0.0}, {"position", {0, 1, 5}}, {"target", {0, 0, 0}}},
            {{"time", 0.7}, {"position", {3, 2, 4}}, {"target", {1, 0, 0}}},
            {{"time", 1.2}, {"position", {4, 1, 1}}, {"target", {1, 0.5, -1}}},
            {{"time", 2.5}, {"position", {2, 3, -3}}, {"target", {0, 0, -2}}},
            {{"time", 3.0}, {"position", {-1, 2, -4}}, {"target", {0, 0, 0}}}}}};
}

std::string error_of(const std::string& text) {
  std::string file = ::testing::TempDir() + "glintlab_bad_path.json";
  std::ofstream(file) << text;
  try {
    CameraPath::load(file);
  } catch (const ConfigError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(file), std::string::npos) << "error must name the file: " << msg;
    return msg;
  }
  ADD_FAILURE() << "no ConfigError for " << text;
  return "";
}

bool same(const glm::mat4& a, const glm::mat4& b) { return std::memcmp(&a, &b, sizeof(glm::mat4)) == 0; }

}  // namespace

TEST(CameraPath, CatmullRomPassesThroughEveryKeyframeExactly) {
  auto j = keyframe_json("catmull_rom");
  CameraPath p = path_from(j);
  for (const auto& k : j["keyframes"]) {
    CameraState c = p.at(k["time"].get<double>());
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(c.position[i], k["position"][i].get<float>());
      EXPECT_EQ(c.target[i], k["target"][i].get<float>());
    }
  }
}

TEST(CameraPath, CatmullRomMatchesTheUniformFormulaForEvenlySpacedKeys) {
  // Classic uniform Catmull-Rom (Catmull & Rom 1974) segment P1..P2 as an fp64 reference.
  glm::dvec3 P[4] = {{0, 1, 5}, {3, 2, 4}, {4, 1, 1}, {2, 3, -3}};
  nlohmann::json keys = nlohmann::json::array();
  for (int i = 0; i < 4; ++i)
    keys.push_back({{"time", 0.5 * i}, {"position", {P[i].x, P[i].y, P[i].z}}, {"target", {0, 0, -10}}});
  CameraPath p = path_from({{"type", "keyframes"}, {"fps", 10}, {"frames", 16}, {"keyframes", keys}});
  for (double u : {0.1, 0.25, 0.5, 0.8}) {
    glm::dvec3 ref = 0.5 * (2.0 * P[1] + (-P[0] + P[2]) * u + (2.0 * P[0] - 5.0 * P[1] + 4.0 * P[2] - P[3]) * u * u +
                            (-P[0] + 3.0 * P[1] - 3.0 * P[2] + P[3]) * u * u * u);
    glm::dvec3 got(p.at(0.5 + 0.5 * u).position);
    EXPECT_LT(glm::length(got - ref), 1e-5) << "u = " << u;
  }
}

TEST(CameraPath, CatmullRomIsC1AndLinearIsOnlyC0AtInteriorKeys) {
  CameraPath cr = path_from(keyframe_json("catmull_rom"));
  CameraPath lin = path_from(keyframe_json("linear"));
  const double h = 1e-3;
  double max_cr_jump = 0.0, min_lin_jump = 1e30;
  for (double tk : {0.7, 1.2, 2.5}) {
    for (auto member : {&CameraState::position, &CameraState::target}) {
      auto jump = [&](const CameraPath& p) {
        glm::dvec3 c(p.at(tk).*member), l(p.at(tk - h).*member), r(p.at(tk + h).*member);
        glm::dvec3 dl = (c - l) / h, dr = (r - c) / h;
        // C0: both one-sided neighbours within O(h) of the key.
        EXPECT_LT(glm::length(l - c), 100 * h);
        EXPECT_LT(glm::length(r - c), 100 * h);
        return glm::length(dr - dl);
      };
      max_cr_jump = std::max(max_cr_jump, jump(cr));
      min_lin_jump = std::min(min_lin_jump, jump(lin));
    }
  }
  // One-sided differences of a C1 curve differ by O(h |p''|) (|p''| < 50 here), plus float rounding.
  EXPECT_LT(max_cr_jump, 50 * h + 1e-2);
  EXPECT_GT(min_lin_jump, 1.0);  // the test data has real kinks, so the check above can fail
}

TEST(CameraPath, OrientationKeyframeLooksAlongYawPitch) {
  nlohmann::json j = {{"type", "keyframes"}, {"fps", 30}, {"frames", 10}, {"interpolation", "linear"},
                      {"keyframes",
                       {{{"time", 0.0}, {"position", {0, 1, 0}}, {"orientation", {{"yaw_deg", 90}, {"pitch_deg", -30}}}},
                        {{"time", 1.0}, {"position", {1, 1, 0}}, {"target", {1, 0, 5}}}}}};
  CameraState c = path_from(j).at(0.0);
  glm::vec3 f = glm::normalize(c.target - c.position);
  EXPECT_NEAR(f.x, 0.0f, 1e-6f);  // yaw 90° = +Z (azimuth from +X towards +Z)
  EXPECT_NEAR(f.y, -0.5f, 1e-6f);
  EXPECT_NEAR(f.z, std::sqrt(3.0f) / 2.0f, 1e-6f);
}

TEST(CameraPath, PreviousMatricesAreThoseOfThePreviousFrame) {
  CameraPath p = CameraPath::builtin("orbit-close");
  const int W = 320, H = 180;
  glm::vec2 jit[3] = {{0.25f, -0.25f}, {-0.375f, 0.125f}, {0.0625f, 0.4375f}};
  FrameCamera f0 = p.frame(0, W, H, jit[0], jit[2]);
  EXPECT_TRUE(same(f0.prev_view_proj_unjittered, f0.view_proj_unjittered));  // frame 0: own
  EXPECT_TRUE(same(f0.prev_view_proj, f0.view_proj));
  for (int k = 1; k < 3; ++k) {
    FrameCamera prev = p.frame(k - 1, W, H, jit[k - 1], jit[(k + 1) % 3]);
    FrameCamera cur = p.frame(k, W, H, jit[k], jit[k - 1]);
    EXPECT_TRUE(same(cur.prev_view_proj_unjittered, prev.view_proj_unjittered));
    EXPECT_TRUE(same(cur.prev_view_proj, prev.view_proj));
    EXPECT_FALSE(same(cur.view_proj_unjittered, prev.view_proj_unjittered));  // the camera moves
    EXPECT_EQ(cur.time, double(k) / 30.0);
    EXPECT_EQ(cur.position, cur.state.position);
  }
  // Deterministic frame times from the integer index, far into a long path.
  EXPECT_EQ(p.frame_time(99999), 99999.0 / 30.0);
}

TEST(CameraProjection, JitterMovesTheImageByExactlyThatManyPixels) {
  CameraState c;
  c.position = {1.0f, 2.0f, 6.0f};
  c.target = {0.0f, 0.5f, 0.0f};
  const int W = 400, H = 300;
  glm::mat4 view = view_matrix(c);
  glm::mat4 vp0 = projection(c, W, H) * view;
  // The target projects to the image centre.
  glm::vec2 centre = project_to_pixel(vp0, c.target, W, H);
  EXPECT_NEAR(centre.x, 200.0f, 1e-3f);
  EXPECT_NEAR(centre.y, 150.0f, 1e-3f);
  // World up is up on screen: a point above the target lands on a smaller row (row 0 = top).
  EXPECT_LT(project_to_pixel(vp0, c.target + glm::vec3(0, 0.5f, 0), W, H).y, centre.y - 5.0f);
  for (glm::vec3 p : {glm::vec3(0.3f, 0.1f, -0.4f), glm::vec3(-1.0f, 1.0f, 0.5f)}) {
    glm::vec2 q0 = project_to_pixel(vp0, p, W, H);
    glm::vec2 qx = project_to_pixel(projection(c, W, H, {0.5f, 0.0f}) * view, p, W, H);
    glm::vec2 qy = project_to_pixel(projection(c, W, H, {0.0f, 0.5f}) * view, p, W, H);
    EXPECT_NEAR(qx.x - q0.x, 0.5f, 2e-4f);
    EXPECT_NEAR(qx.y - q0.y, 0.0f, 2e-4f);
    EXPECT_NEAR(qy.x - q0.x, 0.0f, 2e-4f);
    EXPECT_NEAR(qy.y - q0.y, 0.5f, 2e-4f);  // +y jitter moves down (towards larger rows)
  }
  // Vulkan clip depth [0, 1]: near plane -> 0, far plane -> 1.
  glm::mat4 P = projection(c, W, H);
  glm::vec4 n = P * glm::vec4(0, 0, -c.near, 1), f = P * glm::vec4(0, 0, -c.far, 1);
  EXPECT_NEAR(n.z / n.w, 0.0f, 1e-6f);
  EXPECT_NEAR(f.z / f.w, 1.0f, 1e-5f);
}

TEST(CameraProjection, MeshFrontFacesAreVulkanCounterClockwise) {
  // Vulkan spec "Basic Polygon Rasterization": a = -1/2 Σ (x_i y_{i+1} - x_{i+1} y_i) in framebuffer
  // coordinates; with VK_FRONT_FACE_COUNTER_CLOCKWISE a triangle is front-facing iff a > 0.
  MeshSpec s;
  s.type = "sphere";
  s.tessellation = 16;
  s.size = 2.0f;
  Mesh m = build_mesh(s);
  CameraState c;
  c.position = {0.5f, 3.0f, 4.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  const int W = 640, H = 480;
  glm::mat4 vp = projection(c, W, H) * view_matrix(c);
  int front = 0, back = 0, wrong = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    glm::vec3 P[3];
    glm::vec2 q[3];
    for (int i = 0; i < 3; ++i) P[i] = m.vertices[m.indices[t + i]].position, q[i] = project_to_pixel(vp, P[i], W, H);
    double a = 0.0;
    for (int i = 0; i < 3; ++i) a += double(q[i].x) * q[(i + 1) % 3].y - double(q[(i + 1) % 3].x) * q[i].y;
    a *= -0.5;
    glm::vec3 g = glm::cross(P[1] - P[0], P[2] - P[0]);
    bool faces_camera = glm::dot(g, c.position - P[0]) > 0.0f;
    if (std::fabs(a) < 1e-3) continue;  // edge-on
    (faces_camera ? front : back)++;
    if (faces_camera != (a > 0.0)) ++wrong;
  }
  EXPECT_GT(front, 50);
  EXPECT_GT(back, 50);
  EXPECT_EQ(wrong, 0);
}

TEST(CameraProjection, DegenerateCamerasThrowInsteadOfNaN) {
  CameraState c;
  c.position = c.target = {1, 2, 3};
  EXPECT_THROW(view_matrix(c), std::invalid_argument);
  c.position = {0, 5, 0};
  c.target = {0, 0, 0};  // looking straight down with up = +Y
  EXPECT_THROW(view_matrix(c), std::invalid_argument);
  c.up = {0, 0, -1};
  glm::mat4 v = view_matrix(c);
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(v[i][k]));
  EXPECT_THROW(projection(c, 0, 10), std::invalid_argument);
  c.fov_y_deg = 180.0f;
  EXPECT_THROW(projection(c, 10, 10), std::invalid_argument);
  // A path whose camera degenerates names the frame.
  try {
    path_from({{"type", "static"}, {"fps", 24}, {"frames", 2}, {"position", {0, 5, 0}}, {"target", {0, 0, 0}}});
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("frame 0"), std::string::npos) << e.what();
  }
}

TEST(CameraPath, OrbitKeepsItsDistanceAndSweepsStartToEnd) {
  CameraPath p = path_from({{"type", "orbit"}, {"fps", 25}, {"frames", 51}, {"center", {1, 0.5, -2}},
                            {"radius", 3}, {"height", 1.5}, {"start_deg", 0}, {"end_deg", 90}, {"fov", 35}});
  const glm::dvec3 center(1, 0.5, -2);
  for (int k = 0; k < p.frames(); ++k) {
    CameraState c = p.at(p.frame_time(k));
    EXPECT_NEAR(glm::length(glm::dvec3(c.position) - center), std::sqrt(9.0 + 2.25), 1e-5);
    EXPECT_EQ(c.target, glm::vec3(center));
    EXPECT_EQ(c.fov_y_deg, 35.0f);
  }
  glm::dvec3 first = glm::dvec3(p.at(0.0).position) - center, last = glm::dvec3(p.at(p.duration()).position) - center;
  EXPECT_NEAR(first.x, 3.0, 1e-6);  // 0° = +X
  EXPECT_NEAR(first.z, 0.0, 1e-6);
  EXPECT_NEAR(last.x, 0.0, 1e-6);  // 90° = +Z
  EXPECT_NEAR(last.z, 3.0, 1e-6);
}

TEST(CameraPath, DollyAndFlyoverFollowTheirDefinitions) {
  CameraPath d = path_from({{"type", "dolly"}, {"fps", 10}, {"frames", 11}, {"from", {0, 2, 10}},
                            {"to", {0, 1, 2}}, {"target", {0, 0, 0}}, {"easing", "smoothstep"}});
  EXPECT_EQ(d.at(0.0).position, glm::vec3(0, 2, 10));
  EXPECT_EQ(d.at(1.0).position, glm::vec3(0, 1, 2));
  EXPECT_NEAR(d.at(0.5).position.z, 6.0f, 1e-5f);              // smoothstep(0.5) = 0.5
  EXPECT_NEAR(d.at(0.1).position.z, 10.0f - 8.0f * 0.028f, 1e-5f);  // smoothstep(0.1) = 0.028

  CameraPath f = path_from({{"type", "flyover"}, {"fps", 10}, {"frames", 20}, {"start", {-5, 1}},
                            {"direction", {3, 4}}, {"speed", 2}, {"height", 4}, {"look_ahead", 8}});
  CameraState c = f.at(1.5);  // travelled 3 units along (0.6, 0.8)
  EXPECT_NEAR(c.position.x, -5.0f + 1.8f, 1e-5f);
  EXPECT_NEAR(c.position.z, 1.0f + 2.4f, 1e-5f);
  EXPECT_EQ(c.position.y, 4.0f);
  EXPECT_NEAR(c.target.x, c.position.x + 4.8f, 1e-5f);
  EXPECT_EQ(c.target.y, 0.0f);
}

TEST(CameraPath, BuiltinsMatchTheirFilesInExperimentsPaths) {
  auto names = CameraPath::builtin_names();
  ASSERT_GE(names.size(), 3u);
  for (const auto& name : names) {
    CameraPath b = CameraPath::builtin(name);
    CameraPath f = CameraPath::load(std::string(GLINTLAB_EXPERIMENT_DIR) + "/paths/" + name + ".json");
    ASSERT_EQ(b.frames(), f.frames()) << name;
    EXPECT_EQ(b.type(), f.type());
    for (int k = 0; k < b.frames(); ++k) {
      FrameCamera x = b.frame(k, 64, 36), y = f.frame(k, 64, 36);
      EXPECT_TRUE(same(x.view_proj, y.view_proj)) << name << " frame " << k;
    }
  }
  EXPECT_THROW(CameraPath::builtin("nope"), std::invalid_argument);
  EXPECT_NO_THROW(CameraPath::load(std::string(GLINTLAB_EXPERIMENT_DIR) + "/paths/keyframes-sweep.json"));
}

TEST(CameraPath, MalformedFilesNameTheKey) {
  EXPECT_NE(error_of(R"({"type":"static","fps":30,"frames":5,"position":[0,1,5],"target":[0,0,0],"zoom":2})")
                .find("zoom"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type":"static","frames":5,"position":[0,1,5],"target":[0,0,0]})").find("fps"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type":"static","fps":"thirty","frames":5,"position":[0,1,5],"target":[0,0,0]})")
                .find("fps"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type":"spline","fps":30,"frames":5})").find("type"), std::string::npos);
  EXPECT_NE(error_of(R"({"type":"keyframes","fps":30,"frames":5,"keyframes":[
      {"time":0,"position":[0,1,5],"target":[0,0,0]},
      {"time":1,"position":[1,1,5],"target":[0,0,0]},
      {"time":1,"position":[2,1,5],"target":[0,0,0]}]})")
                .find("keyframes[2].time"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type":"keyframes","fps":30,"frames":5,"keyframes":[
      {"time":0,"position":[0,1,5]},{"time":1,"position":[1,1,5],"target":[0,0,0]}]})")
                .find("keyframes[0]"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type":"orbit","fps":30,"frames":5,"center":[0,0],"radius":1,"start_deg":0,"end_deg":1})")
                .find("center"),
            std::string::npos);
}

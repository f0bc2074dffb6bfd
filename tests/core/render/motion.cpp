// Motion vectors and distances of the surface pass (shaders/common/motion.glsl):
// reprojecting frame t-1 along them reproduces frame t of a static scene
// except where the disocclusion mask says the point was hidden or off-screen,
// and a moving object's vectors match its analytic motion.
#include "core/render/surface_pass.h"
#include "core/scene/camera.h"
#include "core/scene/mesh.h"
#include "core/scene/object_motion.h"
#include "metrics/flicker.h"
#include "tests/support/vk_test_util.h"

#include <glm/gtc/matrix_inverse.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace glintlab;

namespace {

core::EnvironmentTexture black_env() {
  core::EnvironmentTexture env;
  env.width = env.height = 1;
  env.mips_rgba = {std::vector<float>(4, 0.0f)};
  return env;
}

core::FrameUniforms uniforms(const core::CameraState& cam, const core::CameraState& prev, int w, int h,
                             const core::ObjectMotion& motion = {}, double t = 0, double t_prev = 0) {
  core::FrameUniforms f;
  f.view_proj = core::projection(cam, w, h) * core::view_matrix(cam);
  f.prev_view_proj = core::projection(prev, w, h) * core::view_matrix(prev);
  f.inv_view_proj = glm::inverse(f.view_proj);
  f.model = motion.model_at(t);
  f.normal_matrix = glm::inverseTranspose(f.model);
  f.prev_model = motion.model_at(t_prev);
  f.camera_pos = glm::vec4(cam.position, 0.0f);
  f.prev_camera_pos = glm::vec4(prev.position, 0.0f);
  f.resolution = glm::vec4(float(w), float(h), 1.0f / float(w), 1.0f / float(h));
  return f;
}

core::SurfacePassOptions position_pass() {
  core::SurfacePassOptions o;
  o.program.fragment = "tests/position.frag";
  o.sky = false;
  o.motion = true;
  return o;
}

std::vector<float> channel(const Image& img, int c) {
  std::vector<float> v(img.pixel_count());
  for (size_t i = 0; i < v.size(); ++i) v[i] = img.data[i * img.channels + size_t(c)];
  return v;
}

}  // namespace

TEST(Motion, ReprojectionReproducesAStaticSceneExceptAtMaskedDisocclusions) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  // Dunes seen low and from the side: ridges hide the ground behind them, and
  // a sideways camera move uncovers some of it.
  core::MeshSpec spec;
  spec.type = "dunes";
  spec.size = 40.0f;
  spec.tessellation = 160;
  spec.amplitude = 2.0f;
  core::Mesh mesh = core::build_mesh(spec);
  core::SceneGpu scene(ctx, mesh, black_env());
  const int w = 160, h = 90;
  core::SurfaceRenderer r(ctx, scene, w, h, position_pass());
  core::CameraState prev, cur;
  prev.position = {-14.0f, 5.0f, -2.0f};
  prev.target = {0.0f, 0.0f, 0.0f};
  cur = prev;
  cur.position = {-14.0f, 5.0f, -1.4f};  // 0.6 units sideways
  const core::SamplePush centre0{core::projection(prev, w, h) * core::view_matrix(prev), {0, 0, 1, 0}};
  const core::SamplePush centre1{core::projection(cur, w, h) * core::view_matrix(cur), {0, 0, 1, 0}};
  core::FrameResult f0 = r.render(uniforms(prev, prev, w, h), {centre0});
  core::FrameResult f1 = r.render(uniforms(cur, prev, w, h), {centre1});
  const Image &pos0 = f0.images.at("color"), &pos1 = f1.images.at("color");
  const Image& m1 = f1.images.at("motion");
  const glm::dmat4 vp1 = glm::dmat4(centre1.view_proj);
  auto to_pixel = [&](glm::dvec3 x) {
    glm::dvec4 c = vp1 * glm::dvec4(x, 1.0);
    return glm::dvec2((c.x / c.w * 0.5 + 0.5) * w, (c.y / c.w * 0.5 + 0.5) * h);
  };
  const auto warp = metrics::reproject(m1, channel(f0.images.at("motion"), 2));
  // Reprojected world position of each pixel's surface point vs where it is now.
  std::vector<std::vector<float>> prev_xyz = {channel(pos0, 0), channel(pos0, 1), channel(pos0, 2)};
  size_t valid = 0, masked = 0, background = 0, masked_hidden = 0, masked_far = 0;
  std::vector<double> err;
  for (size_t i = 0; i < warp.size(); ++i) {
    const glm::dvec3 now(pos1.data[i * 4], pos1.data[i * 4 + 1], pos1.data[i * 4 + 2]);
    if (warp[i].state == metrics::Reprojected::kBackground) {
      ++background;
      continue;
    }
    metrics::Reprojected any = warp[i];
    if (warp[i].state == metrics::Reprojected::kDisoccluded) {
      ++masked;
      // Where the mask flags a point hidden in frame t-1, naive warping lands on another surface.
      const double qx = double(i % w) - m1.data[i * 4], qy = double(i / w) - m1.data[i * 4 + 1];
      if (qx < 0 || qy < 0 || qx > w - 1 || qy > h - 1 || m1.data[i * 4 + 3] <= 0.0f) continue;
      ++masked_hidden;
      const size_t j = size_t(std::lround(qy)) * size_t(w) + size_t(std::lround(qx));
      const glm::dvec3 then(prev_xyz[0][j], prev_xyz[1][j], prev_xyz[2][j]);
      if (glm::length(then - now) > 0.5) ++masked_far;
      continue;
    }
    ++valid;
    const glm::dvec3 then(any.sample(prev_xyz[0]), any.sample(prev_xyz[1]), any.sample(prev_xyz[2]));
    // On screen: where the warped point projects in frame t vs where the surface point is.
    err.push_back(glm::length(to_pixel(then) - to_pixel(now)));
  }
  ASSERT_GT(valid, size_t(w * h / 2));
  EXPECT_GT(masked, 20u) << "the scene must have disocclusions for this test to mean anything";
  EXPECT_GT(background, 0u);
  std::sort(err.begin(), err.end());
  const double median = err[err.size() / 2], p99 = err[err.size() * 99 / 100];
  // Stated bounds, in pixels on screen: half of the points come back within
  // 0.01 px, 99 % within 0.25 px (bilinear interpolation of positions is not
  // exact under perspective, and worst on steep slopes seen at a grazing angle).
  std::printf("reprojection error, pixels: median %.4f, p99 %.4f; %zu valid, %zu masked\n", median, p99,
              valid, masked);
  EXPECT_LT(median, 0.01);
  EXPECT_LT(p99, 0.25);
  // Of the points the mask flags as hidden (not off-screen), naive warping would land most on another surface.
  EXPECT_GT(masked_hidden, 20u);
  EXPECT_GT(double(masked_far), 0.5 * double(masked_hidden)) << masked_far << " of " << masked_hidden;
}

TEST(Motion, MovingObjectVectorsMatchTheAnalyticMotion) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  core::MeshSpec spec;
  spec.type = "sphere";
  spec.size = 2.0f;
  spec.tessellation = 64;
  core::Mesh mesh = core::build_mesh(spec);
  core::SceneGpu scene(ctx, mesh, black_env());
  const int w = 96, h = 64;
  core::SurfaceRenderer r(ctx, scene, w, h, position_pass());
  core::CameraState cam;
  cam.position = {0.3f, 1.0f, 4.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  const glm::dmat4 vp = glm::dmat4(core::projection(cam, w, h) * core::view_matrix(cam));
  auto pixel = [&](glm::dvec3 x) {
    glm::dvec4 c = vp * glm::dvec4(x, 1.0);
    return glm::dvec2((c.x / c.w * 0.5 + 0.5) * w, (c.y / c.w * 0.5 + 0.5) * h);
  };
  for (const char* kind : {"rotate", "translate"}) {
    core::ObjectMotion motion;
    motion.type = kind;
    motion.axis = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));
    motion.deg_per_s = 90.0f;
    motion.center = {0.1f, 0.0f, 0.0f};
    motion.velocity = {1.5f, 0.3f, 0.0f};
    const double t = 1.0, t_prev = 1.0 - 1.0 / 30.0;
    const core::SamplePush s{glm::mat4(vp), {0, 0, 1, 0}};
    core::FrameResult f = r.render(uniforms(cam, cam, w, h, motion, t, t_prev), {s});
    const Image &pos = f.images.at("color"), &m = f.images.at("motion");
    // The object-space point under each pixel, moved back to where it was.
    const glm::dmat4 back = glm::dmat4(motion.model_at(t_prev)) * glm::inverse(glm::dmat4(motion.model_at(t)));
    double worst = 0.0;
    size_t n = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float* p = pos.px(x, y);
        if (p[3] == 0.0f) continue;  // no surface
        const glm::dvec3 now(p[0], p[1], p[2]);
        const glm::dvec3 then = glm::dvec3(back * glm::dvec4(now, 1.0));
        const glm::dvec2 v = pixel(now) - pixel(then);
        worst = std::max(worst, glm::length(v - glm::dvec2(m.at(x, y, 0), m.at(x, y, 1))));
        EXPECT_NEAR(m.at(x, y, 3), glm::length(then - glm::dvec3(cam.position)), 1e-4) << kind;
        ++n;
      }
    EXPECT_GT(n, size_t(w * h / 8)) << kind;
    EXPECT_LT(worst, 2e-3) << kind << ": largest difference from the analytic vector, pixels";
  }
}

TEST(Motion, SkyVectorsAreTheCameraRotation) {
  // The sky is at infinity: between two frames that turn the camera (and move
  // it, which must not matter), a sky pixel's vector is where its view
  // direction now was on the previous frame's screen, in pixels; distances 0.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  core::MeshSpec spec;
  spec.type = "plane";
  spec.size = 20.0f;
  spec.tessellation = 4;
  core::Mesh mesh = core::build_mesh(spec);
  core::SceneGpu scene(ctx, mesh, black_env());
  const int w = 96, h = 64;
  core::SurfacePassOptions o = position_pass();
  o.sky = true;
  core::SurfaceRenderer r(ctx, scene, w, h, o);
  core::CameraState prev, cur;
  prev.position = {0.0f, 1.0f, 0.0f};
  prev.target = {0.3f, 1.6f, -5.0f};
  cur.position = {0.5f, 1.2f, -0.3f};
  cur.target = {-1.4f, 2.1f, -5.0f};
  const glm::dmat4 vp = glm::dmat4(core::projection(cur, w, h) * core::view_matrix(cur));
  const glm::dmat4 vp_prev = glm::dmat4(core::projection(prev, w, h) * core::view_matrix(prev));
  const core::FrameUniforms u = uniforms(cur, prev, w, h);
  const glm::dmat4 inv = glm::dmat4(u.inv_view_proj);  // the fp32 inverse the sky's rays come from
  const core::FrameResult f = r.render(u, {core::SamplePush{glm::mat4(vp), {0, 0, 1, 0}}});
  const Image& m = f.images.at("motion");
  double worst = 0.0;
  size_t n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (m.at(x, y, 2) != 0.0f) continue;  // a surface
      const double nx = (x + 0.5) / w * 2.0 - 1.0, ny = (y + 0.5) / h * 2.0 - 1.0;
      const glm::dvec4 a = inv * glm::dvec4(nx, ny, 0.0, 1.0), b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
      const glm::dvec3 dir = glm::dvec3(b) / b.w - glm::dvec3(a) / a.w;
      auto pixel = [&](const glm::dmat4& m4, glm::dvec3 d) {
        const glm::dvec4 c = m4 * glm::dvec4(d, 0.0);
        EXPECT_GT(c.w, 0.0) << "the test's turn keeps the sky in front of both cameras";
        return glm::dvec2((c.x / c.w * 0.5 + 0.5) * w, (c.y / c.w * 0.5 + 0.5) * h);
      };
      const glm::dvec2 v = pixel(vp, dir) - pixel(vp_prev, dir);
      worst = std::max(worst, glm::length(v - glm::dvec2(m.at(x, y, 0), m.at(x, y, 1))));
      EXPECT_EQ(m.at(x, y, 3), 0.0f);
      ++n;
    }
  EXPECT_GT(n, size_t(w * h / 4)) << "the view must show sky";
  // The sky's rays are unprojected from NDC depths 0 and 1 in fp32 (passes/sky.vert), good to about
  // 1e-4 relative with this camera's near and far planes: 0.011 px on a 30-pixel turn, before and
  // after the vectors moved to the vertex stage. A wrong vector (this frame's matrix for both: 76 px
  // here) is off by pixels.
  EXPECT_LT(worst, 0.05) << "largest difference from the analytic vector, pixels";
}

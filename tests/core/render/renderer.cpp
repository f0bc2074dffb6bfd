// The forward renderer on lavapipe: exact readback at odd sizes, an analytic
// shader against a CPU fp64 evaluation pixel by pixel, and sample
// accumulation.
#include "core/scene/camera.h"
#include "core/scene/mesh.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "tests/support/vk_test_util.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

using namespace glintlab;

namespace {

core::EnvironmentTexture constant_env(float v) {
  core::EnvironmentTexture env;
  env.width = 8;
  env.height = 4;
  for (uint32_t w = 8, h = 4; ; w = std::max(1u, w / 2), h = std::max(1u, h / 2)) {
    env.mips_rgba.emplace_back(size_t(w) * h * 4, v);
    if (w == 1 && h == 1) break;
  }
  return env;
}

core::Mesh big_plane() {
  core::MeshSpec spec;
  spec.type = "plane";
  spec.size = 200.0f;
  spec.tessellation = 4;
  return core::build_mesh(spec);
}

core::FrameUniforms uniforms_for(const glm::mat4& view_proj, int w, int h, glm::vec3 eye) {
  core::FrameUniforms f;
  f.view_proj = view_proj;
  f.inv_view_proj = glm::inverse(view_proj);
  f.prev_view_proj = view_proj;
  f.camera_pos = glm::vec4(eye, 0.0f);
  f.resolution = glm::vec4(float(w), float(h), 1.0f / float(w), 1.0f / float(h));
  return f;
}

// A surface pass with a test shader and no sky.
core::SurfacePassOptions surface_options(const std::string& fragment) {
  core::SurfacePassOptions o;
  o.program.fragment = fragment;
  o.sky = false;
  return o;
}

const Image& color(const core::FrameResult& r) { return r.images.at("color"); }

// Two concentric sphere shells (radius 1 and 1 - spacing) on the device under
// a constant sky, and a camera that sees the outer one whole with its
// view-projection at w x h: four surfaces behind most pixels, or two
// coincident ones with spacing 0.
struct LayeredSphere {
  core::Mesh mesh;
  core::SceneGpu scene;
  core::CameraState cam;
  glm::mat4 vp;

  LayeredSphere(core::VkContext& ctx, int tessellation, float spacing, float sky, int w, int h)
      : mesh(shells(tessellation, spacing)), scene(ctx, mesh, constant_env(sky)), cam(camera()),
        vp(core::projection(cam, w, h) * core::view_matrix(cam)) {}

  static core::Mesh shells(int tessellation, float spacing) {
    core::MeshSpec spec;
    spec.type = "sphere";
    spec.size = 2.0f;  // radius 1
    spec.tessellation = tessellation;
    spec.layers = 2;
    spec.layer_spacing = spacing;
    return core::build_mesh(spec);
  }
  static core::CameraState camera() {
    core::CameraState c;
    c.position = {0.4f, 0.9f, 3.2f};
    c.target = {0.0f, 0.0f, 0.0f};
    c.fov_y_deg = 50.0f;
    return c;
  }
};

// One sample per jitter offset (pixels), each weighted 1/N.
std::vector<core::SamplePush> jittered_samples(const core::CameraState& cam, int w, int h,
                                               const std::vector<glm::vec2>& offsets) {
  std::vector<core::SamplePush> samples;
  for (size_t i = 0; i < offsets.size(); ++i)
    samples.push_back({core::projection(cam, w, h, offsets[i]) * core::view_matrix(cam),
                       {offsets[i].x, offsets[i].y, 1.0f / float(offsets.size()), float(i)}});
  return samples;
}

}  // namespace

TEST(Renderer, ReadbackOfOddSizeIsExact) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 97, h = 61;
  core::Mesh mesh = big_plane();
  core::SceneGpu scene(ctx, mesh, constant_env(0.0f));
  core::SurfaceRenderer pass(ctx, scene, w, h, surface_options("tests/fragcoord.frag"));
  core::CameraState cam;
  cam.position = {0.0f, 10.0f, 0.001f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.fov_y_deg = 90.0f;
  glm::mat4 vp = core::projection(cam, w, h) * core::view_matrix(cam);
  core::SamplePush s{vp, {0, 0, 1, 0}};
  auto out = pass.render(uniforms_for(vp, w, h, cam.position), {s});
  ASSERT_EQ(color(out).width, w);
  ASSERT_EQ(color(out).height, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = color(out).px(x, y);
      ASSERT_EQ(p[0], float(x)) << x << "," << y;
      ASSERT_EQ(p[1], float(y)) << x << "," << y;
      ASSERT_EQ(p[2], float(y * 1000 + x)) << x << "," << y;
      ASSERT_EQ(p[3], 1.0f);
    }
  ASSERT_EQ(out.timings.size(), 1u);
  EXPECT_GT(out.timings[0].gpu_ms, 0.0);
}

TEST(Renderer, AnalyticShaderMatchesFp64PixelByPixel) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 160, h = 90;
  core::Mesh mesh = big_plane();
  core::SceneGpu scene(ctx, mesh, constant_env(0.0f));
  core::SurfaceRenderer pass(ctx, scene, w, h, surface_options("tests/analytic.frag"));
  core::CameraState cam;
  cam.position = {0.3f, 2.0f, 4.5f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.fov_y_deg = 60.0f;
  glm::mat4 vp = core::projection(cam, w, h) * core::view_matrix(cam);
  auto out = pass.render(uniforms_for(vp, w, h, cam.position), {core::SamplePush{vp, {0, 0, 1, 0}}});

  glm::dmat4 inv = glm::inverse(glm::dmat4(vp));
  int compared = 0, sky = 0;
  double max_pos_err = 0, max_f_err = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Pixel centre in NDC (pixel convention of core/scene/camera.h), ray to the plane y = 0.
      double nx = (x + 0.5) / w * 2.0 - 1.0, ny = (y + 0.5) / h * 2.0 - 1.0;
      glm::dvec4 a = inv * glm::dvec4(nx, ny, 0.0, 1.0), b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
      glm::dvec3 p0 = glm::dvec3(a) / a.w, p1 = glm::dvec3(b) / b.w;
      glm::dvec3 d = p1 - p0;
      const float* px = color(out).px(x, y);
      double t = d.y < 0 ? -p0.y / d.y : -1.0;
      if (t < 0 || t > 1) {  // misses the plane: nothing drawn
        EXPECT_EQ(px[3], 0.0f) << x << "," << y;
        ++sky;
        continue;
      }
      glm::dvec3 X = p0 + t * d;
      if (std::abs(X.x) > 99 || std::abs(X.z) > 99) continue;  // past the plane's edge
      double f = std::exp(-0.1 * glm::length(X)) * (1.0 + 0.5 * std::sin(3.0 * X.x) * std::cos(2.0 * X.z));
      EXPECT_EQ(px[3], 1.0f);
      max_pos_err = std::max({max_pos_err, std::abs(px[0] - X.x) / (1 + std::abs(X.x)),
                              std::abs(px[1] - X.z) / (1 + std::abs(X.z))});
      max_f_err = std::max(max_f_err, std::abs(px[2] - f));
      ++compared;
    }
  EXPECT_GT(compared, w * h / 2);
  EXPECT_GT(sky, 0);
  // fp32 rasterisation + perspective-correct interpolation vs fp64 ray casting.
  EXPECT_LT(max_pos_err, 2e-4) << "world position differs from the fp64 ray-plane hit";
  EXPECT_LT(max_f_err, 2e-4);
}

TEST(Renderer, JitteredSamplesAverageWithWeights) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 33, h = 17;
  core::Mesh mesh = big_plane();
  core::SceneGpu scene(ctx, mesh, constant_env(0.0f));
  core::SurfaceRenderer pass(ctx, scene, w, h, surface_options("tests/fragcoord.frag"));
  core::CameraState cam;
  cam.position = {0.0f, 10.0f, 0.001f};
  cam.fov_y_deg = 90.0f;
  auto offsets = core::stratified_offsets(4, 7u);
  ASSERT_EQ(offsets.size(), 16u);
  std::vector<core::SamplePush> samples;
  for (size_t i = 0; i < offsets.size(); ++i) {
    EXPECT_GE(offsets[i].x, -0.5f);
    EXPECT_LT(offsets[i].x, 0.5f);
    glm::mat4 vp = core::projection(cam, w, h, offsets[i]) * core::view_matrix(cam);
    samples.push_back({vp, {offsets[i].x, offsets[i].y, 1.0f / 16.0f, float(i)}});
  }
  glm::mat4 vp0 = core::projection(cam, w, h) * core::view_matrix(cam);
  auto out = pass.render(uniforms_for(vp0, w, h, cam.position), samples);
  // Each sample writes the index of the pixel it lands in, which is the pixel
  // itself for |jitter| < 0.5: the weighted mean is exact, and coverage is 1.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      EXPECT_NEAR(color(out).at(x, y, 0), float(x), 1e-5f);
      EXPECT_NEAR(color(out).at(x, y, 3), 1.0f, 1e-6f);
    }
  EXPECT_EQ(out.timings[0].pass, "surface");
}

TEST(Renderer, OnlyTheNearestOfOverlappingSurfacesIsAccumulated) {
  // A layered sphere: two concentric shells seen through each other, four
  // surfaces behind most pixels, drawn in mesh order (inner shell after the
  // outer). Each sample must add exactly one fragment: coverage 1 and the
  // colour of the nearest hit (fp64 ray-sphere), for 1 and for 9 samples.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 96, h = 64;
  const LayeredSphere s(ctx, 192, 0.3f, 0.0f, w, h);  // inner shell radius 0.7
  core::SurfaceRenderer pass(ctx, s.scene, w, h, surface_options("tests/analytic.frag"));
  glm::dmat4 inv = glm::inverse(glm::dmat4(s.vp));
  for (int n : {1, 3}) {
    const std::vector<core::SamplePush> samples = jittered_samples(
        s.cam, w, h, n == 1 ? std::vector<glm::vec2>{glm::vec2(0.0f)} : core::stratified_offsets(n, 3u));
    auto out = pass.render(uniforms_for(s.vp, w, h, s.cam.position), samples);
    int interior = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float* px = color(out).px(x, y);
        ASSERT_LE(px[3], 1.0f + 1e-5f) << "more than one fragment accumulated at " << x << "," << y;
        if (n != 1) continue;
        double nx = (x + 0.5) / w * 2.0 - 1.0, ny = (y + 0.5) / h * 2.0 - 1.0;
        glm::dvec4 a = inv * glm::dvec4(nx, ny, 0.0, 1.0), b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
        glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::normalize(glm::dvec3(b) / b.w - o);
        double bq = glm::dot(o, d), c = glm::dot(o, o) - 1.0, disc = bq * bq - c;
        if (disc < 0.05) continue;  // misses the outer shell or grazes its tessellated silhouette
        glm::dvec3 X = o + (-bq - std::sqrt(disc)) * d;  // nearest hit: the outer shell
        EXPECT_EQ(px[3], 1.0f) << x << "," << y;
        EXPECT_NEAR(px[0], X.x, 5e-3) << x << "," << y;
        EXPECT_NEAR(px[1], X.z, 5e-3) << x << "," << y;
        ++interior;
      }
    if (n == 1) {
      EXPECT_GT(interior, w * h / 8);
    }
  }
}

TEST(Renderer, SupersampledPassEqualsOnePassPerSample) {
  // The reference's supersampled mode (f = 3: one geometry pass serves the 9
  // samples of a 3x3 grid per pixel, then a box filter) against nine ordinary
  // passes at the same sample positions, on the layered sphere whose nearest
  // surfaces the test above checks against fp64 ray casting. Same positions,
  // same nearest surfaces: the images agree up to fp32 rounding of the
  // interpolation and the rare silhouette sample that the two raster
  // resolutions snap differently; and no pixel accumulates two fragments.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 96, h = 64, f = 3;
  const LayeredSphere s(ctx, 192, 0.3f, 0.0f, w, h);
  core::FrameUniforms uniforms = uniforms_for(s.vp, w, h, s.cam.position);

  core::SurfacePassOptions ss_opt = surface_options("tests/analytic.frag");
  ss_opt.supersample = f;
  core::SurfaceRenderer ss_pass(ctx, s.scene, w, h, ss_opt);
  auto ss = ss_pass.render(uniforms, {core::SamplePush{s.vp, {0.0f, 0.0f, 1.0f, 0.0f}}});

  // The high-resolution pixel centres of one low-resolution pixel, as jitters.
  std::vector<core::SamplePush> samples;
  for (int j = 0; j < f; ++j)
    for (int i = 0; i < f; ++i) {
      glm::vec2 o((i + 0.5f) / f - 0.5f, (j + 0.5f) / f - 0.5f);
      samples.push_back({core::projection(s.cam, w, h, o) * core::view_matrix(s.cam),
                         {o.x, o.y, 1.0f / float(f * f), float(samples.size())}});
    }
  core::SurfaceRenderer ref_pass(ctx, s.scene, w, h, surface_options("tests/analytic.frag"));
  auto per_sample = ref_pass.render(uniforms, samples);

  int differing = 0, covered = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* a = color(ss).px(x, y);
      const float* b = color(per_sample).px(x, y);
      ASSERT_LE(a[3], 1.0f + 1e-5f) << "more than one fragment accumulated at " << x << "," << y;
      if (b[3] > 0.0f) ++covered;
      float d = 0.0f;
      for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(a[c] - b[c]));
      if (d > 1e-4f) ++differing;
    }
  EXPECT_GT(covered, w * h / 8);
  // A silhouette pixel differs when one of its nine samples is snapped to the
  // other side of an edge: a few per cent of the covered pixels at most.
  EXPECT_LT(differing, covered / 50) << differing << " of " << covered << " covered pixels differ";
}

// The supersampled pass's checkerboard halves (option `halves`: the means of each pixel's f x f
// block's cells with i + j even and odd) on glinting sand, where samples differ: the colour target is
// the same bits as the pass without halves; (n_a A + n_b B) / f^2 is that mean within fp32 summation
// order (stated bound 1e-6 relative + 1e-7; the block's sum in another order); the halves differ
// wherever the block's samples do (they are two estimates, not one copied); and with an odd f the
// halves hold ceil and floor of f^2 / 2 cells. The option needs supersample >= 2.
TEST(Renderer, SupersampledHalvesAreTwoEstimatesWhoseMeanIsTheTarget) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 64, h = 40;
  const LayeredSphere s(ctx, 96, 0.3f, 0.0f, w, h);
  const core::FrameUniforms uniforms = uniforms_for(s.vp, w, h, s.cam.position);
  for (int f : {4, 3}) {
    core::SurfacePassOptions plain = surface_options("tests/analytic.frag");
    plain.supersample = f;
    core::SurfacePassOptions split = plain;
    split.halves = true;
    const std::vector<core::SamplePush> one = {core::SamplePush{s.vp, {0.0f, 0.0f, 1.0f, 0.0f}}};
    core::SurfaceRenderer a_pass(ctx, s.scene, w, h, plain), b_pass(ctx, s.scene, w, h, split);
    const core::FrameResult ra = a_pass.render(uniforms, one), rb = b_pass.render(uniforms, one);
    const Image &full = color(ra), &same = color(rb), &half_a = rb.images.at("color.a"), &half_b = rb.images.at("color.b");
    const double na = (f * f + 1) / 2, nb = (f * f) / 2;
    size_t differ_bits = 0, outside = 0, halves_differ = 0;
    for (size_t i = 0; i < full.data.size(); ++i) {
      differ_bits += std::memcmp(&full.data[i], &same.data[i], sizeof(float)) != 0;
      const double mean = (na * half_a.data[i] + nb * half_b.data[i]) / double(f * f);
      outside += std::abs(mean - full.data[i]) > 1e-6 * std::abs(full.data[i]) + 1e-7;
      halves_differ += half_a.data[i] != half_b.data[i];
    }
    EXPECT_EQ(differ_bits, 0u) << "f = " << f;
    EXPECT_EQ(outside, 0u) << "f = " << f;
    EXPECT_GT(halves_differ, full.data.size() / 20) << "f = " << f;
  }
  core::SurfacePassOptions bad = surface_options("tests/analytic.frag");
  bad.halves = true;
  EXPECT_THROW(core::SurfacePass(ctx, s.scene, bad), core::VulkanError);
}

TEST(Renderer, OneOpaqueSampleWithSkyRewritesEveryPixelWithoutAClear) {
  // With one opaque sample and the sky on, the pass skips clearing colour and
  // motion: every pixel must be written by the nearest surface or the sky. A
  // frame that looks straight down (surface everywhere) and then one towards
  // the horizon (sky above it) must give exactly what a fresh pass gives for
  // the second frame: a pixel neither wrote would keep the first frame's value.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 96, h = 64;
  core::Mesh mesh = big_plane();
  core::SceneGpu scene(ctx, mesh, constant_env(2.5f));
  core::SurfacePassOptions o;
  o.program.fragment = "tests/position.frag";
  o.single_sample = true;
  o.motion = true;
  ASSERT_TRUE(o.sky);
  auto frame = [&](glm::vec3 eye, glm::vec3 target) {
    core::CameraState cam;
    cam.position = eye;
    cam.target = target;
    cam.fov_y_deg = 50.0f;
    glm::mat4 vp = core::projection(cam, w, h) * core::view_matrix(cam);
    return std::make_pair(uniforms_for(vp, w, h, eye), core::SamplePush{vp, {0, 0, 1, 0}});
  };
  const auto down = frame({0.0f, 5.0f, 0.01f}, {0.0f, 0.0f, 0.0f});
  const auto horizon = frame({0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, -10.0f});
  auto coverage = [&](const core::FrameResult& r) {
    int surface = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) surface += color(r).at(x, y, 3) == 1.0f;
    return surface;
  };

  core::SurfaceRenderer reused(ctx, scene, w, h, o);
  ASSERT_EQ(coverage(reused.render(down.first, {down.second})), w * h) << "the first frame must be all surface";
  const core::FrameResult second = reused.render(horizon.first, {horizon.second});
  core::SurfaceRenderer fresh(ctx, scene, w, h, o);
  const core::FrameResult expected = fresh.render(horizon.first, {horizon.second});
  const int surface = coverage(expected);
  EXPECT_GT(surface, w * h / 4);
  EXPECT_LT(surface, w * h * 3 / 4) << "the second frame must show sky too";
  for (const char* target : {"color", "motion"}) {
    const Image& a = second.images.at(target);
    const Image& b = expected.images.at(target);
    ASSERT_EQ(a.data.size(), b.data.size());
    size_t differing = 0;
    for (size_t i = 0; i < a.data.size(); ++i) differing += std::memcmp(&a.data[i], &b.data[i], sizeof(float)) != 0;
    EXPECT_EQ(differing, 0u) << target << ": values left from the previous frame";
  }
}

TEST(Renderer, CoincidentSurfacesAccumulateOneFragmentPerSample) {
  // Two identical shells (layer spacing 0): every covered pixel has two
  // fragments at exactly the same depth. Depth test EQUAL alone would shade
  // both and add them (alpha 2); each sample must add exactly one, in every
  // mode of the pass: one opaque sample, opaque samples summed by the add pass
  // (one and four), and blended samples (pre-pass, EQUAL and stencil: with
  // motion vectors, and supersampled), with the sky on so that it must not add
  // onto a surface either.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 64, h = 48;
  const LayeredSphere s(ctx, 64, 0.0f, 0.0f, w, h);
  struct Mode {
    const char* name;
    int samples, supersample;
    bool single, motion;
  };
  for (Mode m : {Mode{"one opaque sample", 1, 1, true, false}, Mode{"one summed sample", 1, 1, false, false},
                 Mode{"4 summed samples", 4, 1, false, false}, Mode{"4 blended samples", 4, 1, false, true},
                 Mode{"supersampled 2x2", 1, 2, false, false}}) {
    core::SurfacePassOptions o;
    o.program.fragment = "tests/position.frag";  // alpha = weight; also writes motion
    o.motion = m.motion;
    o.single_sample = m.single;
    o.supersample = m.supersample;
    core::SurfaceRenderer pass(ctx, s.scene, w, h, o);
    const std::vector<core::SamplePush> samples = jittered_samples(
        s.cam, w, h, m.samples == 1 ? std::vector<glm::vec2>{glm::vec2(0.0f)} : core::stratified_offsets(2, 5u));
    auto out = pass.render(uniforms_for(s.vp, w, h, s.cam.position), samples);
    int covered = 0, doubled = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float a = color(out).at(x, y, 3);
        covered += a > 0.0f;
        doubled += a > 1.0f + 1e-5f;
      }
    EXPECT_GT(covered, w * h / 8) << m.name;
    EXPECT_EQ(doubled, 0) << m.name << ": pixels that accumulated both coincident fragments";
  }
}

TEST(Renderer, SumOfOpaqueSamplesEqualsBlendedAccumulation) {
  // Several samples without motion vectors are each drawn opaque into the
  // pass's own image and added to the colour target by a blended draw; with
  // motion vectors they are blended after a depth pre-pass (EQUAL + stencil).
  // Both add the same fragments in the same order: equal colour, bit for bit,
  // on the layered sphere (four surfaces behind most pixels), sky on.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 96, h = 64;
  const LayeredSphere s(ctx, 96, 0.3f, 0.25f, w, h);
  const std::vector<core::SamplePush> samples = jittered_samples(s.cam, w, h, core::stratified_offsets(3, 7u));
  core::SurfacePassOptions summed;
  summed.program.fragment = "tests/position.frag";  // colour = world position (it also writes motion)
  core::SurfacePassOptions blended = summed;
  blended.motion = true;
  const core::FrameUniforms u = uniforms_for(s.vp, w, h, s.cam.position);
  const Image a = color(core::SurfaceRenderer(ctx, s.scene, w, h, summed).render(u, samples));
  const Image b = color(core::SurfaceRenderer(ctx, s.scene, w, h, blended).render(u, samples));
  ASSERT_EQ(a.data.size(), b.data.size());
  size_t differing = 0, covered = 0, sky = 0;
  for (size_t i = 0; i < a.data.size(); ++i) differing += std::memcmp(&a.data[i], &b.data[i], sizeof(float)) != 0;
  for (size_t px = 0; px < a.pixel_count(); ++px) {
    covered += a.data[px * 4 + 3] > 0.0f;
    sky += a.data[px * 4 + 3] < 1.0f && a.data[px * 4] > 0.0f;
  }
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(covered, a.pixel_count() / 8);
  EXPECT_GT(sky, 0u) << "some pixels must mix surface and sky samples or show sky";
}

TEST(Renderer, CulledChunksLeaveTheImageUnchanged) {
  // The surface pass draws only the mesh chunks a sample's view can see. On a
  // wavy plane seen from inside (part of it behind and beside the camera), in
  // every mode (one opaque sample with and without motion, a sum of opaque
  // samples, blended samples with motion, a supersampled pass), and looking
  // up at the sky (nothing to draw): colour and motion equal the unculled
  // pass bit for bit, and culling left triangles out.
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const int w = 96, h = 64;
  core::MeshSpec spec;
  spec.type = "wavy";
  spec.size = 10.0f;
  spec.tessellation = 64;
  spec.amplitude = 0.4f;
  spec.wavelength = 5.0f;
  const core::Mesh mesh = core::build_mesh(spec);
  ASSERT_EQ(mesh.chunks.size(), 64u);
  const core::SceneGpu scene(ctx, mesh, constant_env(0.5f));
  core::CameraState cam;
  cam.position = {-1.0f, 1.2f, 0.5f};
  cam.fov_y_deg = 40.0f;
  struct Mode {
    const char* name;
    bool single, motion;
    int supersample, samples;
  };
  for (const glm::vec3 target : {glm::vec3(3.0f, 0.0f, -1.0f), glm::vec3(0.0f, 10.0f, 0.6f)}) {
    cam.target = target;
    const bool sky_only = target.y > 1.0f;
    const glm::mat4 vp = core::projection(cam, w, h) * core::view_matrix(cam);
    const core::FrameUniforms u = uniforms_for(vp, w, h, cam.position);
    for (const Mode m : {Mode{"one opaque sample", true, false, 1, 1}, Mode{"one opaque sample, motion", true, true, 1, 1},
                         Mode{"sum of opaque samples", false, false, 1, 4},
                         Mode{"blended samples, motion", false, true, 1, 4}, Mode{"supersampled", false, false, 2, 1}}) {
      SCOPED_TRACE(std::string(m.name) + (sky_only ? ", sky only" : ""));
      core::SurfacePassOptions o;
      o.program.fragment = "tests/position.frag";
      o.single_sample = m.single;
      o.motion = m.motion;
      o.supersample = m.supersample;
      const std::vector<core::SamplePush> samples =
          m.samples == 1 ? std::vector<core::SamplePush>{core::SamplePush{vp, {0.0f, 0.0f, 1.0f, 0.0f}}}
                         : jittered_samples(cam, w, h, core::stratified_offsets(2, 3u));
      core::SurfaceRenderer culled(ctx, scene, w, h, o);
      o.cull = false;
      core::SurfaceRenderer all(ctx, scene, w, h, o);
      const core::FrameResult a = culled.render(u, samples), b = all.render(u, samples);
      for (const char* target_name : {"color", "motion"}) {
        if (!a.images.count(target_name)) continue;
        const Image &x = a.images.at(target_name), &y = b.images.at(target_name);
        ASSERT_EQ(x.data.size(), y.data.size());
        EXPECT_EQ(std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)), 0) << target_name;
      }
      size_t covered = 0;
      for (size_t px = 0; px < color(a).pixel_count(); ++px) covered += color(a).data[px * 4 + 3] > 0.0f;
      const uint64_t drawn = culled.pass().triangles_drawn(), total = culled.pass().triangles_submitted_without_culling();
      EXPECT_EQ(total, mesh.indices.size() / 3 * samples.size());
      EXPECT_EQ(all.pass().triangles_drawn(), total);
      if (sky_only) {
        EXPECT_EQ(covered, 0u);
        EXPECT_EQ(drawn, 0u);
      } else {
        EXPECT_GT(covered, color(a).pixel_count() / 2);
        EXPECT_GT(drawn, 0u);
        EXPECT_LT(drawn, total / 2) << "most of the plane is behind or beside the camera";
      }
    }
  }
}

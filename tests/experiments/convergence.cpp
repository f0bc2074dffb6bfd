// The reference estimator converges at the Monte Carlo rate: on a glint-free
// output (the diffuse term: grain palette and porosity, discontinuous at grain
// edges) the RMS error of N uniformly jittered samples per pixel against a
// 32x32-sample reference falls like 1/sqrt(N), and the stratified estimator
// used for references is at least as good.
#include "core/scene/mesh.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

using namespace glintlab;

namespace {

const char* kScene = R"({
  "resolution": [48, 27],
  "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 16, "amplitude": 0.4, "wavelength": 5}},
  "camera_path": {"type": "static", "fps": 30, "frames": 1, "position": [0, 1.5, 3], "target": [0, 0, 0], "fov": 40},
  "material": {"preset": "thesis-default", "noise_scale": 60, "sigmoid_b": 100,
               "palette": [[0.9,0.7,0.5],[0.2,0.2,0.2],[0.8,0.6,0.4],[0.5,0.5,0.5],[1,1,1],[0.3,0.25,0.2],[0.6,0.5,0.3],[0.1,0.1,0.1]]},
  "variants": [{"name": "diffuse", "debug": "diffuse"}]
})";

double rms_error(const Image& a, const Image& b) {
  double s = 0;
  for (size_t i = 0; i < a.data.size(); i += 4)
    for (int c = 0; c < 3; ++c) s += (a.data[i + c] - b.data[i + c]) * double(a.data[i + c] - b.data[i + c]);
  return std::sqrt(s / double(a.pixel_count() * 3));
}

}  // namespace

TEST(ReferenceConvergence, ErrorFallsLikeInverseSqrtSpp) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  ExperimentSpec spec = ExperimentSpec::from_json(nlohmann::json::parse(kScene), "inline-test");
  metrics::ColorManager cm;
  core::Mesh mesh = core::build_mesh(spec.mesh);
  core::Environment env = prepare_environment(spec, cm);
  core::EnvironmentTexture tex = environment_texture(env);
  core::SceneGpu scene(ctx, mesh, tex);
  core::SandParams params = to_working_space(spec.variants[0].material, spec.working_space, cm);
  core::SandFeatures needs = distance_range(spec, mesh);
  needs.debug_output = "diffuse";
  const int w = spec.width, h = spec.height;
  core::SurfacePassOptions opt;
  opt.program = core::sand_program(params, needs, core::ProgramRole::Variant);
  core::SurfaceRenderer pass(ctx, scene, w, h, opt);
  core::FrameCamera cam0 = spec.path.frame(0, w, h);
  core::FrameUniforms fu = frame_uniforms(cam0, env, w, h, tex.mips_rgba.size());

  auto render = [&](const std::vector<glm::vec2>& offsets) {
    std::vector<core::SamplePush> s;
    for (size_t i = 0; i < offsets.size(); ++i)
      s.push_back({spec.path.frame(0, w, h, offsets[i]).view_proj,
                   {offsets[i].x, offsets[i].y, 1.0f / float(offsets.size()), float(i)}});
    return pass.render(fu, s).images.at("color");
  };
  Image ref = render(core::stratified_offsets(32, 99u));

  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  std::vector<double> log_n, log_e;
  double prev_strat = INFINITY;
  for (int n : {1, 4, 16, 64}) {
    // Mean squared error over a few independent seeds (the expectation the rate is about).
    double mse = 0;
    const int trials = 4;
    for (int t = 0; t < trials; ++t) {
      std::vector<glm::vec2> offs(n);
      for (auto& o : offs) o = {u(rng), u(rng)};
      double e = rms_error(render(offs), ref);
      mse += e * e / trials;
    }
    log_n.push_back(std::log(double(n)));
    log_e.push_back(0.5 * std::log(mse));
    int g = int(std::lround(std::sqrt(double(n))));
    double strat = rms_error(render(core::stratified_offsets(g, 7u + uint32_t(n))), ref);
    EXPECT_LE(strat, std::sqrt(mse) * 1.15) << "stratified worse than uniform at n = " << n;
    EXPECT_LT(strat, prev_strat);
    prev_strat = strat;
  }
  // Least-squares slope of log RMSE against log N.
  double mx = 0, my = 0;
  for (size_t i = 0; i < log_n.size(); ++i) mx += log_n[i] / log_n.size(), my += log_e[i] / log_e.size();
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < log_n.size(); ++i) sxy += (log_n[i] - mx) * (log_e[i] - my), sxx += (log_n[i] - mx) * (log_n[i] - mx);
  double slope = sxy / sxx;
  EXPECT_NEAR(slope, -0.5, 0.1) << "RMS error should fall like N^-1/2";
  EXPECT_GT(std::exp(log_e.front()), 1e-3) << "the test scene must have sub-pixel detail to converge";
}

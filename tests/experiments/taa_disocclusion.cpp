// The TAA resolve's disocclusion test (option `disocclusion`, passes/taa.frag same_surface), counted
// pixel by pixel through the count of accumulated frames the resolve keeps (taa.state.y with
// `accumulate`: n = k + 1 at frame k where the history was kept every frame, 1 where it restarted):
//  - a static, jittered camera over a plane seen down to the horizon, where the distance changes by
//    more than the tolerance within a pixel: the pixels that see the plane keep their history;
//  - a static, jittered camera over dunes whose ridges stand against the dunes behind them: the
//    edges keep their history and converge to supersampling's edge profile;
//  - a square moving over a still background, and a camera cut: exactly the pixels a CPU
//    computation from the square's positions names restart;
// and the accumulation schedule on the horizon view ends within 1.1x the CIEDE2000 of
// supersampling with as many samples (validation on throughout).
#include "core/render/frame_graph.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"
#include "experiments/runner/runner.h"
#include "experiments/sources/variant_factory.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "experiments/stress/render_util.h"
#include "metrics/color/color_manager.h"

#include "tests/support/csv.h"
#include "tests/support/temp_dir.h"
#include "tests/support/vk_test_util.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace glintlab;
using nlohmann::json;

namespace {

constexpr int kW = 160, kH = 90;

// Sand seen from `camera` (a static path), glints as `glints` (0: off, so edges are geometry alone).
json sand_view(const json& mesh, const json& camera, double glints) {
  return {{"name", "disocclusion-test"},
          {"resolution", {kW, kH}},
          {"scene",
           {{"mesh", mesh},
            {"sky",
             {{"turbidity", 2.5}, {"sky_intensity", 0.5}, {"sun_elevation_deg", 12}, {"sun_azimuth_deg", 10},
              {"sun_intensity", 5}}}}},
          {"camera_path", camera},
          {"material",
           {{"preset", "thesis-hdri-match"}, {"noise_scale", 120}, {"glint_sigma", 0.002},
            {"I_glints", {glints, glints, glints}}, {"sigmoid_a", 2}, {"sigmoid_b", 1000}}},
          {"variants", json::array({json{{"name", "taa"}, {"aa", "taa"}}})},
          {"output", {{"exr", false}, {"png", false}, {"every", 1}}}};
}

// A plane of 200 units, the eye half a unit above it looking 4 degrees down: most pixels see the
// sand at 80-89.9 degrees from its normal, where the distance to the eye changes by 5-100 % from
// one pixel to the next, and the plane's far edge stands against the sky near the horizon.
json horizon_view(int frames) {
  const double down = std::tan(4.0 * M_PI / 180.0) * 10.0;
  return sand_view({{"type", "plane"}, {"size", 200}, {"tessellation", 16}},
                   {{"type", "static"}, {"fps", 30}, {"frames", frames}, {"position", {0, 0.5, 0}},
                    {"target", {10, 0.5 - down, 1.5}}, {"fov", 45}},
                   20);
}

// Dunes seen low over their crests: ridges stand against the dunes behind them and the sky.
json ridge_view(int frames, double glints) {
  return sand_view({{"type", "dunes"}, {"size", 80}, {"tessellation", 160}, {"amplitude", 3}, {"wavelength", 24},
                    {"octaves", 3}, {"gain", 0.4}, {"seed", 3}},
                   {{"type", "static"}, {"fps", 30}, {"frames", frames}, {"position", {-30, 4.5, -4}},
                    {"target", {0, 2.0, 2}}, {"fov", 35}},
                   glints);
}

core::TaaSettings accumulating(core::JitterSequence jitter) {
  core::TaaSettings s;  // the 1/n schedule with no rectification: the mean of the frames since a restart
  s.jitter = jitter;
  s.set("clamp", "none");
  s.set("feedback", "fixed");
  s.set("alpha", 1.0 / 64);
  s.set("accumulate", true);
  s.set("disocclusion", true);
  return s;
}

// Every frame of `e`'s path through a surface pass and `settings`' resolve: taa.color, taa.state
// (y = the frames accumulated) and the motion target (the jittered sample's surface distance in z).
struct Frames {
  std::vector<Image> color, state, motion;
};
Frames resolve(const json& e, const core::TaaSettings& settings) {
  core::VkContext& ctx = test::shared_context();
  const ExperimentSpec spec = ExperimentSpec::from_json(e, "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  const core::MaterialProgram program =
      core::sand_program(spec.variants[0].material, data.range, core::ProgramRole::Variant);
  core::FrameGraph graph(ctx, spec.width, spec.height);
  core::SurfacePassOptions o;
  o.program = program;
  o.single_sample = true;
  o.motion = true;
  graph.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  graph.add(std::make_unique<core::TaaPass>(ctx, settings));
  graph.build({"taa.color", "taa.state", "motion"});
  Frames out;
  for (int k = 0; k < spec.frames; ++k) {
    core::FrameInputs in;
    in.frame = k;
    in.uniforms = frame_uniforms(spec, data, k);
    in.samples = core::samples_for(spec.path, k, spec.width, spec.height, {core::jitter_offset(settings.jitter, k)});
    core::FrameResult r = graph.execute(in);
    out.color.push_back(std::move(r.images.at("taa.color")));
    out.state.push_back(std::move(r.images.at("taa.state")));
    out.motion.push_back(std::move(r.images.at("motion")));
  }
  return out;
}

// One frame of `e` at frame 0 through a surface pass with the given sample offsets ("color").
Image render(const json& e, const std::vector<glm::vec2>& offsets, bool motion = false) {
  core::VkContext& ctx = test::shared_context();
  const ExperimentSpec spec = ExperimentSpec::from_json(e, "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  core::FrameGraph graph(ctx, spec.width, spec.height);
  core::SurfacePassOptions o;
  o.program = motion ? core::geometry_only_program()
                     : core::sand_program(spec.variants[0].material, data.range, core::ProgramRole::Variant);
  o.single_sample = offsets.size() == 1;
  o.motion = motion;
  graph.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  graph.build({motion ? "motion" : "color"});
  core::FrameInputs in;
  in.uniforms = frame_uniforms(spec, data, 0);
  in.samples = core::samples_for(spec.path, 0, spec.width, spec.height, offsets);
  return graph.execute(in).images.at(motion ? "motion" : "color");
}

// Pixels whose every pixel within Chebyshev distance `r` sees a surface (motion z > 0) in every frame:
// the history's lookups of such a pixel (its 3x3, reprojected by under a pixel of jitter change) see
// that surface only.
std::vector<char> on_surface_throughout(const std::vector<Image>& motion, int r) {
  const int w = motion[0].width, h = motion[0].height;
  std::vector<char> keep(size_t(w) * h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (const Image& m : motion)
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int i = std::clamp(x + dx, 0, w - 1), j = std::clamp(y + dy, 0, h - 1);
            if (!(m.at(i, j, 2) > 0.0f)) keep[size_t(y) * w + x] = 0;
          }
  return keep;
}

double luma(const Image& im, int x, int y) {
  return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

}  // namespace

// A surface seen down to the horizon under a static, jittered camera: nothing is disoccluded, yet
// the distance of a jittered sample differs from last frame's by more than the 5 % tolerance on
// most of the plane (comparing the two point samples within 5 % would restart them). Every pixel whose neighbourhood sees the plane in every frame must keep its history in
// every frame (bound: 99.9 % of them; the count is printed). The pixels at the plane's far edge,
// which see the sky in some frames, are left out.
TEST(TaaDisocclusion, AStaticJitteredCameraKeepsTheHistoryOfASurfaceSeenToTheHorizon) {
  test::ValidationGuard guard(test::shared_context());
  for (core::JitterSequence jitter : {core::JitterSequence::Halton16, core::JitterSequence::R2}) {
    const Frames f = resolve(horizon_view(17), accumulating(jitter));
    const std::vector<char> surface = on_surface_throughout(f.motion, 2);
    size_t counted = 0;
    for (char c : surface) counted += c;
    ASSERT_GT(counted, size_t(kW * kH / 3)) << "the plane fills the lower half of the frame";
    for (size_t k = 1; k < f.state.size(); ++k) {
      size_t kept = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          if (surface[size_t(y) * kW + x]) kept += f.state[k].at(x, y, 1) == float(k + 1);
      const double share = double(kept) / double(counted);
      if (k == 1 || k + 1 == f.state.size())
        std::printf("%s frame %zu: %zu of %zu plane pixels kept their history (%.4f %%)\n",
                    enum_name(core::kJitterNames, jitter), k, kept, counted, 100.0 * share);
      EXPECT_GE(share, 0.999) << "frame " << k;
    }
  }
}

// The 1/n schedule under a static camera is the mean of its jittered frames; where the test keeps
// the history, that is supersampling with as many samples. On the horizon view, 64 frames of R2
// jitter against 8x8 supersampling (64 samples a pixel), both against a truth of 32x32 = 1024
// samples (16x as many): the schedule's CIEDE2000 at its last frame within 1.1x supersampling's.
TEST(TaaDisocclusion, TheScheduleOnAHorizonViewEndsWithinATenthOfSupersampling) {
  json e = horizon_view(64);
  e["reference"] = {{"grid", 32}};
  e["metrics"] = {"deltaE2000"};
  json schedule = {{"clamp", "none"}, {"feedback", "fixed"}, {"alpha", 0.015625}, {"accumulate", true},
              {"disocclusion", true}, {"jitter", "r2"}};
  e["variants"] = {{{"name", "ssaa-8x8"}, {"aa", "ssaa"}, {"ssaa_grid", 8}},
                   {{"name", "taa-accumulate"}, {"aa", "taa"}, {"taa", schedule}}};
  const test::TempDir tmp("taa_horizon_schedule");
  std::ofstream(tmp.path() / "e.json") << e.dump(2);
  RunOptions opt;
  opt.report = false;
  opt.experiment = (tmp.path() / "e.json").string();
  opt.out_dir = (tmp.path() / "out").string();
  opt.cache_dir = (tmp.path() / "cache").string();
  opt.validation = true;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  double taa = NAN, ssaa = NAN;
  for (const auto& row : test::read_csv_rows(tmp.path() / "out" / "frames.csv"))
    if (row.at("frame") == "63") (row.at("variant") == "ssaa-8x8" ? ssaa : taa) = std::stod(row.at("deltaE2000"));
  std::printf("deltaE2000 at frame 63: schedule %.4f, 8x8 supersampling %.4f (ratio %.3f)\n", taa, ssaa, taa / ssaa);
  EXPECT_LE(taa, 1.1 * ssaa);
}

// Ridges against the dunes behind them, static camera: the resolve's distance is the nearest of the
// pixel's 3x3, so an edge pixel whose jittered sample falls on either side still holds the ridge and
// keeps its history; after 64 frames of R2 jitter its colour is the mean of 64 samples across the
// edge, as 8x8 supersampling's. Glints off (geometry edges alone). On the edge pixels (3x3 distance
// ratio above 1.25, or sky beside sand, from the unjittered distances), the mean |luma difference|
// to 8x8 supersampling is at most 1/4 of one centre sample's (measured: printed), and no pixel of the
// frame restarts.
TEST(TaaDisocclusion, RidgeEdgesUnderAStaticJitteredCameraConvergeToSupersampling) {
  test::ValidationGuard guard(test::shared_context());
  const json e = ridge_view(64, 0);
  const Frames f = resolve(e, accumulating(core::JitterSequence::R2));
  const Image ssaa = render(e, core::stratified_offsets(8, kSsaaPatternSeed));
  const Image centre = render(e, {glm::vec2(0.0f)});
  const Image motion = render(e, {glm::vec2(0.0f)}, true);
  size_t edges = 0, restarted = 0;
  double err_taa = 0, err_centre = 0;
  for (int y = 1; y + 1 < kH; ++y)
    for (int x = 1; x + 1 < kW; ++x) {
      float lo = INFINITY, hi = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const float z = motion.at(x + dx, y + dy, 2);
          lo = std::min(lo, z);
          hi = std::max(hi, z);
        }
      restarted += f.state.back().at(x, y, 1) != 64.0f;
      if (!(hi > 1.25f * lo)) continue;  // sky (0) beside sand, or a jump of distance: an edge
      ++edges;
      err_taa += std::abs(luma(f.color.back(), x, y) - luma(ssaa, x, y));
      err_centre += std::abs(luma(centre, x, y) - luma(ssaa, x, y));
    }
  std::printf("%zu edge pixels: mean |luma - 8x8 SSAA| schedule %.4g, one centre sample %.4g (ratio %.3f); "
              "%zu pixels restarted\n",
              edges, err_taa / double(edges), err_centre / double(edges), err_taa / err_centre, restarted);
  ASSERT_GT(edges, size_t(100)) << "the view must show ridges against what lies behind them";
  EXPECT_LE(err_taa, 0.25 * err_centre);
  EXPECT_EQ(restarted, 0u);
}

// A square moving (3, 2) pixels a frame over a still background (shaders/tests/taa_stress.frag),
// then a camera cut. The resolve's distance is the nearest of the 3x3 (the square, within a pixel
// of it), so the pixels that must restart in frame k are those within a pixel of the square in
// frame k-1 and not in frame k (the background it uncovered; its own pixels reproject onto its
// last position); every pixel at the first frame and at the cut. Counted exactly against the
// resolve's count of accumulated frames.
TEST(TaaDisocclusion, AMovingSquareAndACameraCutRestartExactlyThePixelsTheyShould) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  constexpr int W = 64, H = 48, kSide = 12, kCut = 5, kFrames = 8;
  const glm::vec2 step(3.0f, 2.0f);
  auto corner = [&](int k) { return glm::vec2(8.0f, 6.0f) + float(k % kCut) * step; };  // restarts at the cut
  auto near_square = [&](int k, int x, int y) {  // within one pixel (Chebyshev) of the square
    const glm::vec2 c = corner(k);
    return x >= c.x - 1 && x <= c.x + kSide && y >= c.y - 1 && y <= c.y + kSide;
  };
  auto mesh = std::make_shared<const core::Mesh>(stress::plane_mesh(40, 2));
  core::SceneGpu scene(ctx, *mesh, stress::constant_env(0.0f));
  core::CameraState cam;
  cam.position = {0.0f, 3.0f, 0.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.up = {0.0f, 0.0f, -1.0f};
  cam.fov_y_deg = 60;
  core::FrameGraph g(ctx, W, H);
  core::SurfacePassOptions o;
  o.program.fragment = "tests/taa_stress.frag";
  o.sky = false;
  o.motion = true;
  g.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  core::TaaSettings s = accumulating(core::JitterSequence::None);
  s.set("velocity", "closest_depth");
  g.add(std::make_unique<core::TaaPass>(ctx, s));
  g.build({"taa.state"});
  for (int k = 0; k < kFrames; ++k) {
    core::FrameInputs in;
    in.frame = k;
    in.camera_cut = k == kCut;
    in.uniforms = stress::frame_uniforms(cam, W, H, stress::Lighting{});
    in.uniforms.sun_dir = glm::vec4(0.0f, 0.0f, float(k + 1), 0.0f);  // constant colour
    in.uniforms.env_sh[1] = glm::vec4(corner(k), float(kSide), 1.0f);
    in.uniforms.env_sh[2] = glm::vec4(k % kCut == 0 ? glm::vec2(0.0f) : step, 2.0f, 5.0f);
    in.samples = stress::samples(cam, W, H);
    const Image state = g.execute(in).images.at("taa.state");
    size_t want = 0, got = 0, wrong = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const bool restart = k == 0 || k == kCut || (near_square(k - 1, x, y) && !near_square(k, x, y));
        const float n = state.at(x, y, 1);
        const bool restarted = n == 1.0f;
        want += restart;
        got += restarted;
        wrong += restart != restarted;
      }
    std::printf("frame %d: %zu pixels restarted, %zu expected, %zu differ\n", k, got, want, wrong);
    EXPECT_EQ(wrong, 0u) << "frame " << k;
    if (k > 0 && k != kCut) {
      EXPECT_GT(want, size_t(0)) << "the square uncovers background every frame";
    }
  }
}

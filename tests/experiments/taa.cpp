// TAA and flicker end to end through the runner (real Vulkan on lavapipe,
// validation on): every TAA option compiles, runs and lands in frames.csv;
// the resolve's quads that share their neighbourhood fetches give the bits of
// fetching every texel;
// under a static camera TAA without rectification converges toward the
// reference; and on orbits over glinting sand the flicker ratio ranks one
// sample per pixel above 2x2 above 4x4 supersampling, all above the truth.
#include "core/render/frame_graph.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"
#include "experiments/runner/runner.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"

#include "tests/support/temp_dir.h"
#include "tests/support/vk_test_util.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using namespace glintlab;
using nlohmann::json;

namespace {

// Glinting sand on a wavy plane seen from the thesis' comparison camera. A
// narrow field of view keeps the pixel footprint of the 640x360 default at a
// fraction of its cost.
json glint_scene(int w, int h, const json& path) {
  return {{"resolution", {w, h}},
          {"scene",
           {{"mesh", {{"type", "wavy"}, {"size", 10}, {"tessellation", 64}, {"amplitude", 0.4}, {"wavelength", 5}}},
            {"sky",
             {{"turbidity", 3}, {"sky_intensity", 0.5}, {"sun_elevation_deg", 25}, {"sun_azimuth_deg", 30},
              {"sun_intensity", 6}}}}},
          {"camera_path", path},
          {"material",
           {{"preset", "thesis-hdri-match"}, {"noise_scale", 400}, {"glint_sigma", 0.002}, {"I_glints", {20, 20, 20}},
            {"sigmoid_a", 2}, {"sigmoid_b", 6}}},
          {"output", {{"exr", false}, {"png", false}, {"every", 1}}}};
}

json orbit(double deg_per_frame, int frames, double fov) {
  return {{"type", "orbit"}, {"fps", 30},       {"frames", frames},       {"center", {0, 0, 0}},
          {"radius", 3.6252}, {"height", 1.6905}, {"start_deg", 180}, {"end_deg", 180 + deg_per_frame * (frames - 1)},
          {"fov", fov}};
}

// Runs `experiment` in `dir` (a TempDir of the calling test, which outlives the files read afterwards).
json run(const json& experiment, const fs::path& dir) {
  std::ofstream(dir / "e.json") << experiment.dump(2);
  RunOptions opt;
  opt.report = false;  // the report has its own test (report.cpp)
  opt.experiment = (dir / "e.json").string();
  opt.out_dir = (dir / "out").string();
  opt.cache_dir = (dir / "cache").string();
  opt.validation = true;
  std::ostringstream log;
  EXPECT_EQ(run_experiment(opt, log), 0) << log.str();  // 0 also means no validation message
  std::ifstream in(dir / "out" / "summary.json");
  json s = json::parse(in);
  s["_csv"] = (dir / "out" / "frames.csv").string();
  return s;
}

double metric(const json& summary, const std::string& variant, const std::string& name) {
  for (const auto& v : summary["variants"])
    if (v["name"] == variant) return v["metrics"][name]["mean"].get<double>();
  ADD_FAILURE() << "no variant " << variant;
  return NAN;
}

}  // namespace

TEST(Taa, EveryOptionRunsAndAppearsInFramesCsv) {
  json e = glint_scene(48, 27, orbit(1.0, 3, 40));
  e["name"] = "taa-options";
  e["reference"] = {{"grid", 2}};
  e["metrics"] = {"deltaE2000"};
  json variants = json::array({{{"name", "taa-default"}, {"aa", "taa"}}});
  const std::map<std::string, std::vector<json>> options = {
      {"jitter", {"none", "halton8", "halton16", "halton32", "r2"}},
      {"clamp", {"none", "minmax", "clip", "variance"}},
      {"space", {"rgb", "ycocg"}},
      {"history_filter", {"bilinear", "catmull_rom"}},
      {"velocity", {"center", "closest_depth", "longest"}},
      {"feedback", {"fixed", "luma", "karis"}},
      {"hdr", {"none", "inverse_luma", "tonemap"}},
      {"anti_flicker", {true}},
      {"dering", {true}},
      {"alpha", {0.04}},
      {"gamma", {1.25}},
      {"accumulate", {true}},
      {"reactive", {0.5}},
      {"glint_layer", {true}},
      {"glint_lock", {true}},
      {"disocclusion", {true}}};
  for (const auto& [key, values] : options)
    for (const auto& v : values) {
      std::string name = "taa-" + key + "-" + (v.is_string() ? v.get<std::string>() : v.dump());
      for (char& c : name)
        if (c == '.') c = 'p';
      variants.push_back({{"name", name}, {"aa", "taa"}, {"taa", {{key, v}}}});
    }
  // The glint layer's own keys, and every target of the resolve at once (taa.luma and taa.extra).
  variants.push_back({{"name", "taa-glint-everything"},
                      {"aa", "taa"},
                      {"taa",
                       {{"glint_layer", true}, {"glint_alpha", 0.3}, {"glint_clamp", "minmax"}, {"accumulate", true},
                        {"reactive", 0.25}, {"glint_lock", true}, {"anti_flicker", true}}}});
  e["variants"] = variants;
  const glintlab::test::TempDir tmp("taa_options");
  json s = run(e, tmp.path());
  ASSERT_EQ(s["variants"].size(), variants.size());
  for (const auto& v : s["variants"]) {
    EXPECT_EQ(v["metrics"]["nonfinite_pixels"]["max"], 0) << v["name"];
    EXPECT_EQ(v["metrics"]["negative_pixels"]["max"], 0) << v["name"];
    EXPECT_TRUE(v["gpu_ms_per_pass"].contains("taa")) << v["name"];
    EXPECT_TRUE(v["gpu_ms_per_pass"].contains("surface")) << v["name"];
  }
  // One row per variant and frame, with the TAA pass's own GPU time.
  std::ifstream csv(s["_csv"].get<std::string>());
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find("gpu_ms_taa"), std::string::npos) << header;
  std::map<std::string, int> rows;
  while (std::getline(csv, line)) ++rows[line.substr(0, line.find(','))];
  for (const auto& v : variants) EXPECT_EQ(rows[v["name"].get<std::string>()], 3) << v["name"];
}

TEST(Taa, StaticCameraConvergesTowardTheReference) {
  // Static camera, 65 frames: TAA with no rectification and a small alpha
  // averages its jittered samples. Stated factor: at frame 64 its CIEDE2000
  // against the 16x16-sample truth is within 1.5x that of 4x4 supersampling
  // (1.24x measured at this setting; an exponential moving average weighs the
  // jitter positions of a cycle unevenly, so it stays above a uniform 4x4
  // average) and below one centre sample.
  json path = {{"type", "static"}, {"fps", 30},  {"frames", 65}, {"position", {-3.6252, 1.6905, 0.0}},
               {"target", {0, 0, 0}}, {"fov", 40}};
  json e = glint_scene(128, 72, path);
  e["name"] = "static-convergence-test";
  e["reference"] = {{"grid", 16}};
  e["metrics"] = {"deltaE2000"};
  e["variants"] = {{{"name", "no-aa"}},
                   {{"name", "ssaa-4x4"}, {"aa", "ssaa"}, {"ssaa_grid", 4}},
                   {{"name", "taa"}, {"aa", "taa"}, {"taa", {{"clamp", "none"}, {"alpha", 0.05}, {"feedback", "fixed"}}}}};
  const glintlab::test::TempDir tmp("taa_static");
  json s = run(e, tmp.path());
  std::ifstream csv(s["_csv"].get<std::string>());
  std::string line;
  std::getline(csv, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) header.push_back(c);
  }
  const size_t col = size_t(std::find(header.begin(), header.end(), "deltaE2000") - header.begin());
  std::map<std::pair<std::string, int>, double> de;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    de[{cells[0], std::stoi(cells[1])}] = std::stod(cells[col]);
  }
  const double taa64 = de[{"taa", 64}], taa8 = de[{"taa", 8}], taa0 = de[{"taa", 0}];
  const double ssaa = de[{"ssaa-4x4", 64}], none = de[{"no-aa", 64}];
  std::printf("deltaE2000 at frame 64: taa %.4f (frame 8: %.4f), ssaa-4x4 %.4f, no-aa %.4f; ratio %.3f\n", taa64,
              taa8, ssaa, none, taa64 / ssaa);
  EXPECT_LT(taa64, 1.5 * ssaa);
  EXPECT_LT(taa64, none);
  EXPECT_LT(taa64, taa8);  // converging
  EXPECT_LT(taa64, taa0);
}

TEST(Taa, FlickerRatioRanksSupersamplingOnGlintingOrbitsAtTwoSpeeds) {
  // The ordering a viewer sees: one sample per pixel flickers most, 4x4 least,
  // all more than the truth. At 0.5 and 1.5 degrees of orbit per frame
  // (measured: 3.75 > 2.24 > 1.59 and 2.85 > 2.00 > 1.32). The one-sided excess
  // ranks them alike; TAA's loss is lag (the truth's change it lacks), not
  // added flicker.
  for (double speed : {0.5, 1.5}) {
    json e = glint_scene(160, 90, orbit(speed, 6, 10));
    e["name"] = "glint-orbit-test";
    e["reference"] = {{"grid", 16}};
    e["metrics"] = {"deltaE2000"};
    e["variants"] = {{{"name", "no-aa"}},
                     {{"name", "ssaa-2x2"}, {"aa", "ssaa"}, {"ssaa_grid", 2}},
                     {{"name", "ssaa-4x4"}, {"aa", "ssaa"}, {"ssaa_grid", 4}},
                     {{"name", "taa"}, {"aa", "taa"}}};
    const glintlab::test::TempDir tmp("taa_orbit");
    json s = run(e, tmp.path());
    const double f1 = metric(s, "no-aa", "flicker_ratio"), f2 = metric(s, "ssaa-2x2", "flicker_ratio"),
                 f4 = metric(s, "ssaa-4x4", "flicker_ratio");
    std::printf("orbit %.1f deg/frame: flicker ratio no-aa %.3f, 2x2 %.3f, 4x4 %.3f\n", speed, f1, f2, f4);
    EXPECT_GT(f1, f2) << speed;
    EXPECT_GT(f2, f4) << speed;
    EXPECT_GT(f4, 1.0) << speed;
    const double x1 = metric(s, "no-aa", "flicker_excess"), x2 = metric(s, "ssaa-2x2", "flicker_excess"),
                 x4 = metric(s, "ssaa-4x4", "flicker_excess");
    const double taa_excess = metric(s, "taa", "flicker_excess"), taa_lag = metric(s, "taa", "temporal_lag");
    const double lag1 = metric(s, "no-aa", "temporal_lag");
    std::printf("  flicker excess no-aa %.4g, 2x2 %.4g, 4x4 %.4g; lag no-aa %.4g; taa excess %.4g, lag %.4g\n", x1, x2,
                x4, lag1, taa_excess, taa_lag);
    EXPECT_GT(x1, x2) << speed;
    EXPECT_GT(x2, x4) << speed;
    // TAA reads as "smooth but lagging", one sample per pixel as "twinkles too much": TAA's lag is a
    // far larger share of its temporal mismatch. Its excess is about a tenth of no AA's (the current
    // one-sample frame enters the history with weight 0.1); where the truth itself changes enough
    // (the faster orbit) its lag is the larger of the two.
    EXPECT_GT(taa_lag / taa_excess, 5.0 * lag1 / x1) << speed;
    EXPECT_LT(taa_excess, 0.2 * x1) << speed;
    if (speed > 1.0) {
      EXPECT_GT(taa_lag, taa_excess) << speed;
    }
  }
}

// passes/taa.frag with TAA_QUAD_SHARE: the pixels of a 2x2 quad take five of
// their nine neighbours' colours and motions from the other pixels of the
// quad. Over a moving, jittered orbit of glinting sand (history, disocclusions,
// the variance box, every velocity choice, anti-flicker's lumas) the resolve
// must give exactly the bits of the pass that fetches every texel. A neighbour
// taken from the wrong pixel of the quad (a mirrored or swapped direction)
// changes the box, the mean and variance or the chosen motion, and the image.
// An odd image size leaves the sharing off.
TEST(Taa, QuadsSharingTheirFetchesGiveTheBitsOfFetchingEveryTexel) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  ASSERT_TRUE(ctx.fragment_quad_operations()) << "lavapipe has quad operations in fragment shaders";
  for (auto [w, h] : {std::pair{64, 36}, std::pair{63, 35}}) {
    json e = glint_scene(w, h, orbit(4.0, 6, 40));
    e["variants"] = json::array({json{{"name", "taa"}, {"aa", "taa"}}});
    const ExperimentSpec spec = ExperimentSpec::from_json(e, "inline-test");
    const SceneData data = build_scene(spec, metrics::ColorManager());
    core::SceneGpu scene(ctx, data.mesh, data.env_texture);
    const core::MaterialProgram program =
        core::sand_program(spec.variants[0].material, data.range, core::ProgramRole::Variant);
    core::TaaSettings longest, closest, centre;
    longest.set("dering", true);
    longest.set("anti_flicker", true);
    longest.set("disocclusion", true);  // the nearest distance of the 3x3 and its slopes from shared texels too
    closest.set("velocity", "closest_depth");
    closest.set("clamp", "minmax");
    centre.set("velocity", "center");
    centre.set("space", "rgb");
    for (const core::TaaSettings& settings : {longest, closest, centre}) {
      std::unique_ptr<core::FrameGraph> graphs[2];
      const core::TaaPass* taa[2] = {nullptr, nullptr};
      for (int share = 0; share < 2; ++share) {
        graphs[share] = std::make_unique<core::FrameGraph>(ctx, w, h);
        core::SurfacePassOptions o;
        o.program = program;
        o.single_sample = true;
        o.motion = true;
        graphs[share]->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
        auto pass = std::make_unique<core::TaaPass>(ctx, settings, share == 1);
        taa[share] = pass.get();
        graphs[share]->add(std::move(pass));
        graphs[share]->build({"taa.color"});
      }
      const bool even = w % 2 == 0 && h % 2 == 0;
      EXPECT_FALSE(taa[0]->shares_quads());
      EXPECT_EQ(taa[1]->shares_quads(), even) << w << "x" << h;
      size_t lit = 0;
      for (int k = 0; k < spec.frames; ++k) {
        core::FrameInputs in;
        in.frame = k;
        in.uniforms = frame_uniforms(spec, data, k);
        in.samples = core::samples_for(spec.path, k, w, h, {core::jitter_offset(settings.jitter, k)});
        const Image a = graphs[0]->execute(in).images.at("taa.color");
        const Image b = graphs[1]->execute(in).images.at("taa.color");
        ASSERT_EQ(a.data.size(), b.data.size());
        size_t differ = 0;
        for (size_t i = 0; i < a.data.size(); ++i) {
          differ += std::memcmp(&a.data[i], &b.data[i], sizeof(float)) != 0;
          lit += a.data[i] > 0.0f;
        }
        EXPECT_EQ(differ, 0u) << w << "x" << h << " frame " << k;
      }
      EXPECT_GT(lit, size_t(w) * h) << "the frames must show something";
    }
  }
}

namespace {

// Runs the frames of `e`'s orbit through a surface pass (with the glint layer where `settings` reads
// it) and `settings`' resolve; returns every frame's taa.color.
std::vector<Image> resolve_frames(const json& e, const core::TaaSettings& settings) {
  core::VkContext& ctx = test::shared_context();
  json ev = e;
  ev["variants"] = json::array({json{{"name", "taa"}, {"aa", "taa"}}});
  const ExperimentSpec spec = ExperimentSpec::from_json(ev, "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  const core::MaterialProgram program =
      core::sand_program(spec.variants[0].material, data.range, core::ProgramRole::Variant);
  const int w = spec.width, h = spec.height;
  core::FrameGraph graph(ctx, w, h);
  core::SurfacePassOptions o;
  o.program = program;
  o.single_sample = true;
  o.motion = true;
  o.glint = settings.uses().glint;
  graph.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  graph.add(std::make_unique<core::TaaPass>(ctx, settings));
  graph.build({"taa.color"});
  std::vector<Image> out;
  for (int k = 0; k < spec.frames; ++k) {
    core::FrameInputs in;
    in.frame = k;
    in.uniforms = frame_uniforms(spec, data, k);
    in.samples = core::samples_for(spec.path, k, w, h, {core::jitter_offset(settings.jitter, k)});
    out.push_back(graph.execute(in).images.at("taa.color"));
  }
  return out;
}

size_t differing_floats(const std::vector<Image>& a, const std::vector<Image>& b) {
  size_t differ = 0;
  for (size_t k = 0; k < a.size(); ++k)
    for (size_t i = 0; i < a[k].data.size(); ++i) differ += a[k].data[i] != b[k].data[i];
  return differ;
}

}  // namespace

// The glint-aware options are exact no-ops where there are no glints: with the glint term off
// (I_glints = 0: the glint layer is 0 and its share 0), the layered resolve (colour - 0 through the
// resolve, a glint history of zeros added back), the reactive mask (r = 0) and the locks (no pixel
// is glint) give the bits of the plain resolve, frame after frame of a moving, jittered orbit with
// disocclusions. With glints the same options change the image (so the comparison can fail).
TEST(Taa, GlintAwareOptionsWithAnEmptyGlintLayerGiveThePlainResolvesBits) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  for (const char* filter : {"catmull_rom", "bilinear"}) {
    core::TaaSettings base;
    base.set("dering", true);
    base.set("disocclusion", true);
    base.set("history_filter", filter);
    core::TaaSettings lay = base, rea = base;
    lay.set("glint_layer", true);
    lay.set("glint_clamp", "minmax");
    rea.set("reactive", 0.5);
    rea.set("glint_lock", true);
    json dark = glint_scene(64, 36, orbit(3.0, 6, 40));
    dark["material"]["I_glints"] = {0, 0, 0};
    const std::vector<Image> want = resolve_frames(dark, base);
    size_t lit = 0;
    for (const Image& f : want)
      for (float v : f.data) lit += v > 0.0f;
    EXPECT_GT(lit, want.size() * 64 * 36) << "the frames must show something";
    EXPECT_EQ(differing_floats(want, resolve_frames(dark, lay)), 0u) << "layered, empty glint layer";
    EXPECT_EQ(differing_floats(want, resolve_frames(dark, rea)), 0u) << "reactive + locks, no glints";

    const json glinting = glint_scene(64, 36, orbit(3.0, 6, 40));
    const std::vector<Image> with_glints = resolve_frames(glinting, base);
    EXPECT_GT(differing_floats(with_glints, resolve_frames(glinting, lay)), 100u) << "layered, with glints";
    EXPECT_GT(differing_floats(with_glints, resolve_frames(glinting, rea)), 100u) << "reactive, with glints";
  }
}

// The accumulation schedule alpha = max(alpha_min, 1/n) weighs every frame since the last reset
// equally until 1/n falls below alpha_min: on a static view (zero motion, so the history is read at
// texel centres, unfiltered) with no rectification and alpha_min = 1/64, frame k is the mean of the
// k + 1 jittered one-sample frames, which is what supersampling with those k + 1 offsets computes.
// Checked against that mean at every frame (stated bound 2e-6 relative + 1e-7: fp32 rounding of a
// running mean over 16 terms); Falcor's exponential weights (alpha 0.1, no schedule) stay far from
// it (the same comparison fails by more than 1e-2).
TEST(Taa, AccumulationScheduleOnAStaticViewIsTheMeanOfItsJitteredFrames) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const json path = {{"type", "static"}, {"fps", 30},  {"frames", 16}, {"position", {-3.6252, 1.6905, 0.0}},
                     {"target", {0, 0, 0}}, {"fov", 20}};  // sand only: no silhouette against the sky
  const json e = glint_scene(64, 36, path);
  core::TaaSettings one;  // alpha 1: each frame its own jittered sample
  one.set("clamp", "none");
  one.set("feedback", "fixed");
  one.set("alpha", 1.0);
  core::TaaSettings acc = one, ema = one;
  acc.set("alpha", 1.0 / 64);
  acc.set("accumulate", true);
  ema.set("alpha", 0.1);
  const std::vector<Image> samples = resolve_frames(e, one), accumulated = resolve_frames(e, acc),
                           exponential = resolve_frames(e, ema);
  ASSERT_EQ(samples.size(), 16u);
  std::vector<double> mean(samples[0].data.size(), 0.0);
  double worst_acc = 0, worst_ema = 0;
  size_t bad = 0, total = 0;
  for (size_t k = 0; k < samples.size(); ++k) {
    for (size_t i = 0; i < mean.size(); ++i) {
      if (i % 4 == 3) continue;  // coverage
      mean[i] += samples[k].data[i];
      const double m = mean[i] / double(k + 1), scale = 2e-6 * std::abs(m) + 1e-7;
      worst_acc = std::max(worst_acc, std::abs(accumulated[k].data[i] - m) / scale);
      bad += std::abs(accumulated[k].data[i] - m) > scale;
      ++total;
      worst_ema = std::max(worst_ema, std::abs(exponential[k].data[i] - m) / (std::abs(m) + 1e-7));
    }
  }
  std::printf("accumulated vs the mean of its samples: worst error / bound %.3g (%zu of %zu); exponential: worst relative %.3g\n",
              worst_acc, bad, total, worst_ema);
  EXPECT_LE(worst_acc, 1.0);
  EXPECT_GT(worst_ema, 1e-2);
}

// The README's example resolve (one file written from the interface alone: the 3x3 min/max of
// taa_current, the bilinear taa_history at the pixel's motion, a fixed blend) renders what falcor renders
// with the same choices, within 1e-4 of each frame's maximum, frame after frame of a moving orbit.
TEST(Taa, AResolveWrittenFromTheReadmeRendersAsFalcorWithTheSameChoices) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  (void)ctx;
  core::TaaSettings falcor;
  falcor.set("clamp", "minmax").set("space", "rgb").set("history_filter", "bilinear").set("velocity", "center");
  falcor.set("feedback", "fixed").set("alpha", 0.1);
  const core::TaaSettings readme(
      core::taa_resolve_from_file((fs::path(GLINTLAB_TEST_DATA_DIR) / "taa_resolves" / "minmax_bilinear.glsl").string()));
  const json e = glint_scene(64, 36, orbit(3.0, 8, 40));
  const std::vector<Image> a = resolve_frames(e, falcor), b = resolve_frames(e, readme);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    float peak = 0.0f, worst = 0.0f;
    for (size_t i = 0; i < a[k].data.size(); ++i)
      if (i % 4 != 3) {
        peak = std::max(peak, a[k].data[i]);
        worst = std::max(worst, std::fabs(a[k].data[i] - b[k].data[i]));
      }
    EXPECT_GT(peak, 0.0f);
    EXPECT_LE(worst, 1e-4f * peak) << "frame " << k;
    if (k == a.size() - 1) std::printf("frame %zu: max difference %.3g of the frame's maximum %.3g\n", k, worst / peak, peak);
  }
  // the same file with another blend weight renders something else (the comparison can fail)
  core::TaaSettings other = readme;
  other.set("alpha", 0.5);
  EXPECT_GT(differing_floats(a, resolve_frames(e, other)), 1000u);
}

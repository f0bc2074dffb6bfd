// Temporal upscaling: a variant's "render_scale" renders its frame graph below the output resolution
// and a resolve (taau: falcor's with an upsampling reconstruction) or a spatial upscale brings it to
// the output, where it is measured against the truth at the output resolution.
#include "core/material/program.h"
#include "core/render/sample_schedule.h"
#include "core/util/json_check.h"
#include "experiments/runner/runner.h"
#include "experiments/sources/rendered_sources.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "experiments/taa_test/taa_test.h"
#include "metrics/color/color_manager.h"
#include "tests/support/temp_dir.h"
#include "tests/support/user_file_run.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;
using namespace glintlab;
using json = nlohmann::json;

namespace {

json sand_scene(int w, int h, const json& path) {
  return {{"name", "upscaling-test"},
          {"resolution", {w, h}},
          {"scene",
           {{"mesh", {{"type", "wavy"}, {"size", 20}, {"tessellation", 128}, {"amplitude", 0.5}, {"wavelength", 3}}},
            {"sky",
             {{"turbidity", 3}, {"sky_intensity", 0.5}, {"sun_elevation_deg", 25}, {"sun_azimuth_deg", 30},
              {"sun_intensity", 6}}}}},
          {"camera_path", path},
          {"material",
           {{"preset", "thesis-hdri-match"}, {"noise_scale", 400}, {"glint_sigma", 0.002}, {"I_glints", {20, 20, 20}},
            {"sigmoid_a", 2}, {"sigmoid_b", 1000}}},
          {"output", {{"exr", false}, {"png", false}}}};
}

// Expects experiment `e` with its variants replaced by `variant` to be refused with a message holding `want`.
void expect_rejected(json e, const json& variant, const std::string& want) {
  e["variants"] = json::array({variant});
  try {
    ExperimentSpec::from_json(e, "inline-test");
    ADD_FAILURE() << "accepted " << variant.dump();
  } catch (const ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find(want), std::string::npos) << err.what();
  }
}

// Runs experiment `e` in `dir` (its file e.json, its output out/) and returns every variant's CIEDE2000
// per frame, by variant name; empty (and a failure) if the run fails.
std::map<std::string, std::vector<double>> run_delta_e(const fs::path& dir, const json& e) {
  test::write_text(dir / "e.json", e.dump());
  std::ostringstream log;
  if (run_experiment(test::user_file_run_options(dir / "e.json", dir / "out"), log) != 0) {
    ADD_FAILURE() << log.str();
    return {};
  }
  std::map<std::string, std::vector<double>> de;
  std::ifstream rec(dir / "out" / "records.jsonl");
  for (std::string line; std::getline(rec, line);) {
    const json r = json::parse(line);
    if (r.value("type", "") != "frame") continue;
    std::vector<double>& v = de[r["name"].get<std::string>()];
    v.resize(std::max(v.size(), r["frame"].get<size_t>() + 1), std::nan(""));
    for (const auto& m : r["metrics"])
      if (m[0] == "deltaE2000") v[r["frame"].get<size_t>()] = m[1].get<double>();
  }
  return de;
}

}  // namespace

TEST(Upscaling, RenderScaleIsCheckedAndChoosesFsr2sJitter) {
  EXPECT_EQ(core::fsr2_jitter_phases(1 / 1.5), 18);  // FSR 2's modes: Quality, Balanced, Performance, Ultra
  EXPECT_EQ(core::fsr2_jitter_phases(1 / 1.7), 23);
  EXPECT_EQ(core::fsr2_jitter_phases(0.5), 32);
  EXPECT_EQ(core::fsr2_jitter_phases(1 / 3.0), 72);
  EXPECT_EQ(core::jitter_offset(core::JitterSequence::HaltonFsr2, 32, 0.5),
            core::jitter_offset(core::JitterSequence::HaltonFsr2, 0, 0.5))
      << "32 phases at 1/2";
  EXPECT_NE(core::jitter_offset(core::JitterSequence::HaltonFsr2, 16, 0.5),
            core::jitter_offset(core::JitterSequence::HaltonFsr2, 0, 0.5));

  json e = sand_scene(64, 36, {{"type", "static"}, {"fps", 30}, {"frames", 2}, {"position", {-4.5, 0.9, -0.5}},
                              {"target", {3, 0, 1}}, {"fov", 40}});
  e["variants"] = json::array({json{{"name", "up"}, {"aa", "taa"}, {"render_scale", 0.5}},
                               json{{"name", "up-r2"}, {"aa", "taa"}, {"render_scale", 0.5}, {"taa", {{"jitter", "r2"}}}},
                               json{{"name", "native"}, {"aa", "taa"}}});
  const ExperimentSpec s = ExperimentSpec::from_json(e, "inline-test");
  EXPECT_EQ(s.variants[0].taa.jitter, core::JitterSequence::HaltonFsr2) << "the default below scale 1";
  EXPECT_EQ(s.variants[1].taa.jitter, core::JitterSequence::R2) << "any sequence selectable";
  EXPECT_EQ(s.variants[2].taa.jitter, core::JitterSequence::Halton16) << "native: Falcor's";
  EXPECT_EQ(s.variants[0].render_width(640), 320);
  EXPECT_EQ(s.variants[0].render_height(360), 180);
  expect_rejected(e, {{"name", "x"}, {"render_scale", 0.2}}, "variants[0].render_scale");
  expect_rejected(e, {{"name", "x"}, {"render_scale", 1.5}}, "variants[0].render_scale");
  expect_rejected(e, {{"name", "x"}, {"glint_footprint", "display"}}, "only applies with \"render_scale\" below 1");
  expect_rejected(e, {{"name", "x"}, {"render_scale", 0.5}, {"glint_footprint", "pixel"}}, "\"render\", \"display\"");
}

// At render scale 1 taau renders what falcor renders with the same choices (there is nothing to
// upsample), bit for bit, frame after frame of a moving orbit, with the glint-aware options too.
TEST(Upscaling, TaauAtScaleOneRendersWhatFalcorRenders) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  json e = sand_scene(64, 36, {{"type", "orbit"}, {"fps", 30}, {"frames", 8}, {"center", {0, 0, 0}},
                              {"radius", 3.6}, {"height", 1.7}, {"start_deg", 180}, {"end_deg", 194}, {"fov", 40}});
  const json options = {{"dering", true}, {"glint_layer", true}, {"glint_clamp", "minmax"}, {"accumulate", true},
                        {"disocclusion", true}};
  e["variants"] = json::array({json{{"name", "falcor"}, {"aa", "taa"}, {"taa", {{"name", "falcor"}, {"parameters", options}}}},
                               json{{"name", "taau"}, {"aa", "taa"}, {"taa", {{"name", "taau"}, {"parameters", options}}}}});
  const ExperimentSpec spec = ExperimentSpec::from_json(e, "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  RenderedFrames frames(spec, data);
  std::unique_ptr<ColourSource> src[2];
  for (int i = 0; i < 2; ++i)
    src[i] = rendered_variant(ctx, scene, spec.variants[size_t(i)],
                              core::sand_program(spec.variants[size_t(i)].material, data.range, core::ProgramRole::Variant),
                              frames);
  size_t differ = 0, lit = 0;
  for (int k = 0; k < spec.frames; ++k) {
    const SourceFrame a = src[0]->frame(k), b = src[1]->frame(k);
    ASSERT_EQ(a.image->data.size(), b.image->data.size());
    for (size_t j = 0; j < a.image->data.size(); ++j) {
      differ += a.image->data[j] != b.image->data[j];
      lit += a.image->data[j] > 0.0f;
    }
  }
  EXPECT_GT(lit, size_t(8 * 64 * 36)) << "the frames show something";
  EXPECT_EQ(differ, 0u);
}

// The host compiles a resolve for the case it runs (TAA_RENDER_SCALED: 0 at the output resolution, 1
// below it) and binds what either case reads: a file that reads the glint layer only when upscaling
// is given it there (and with it the motion vectors, beside which the surface pass writes it).
TEST(Upscaling, TheResolveIsCompiledForItsRenderScale) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  test::TempDir dir("upscaling_render_scaled");
  test::write_text(dir.path() / "r.glsl", R"(// taa_resolve checks=finite
TaaResult taa_resolve(TaaPixel p) {
#if TAA_RENDER_SCALED
  // The glint layer's share of the luma under the pixel (in [0, 1]) in green; blue 1.
  return taa_result(vec3(0.0, taa_render_glint(taa_render_texel(vec2(p.pixel) + 0.5)).a, 1.0));
#else
  return taa_result(vec3(1.0, 0.0, 0.0));
#endif
}
)");
  json e = sand_scene(64, 36, {{"type", "orbit"}, {"fps", 30}, {"frames", 1}, {"center", {0, 0, 0}}, {"radius", 3.6},
                              {"height", 1.7}, {"start_deg", 180}, {"end_deg", 194}, {"fov", 40}});
  e["material"]["glint_sigma"] = 0.2;  // broad glints: a glint layer over much of the view
  const json file = {{"file", (dir.path() / "r.glsl").string()}};
  e["variants"] = json::array({json{{"name", "native"}, {"aa", "taa"}, {"taa", file}},
                               json{{"name", "half"}, {"aa", "taa"}, {"render_scale", 0.5}, {"taa", file}}});
  const ExperimentSpec spec = ExperimentSpec::from_json(e, "inline-test");
  EXPECT_TRUE(spec.variants[1].taa.uses().glint) << "read in one case only, bound";
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  RenderedFrames frames(spec, data);
  for (size_t v = 0; v < 2; ++v) {
    const std::unique_ptr<ColourSource> src = rendered_variant(
        ctx, scene, spec.variants[v], core::sand_program(spec.variants[v].material, data.range, core::ProgramRole::Variant),
        frames);
    const SourceFrame f = src->frame(0);
    size_t wrong = 0, glinting = 0;
    for (size_t p = 0; p < f.image->pixel_count(); ++p) {
      const float* c = f.image->data.data() + 4 * p;
      if (v == 0) {
        wrong += !(c[0] == 1.0f && c[1] == 0.0f && c[2] == 0.0f);
      } else {
        wrong += !(c[0] == 0.0f && c[1] >= 0.0f && c[1] <= 1.0f && c[2] == 1.0f);
        glinting += c[1] > 0.0f;
      }
    }
    EXPECT_EQ(wrong, 0u) << spec.variants[v].name;
    if (v == 1) {
      EXPECT_GT(glinting, f.image->pixel_count() / 20) << "the glint layer is bound";
    }
  }
}

// A static view at render scale 1/2: 64 frames of an accumulating taau (16 samples per output pixel)
// end within 1.25x the CIEDE2000 of 4x4 supersampling at the output resolution; a spatial upscale of
// the half-resolution frame cannot recover what it never sampled (one sample per render texel, or 4x4
// supersampled at half resolution), nor can falcor's resolve fed the render texel under each pixel.
TEST(Upscaling, AnAccumulatingTaauAtHalfScaleRecoversOutputResolutionDetail) {
  test::TempDir dir("upscaling");
  json e = sand_scene(96, 54, {{"type", "static"}, {"fps", 30}, {"frames", 64}, {"position", {-4.5, 0.9, -0.5}},
                              {"target", {3, 0, 1}}, {"fov", 40}});
  const json acc = {{"clamp", "none"}, {"feedback", "fixed"}, {"alpha", 0.015625}, {"accumulate", true}};
  e["variants"] = json::array(
      {json{{"name", "ssaa-4x4"}, {"aa", "ssaa"}, {"ssaa_grid", 4}},
       json{{"name", "taau"}, {"aa", "taa"}, {"render_scale", 0.5}, {"taa", {{"name", "taau"}, {"jitter", "r2"}, {"parameters", acc}}}},
       json{{"name", "falcor"}, {"aa", "taa"}, {"render_scale", 0.5}, {"taa", {{"name", "falcor"}, {"jitter", "r2"}, {"parameters", acc}}}},
       json{{"name", "one-sample-upscaled"}, {"render_scale", 0.5}},
       json{{"name", "ssaa-4x4-upscaled"}, {"aa", "ssaa"}, {"ssaa_grid", 4}, {"render_scale", 0.5}}});
  e["reference"] = {{"grid", 16}};
  e["metrics"] = {"deltaE2000"};
  std::map<std::string, double> last;
  for (const auto& [name, de] : run_delta_e(dir.path(), e))
    if (de.size() == 64) last[name] = de[63];
  ASSERT_EQ(last.size(), 5u);
  for (const auto& [n, v] : last) std::printf("%-20s CIEDE2000 at frame 64: %.3f\n", n.c_str(), v);
  const double ssaa = last["ssaa-4x4"];
  EXPECT_LE(last["taau"], 1.25 * ssaa);
  EXPECT_GT(last["one-sample-upscaled"], 2.0 * ssaa);
  EXPECT_GT(last["ssaa-4x4-upscaled"], 2.0 * ssaa);
  EXPECT_GT(last["falcor"], 2.0 * last["taau"]);
  const json summary = read_json_file((dir.path() / "out" / "summary.json").string());
  EXPECT_EQ(summary["variants"][1]["render_resolution"], json({48, 27}));
  EXPECT_TRUE(summary["variants"][1]["gpu_ms_per_pass"].contains("surface"));
  EXPECT_TRUE(summary["variants"][3]["gpu_ms_per_pass"].contains("upscale"));
}

// Each upscaler passes taa-test at render scale 1/2 on the checks its design meets (both declare
// converges failed, as falcor does: the box rejects the history at high-contrast edges).
TEST(Upscaling, TaauAndFsr2PassTaaTestAtHalfScale) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  test::TempDir dir("upscaling_taa_test");
  for (const char* name : {"taau", "fsr2"}) {
    fs::create_directories(dir.path() / name);
    const ConformanceReport r = run_taa_test(ctx, taa_test_settings(name, {}), (dir.path() / name).string(), "", 0.5);
    EXPECT_TRUE(r.all_pass()) << r.text();
    for (const char* c : {"finite", "deterministic", "ghosting", "cut", "pan", "flicker"})
      EXPECT_TRUE(r.check(c)->applies && r.check(c)->pass) << name << " " << c << "\n" << r.text();
  }
}

// The zoomed contact sheet's region lies inside the image and needs the contact sheet.
TEST(Upscaling, TheZoomedContactSheetIsChecked) {
  json e = sand_scene(64, 36, {{"type", "static"}, {"fps", 30}, {"frames", 2}, {"position", {-4.5, 0.9, -0.5}},
                              {"target", {3, 0, 1}}, {"fov", 40}});
  e["variants"] = json::array({json{{"name", "a"}}});
  auto problem = [&](const json& output) {
    json x = e;
    x["output"] = output;
    try {
      ExperimentSpec::from_json(x, "inline-test");
      return std::string();
    } catch (const ConfigError& err) {
      return std::string(err.what());
    }
  };
  EXPECT_EQ(problem({{"contact_sheet", true}, {"contact_sheet_zoom", {{"region", {10, 4, 20, 8}}, {"scale", 3}}}}), "");
  EXPECT_NE(problem({{"contact_sheet", true}, {"contact_sheet_zoom", {{"region", {50, 4, 20, 8}}}}}).find("inside the 64x36"),
            std::string::npos);
  EXPECT_NE(problem({{"contact_sheet_zoom", {{"region", {1, 1, 2, 2}}}}}).find("\"contact_sheet\": true"), std::string::npos);
  EXPECT_NE(problem({{"contact_sheet", true}, {"contact_sheet_zoom", {{"region", {1, 1, 2.5, 2}}}}}).find("whole pixels"),
            std::string::npos);
}

// "mesh_lod": below scale 1 a variant on an adaptive grid draws the output's grid ("display", the
// default, as native variants and the truth do) or the grid adapted for its render resolution
// ("render"): the very grid a run at that resolution draws, fewer triangles. Its images stay close to
// the display grid's (no cracks, no lost surface): the grid keeps its bounds, in render pixels, whose
// 0.5 px of error is a whole output pixel, so its error against the truth may grow by half (a crack or
// a lost patch of surface shows sky: far more).
TEST(Upscaling, MeshLodRenderDrawsTheGridAdaptedForTheRenderResolution) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  test::TempDir dir("upscaling_mesh_lod");
  json e = sand_scene(160, 90, {{"type", "orbit"}, {"fps", 30}, {"frames", 3}, {"center", {0, 1.5, 0}}, {"radius", 6},
                                {"height", 2.5}, {"start_deg", 200}, {"end_deg", 206}, {"fov", 40}});
  e["scene"]["mesh"] = {{"type", "dunes"},        {"size", 80},      {"tessellation", 160}, {"max_edge_px", 4},
                        {"max_error_px", 0.5},    {"amplitude", 3},  {"wavelength", 24},    {"octaves", 3},
                        {"gain", 0.4},            {"seed", 3}};
  e["variants"] = json::array(
      {json{{"name", "native"}, {"aa", "taa"}},
       json{{"name", "render-lod"}, {"aa", "taa"}, {"render_scale", 0.5}, {"taa", {{"name", "taau"}}}, {"mesh_lod", "render"}},
       json{{"name", "display-lod"}, {"aa", "taa"}, {"render_scale", 0.5}, {"taa", {{"name", "taau"}}}}});
  e["reference"] = {{"grid", 4}};
  e["metrics"] = {"deltaE2000"};
  const ExperimentSpec spec = ExperimentSpec::from_json(e, "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  ASSERT_EQ(data.render_lods.size(), 1u);
  const core::Mesh& lod = data.render_lods.at(0.5);
  ExperimentSpec half = spec;
  half.width = 80;
  half.height = 45;
  EXPECT_EQ(lod.indices, core::build_mesh(half.mesh, mesh_views(half)).indices)
      << "the grid of a run at the render resolution: max_edge_px and max_error_px in its pixels";
  EXPECT_LT(lod.indices.size(), data.mesh.indices.size() * 3 / 4);
  std::printf("triangles: output's grid %zu, render scale 1/2's %zu\n", data.mesh.indices.size() / 3,
              lod.indices.size() / 3);
  const SceneGpus gpus(ctx, data);
  EXPECT_EQ(gpus.of(spec.variants[0]).index_count(), data.mesh.indices.size()) << "native: the output's grid";
  EXPECT_EQ(gpus.of(spec.variants[1]).index_count(), lod.indices.size());
  EXPECT_EQ(gpus.of(spec.variants[2]).index_count(), data.mesh.indices.size()) << "mesh_lod display, the default";
  EXPECT_EQ(&gpus.of(spec.variants[1]).env_map(), &gpus.display().env_map()) << "one environment map, shared";

  std::map<std::string, double> mean;
  for (const auto& [name, de] : run_delta_e(dir.path(), e))
    if (de.size() == 3) mean[name] = (de[0] + de[1] + de[2]) / 3.0;
  ASSERT_EQ(mean.size(), 3u);
  std::printf("mean CIEDE2000: native %.3f, render-lod %.3f, display-lod %.3f\n", mean["native"], mean["render-lod"],
              mean["display-lod"]);
  EXPECT_LE(mean["render-lod"], 1.5 * mean["display-lod"]);
  EXPECT_NE(mean["render-lod"], mean["display-lod"]) << "another grid draws another image";
  const json summary = read_json_file((dir.path() / "out" / "summary.json").string());
  EXPECT_EQ(summary["variants"][1]["mesh_lod"], "render");
  EXPECT_EQ(summary["variants"][2]["mesh_lod"], "display");
  EXPECT_FALSE(summary["variants"][0].contains("mesh_lod"));

  expect_rejected(e, {{"name", "x"}, {"mesh_lod", "display"}}, "only applies with \"render_scale\" below 1");
  expect_rejected(e, {{"name", "x"}, {"render_scale", 0.5}, {"mesh_lod", "fine"}}, "\"display\", \"render\"");
  expect_rejected(sand_scene(64, 36, e["camera_path"]), {{"name", "x"}, {"render_scale", 0.5}, {"mesh_lod", "render"}},
                  "scene.mesh.max_edge_px > 0");
}

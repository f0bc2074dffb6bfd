// The truth's noise floor (experiments/runner/frame_loop.cpp): every rendered truth is also kept as
// its two checkerboard halves, and every metric is measured for half B against half A; for the
// metrics that are means of differences, summary.json's references[].floor is half of that (two
// halves differ by twice the whole truth's noise). Checked here against what it predicts: the same
// metric measured between the truth and a truth with 4x the samples (the truth's own error, plus a
// quarter as much of the better one's, in quadrature: 1.12 x the floor for noise alone), within a
// factor of 2, on small versions of `default` (Kajs glints, a dunes flight) and
// `glint-flicker-orbit` (an orbit over a wavy plane). A truth measured against itself scores 0,
// below its floor. The same truth given to `measure` as its two halves (`"output": {"halves": true}`,
// then `--reference-b`, here as a frames-only experiment's "frames_b") has the same floor, and
// frames.csv carries each frame's floor. Real runs on lavapipe, validation on.
#include "experiments/runner/runner.h"

#include "tests/support/csv.h"
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace glintlab;
using nlohmann::json;

namespace {

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

void run(const json& e, const fs::path& dir, const std::string& name) {
  std::ofstream(dir / (name + ".json")) << e.dump(2);
  RunOptions opt;
  opt.report = false;
  opt.experiment = (dir / (name + ".json")).string();
  opt.out_dir = (dir / name).string();
  opt.cache_dir = (dir / "cache").string();
  opt.validation = true;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
}

// `experiment` (a shipped one) at width x height over its first `frames` frames, one variant, its truth and
// motion written as EXR; once at its grid and once at twice the grid (4x the samples); then the first
// truth measured against the second, and against itself, along the run's motion.
void check_floor(const std::string& experiment, int width, int height, int frames) {
  const test::TempDir tmp("noise_floor_" + experiment);
  json e = read_json(fs::path(GLINTLAB_SOURCE_DIR) / "experiments" / "data" / (experiment + ".json"));
  e["resolution"] = {width, height};
  e["frames"] = frames;
  e["variants"] = json::array({e["variants"][0]});  // no-aa
  e["output"] = {{"exr", true}, {"png", false}, {"every", 1}, {"motion", true}, {"halves", true}};
  const int grid = e["reference"]["grid"];
  run(e, tmp.path(), "n");
  e["reference"]["grid"] = 2 * grid;
  run(e, tmp.path(), "n4");
  const json files = {{"name", "truth-against-truth"},
                      {"reference", {{"frames", "n4/reference"}}},
                      {"variants", {{{"name", "truth"}, {"frames", "n/reference"}}, {{"name", "itself"}, {"frames", "n/reference"}}}},
                      {"motion", {{"frames", "n/motion"}, {"convention", "pixels"}}},
                      {"metrics", {"deltaE2000", "flip"}}};
  run(files, tmp.path(), "against");
  json halves = files;  // the same truth from its two halves: their mean, and their difference its floor
  halves["name"] = "halves";
  halves["reference"] = {{"frames", "n/reference-half-a"}, {"frames_b", "n/reference-half-b"}};
  halves["variants"] = {{{"name", "no-aa"}, {"frames", "n/no-aa"}}};
  run(halves, tmp.path(), "halves");
  json self = files;
  self["reference"] = {{"frames", "n/reference"}};
  run(self, tmp.path(), "self");

  const json ref = read_json(tmp.path() / "n" / "summary.json")["references"][0];
  ASSERT_EQ(ref["spp"], grid * grid);
  ASSERT_TRUE(ref.contains("floor")) << ref.dump();
  const json measured = read_json(tmp.path() / "against" / "summary.json")["variants"][0]["metrics"];
  const json itself = read_json(tmp.path() / "self" / "summary.json")["variants"][1]["metrics"];
  for (const char* m : {"deltaE2000", "temporal_error_mc", "temporal_lag", "temporal_error"}) {
    const double floor = ref["floor"][m].get<double>(), got = measured[m]["mean"].get<double>();
    std::printf("%s, %d spp: %s floor %.4g, the truth against 4x its samples %.4g (ratio %.2f)\n",
                experiment.c_str(), grid * grid, m, floor, got, got / floor);
    EXPECT_GT(floor, 0.0) << m;
    EXPECT_GE(got, 0.5 * floor) << m;
    EXPECT_LE(got, 2.0 * floor) << m;
    EXPECT_LE(itself[m]["mean"].get<double>(), floor) << m << ": a truth against itself";
  }

  // A truth read as one estimate has no floor; read as its two halves, the floor the run measured (the
  // same halves, the same motion: the same figures), and the variant's figures against their mean are
  // the run's, to fp32 summation order (the truth sums every sample in one pass).
  EXPECT_FALSE(read_json(tmp.path() / "against" / "summary.json")["references"][0].contains("floor"));
  const json from_halves = read_json(tmp.path() / "halves" / "summary.json");
  const json run_no_aa = read_json(tmp.path() / "n" / "summary.json")["variants"][0]["metrics"];
  ASSERT_TRUE(from_halves["references"][0].contains("floor")) << from_halves["references"][0].dump();
  for (const char* m : {"deltaE2000", "flip", "temporal_error_mc", "flicker_excess", "temporal_lag"}) {
    EXPECT_NEAR(from_halves["references"][0]["floor"][m].get<double>(), ref["floor"][m].get<double>(),
                1e-9 * ref["floor"][m].get<double>()) << m;
    const double run_v = run_no_aa[m]["mean"].get<double>();
    EXPECT_NEAR(from_halves["variants"][0]["metrics"][m]["mean"].get<double>(), run_v, 1e-4 * run_v) << m;
  }

  // frames.csv: each frame's floor, whose mean over the frames is the summary's.
  const auto rows = test::read_csv_rows(tmp.path() / "n" / "frames.csv");
  ASSERT_EQ(rows.size(), size_t(frames));
  for (const char* m : {"deltaE2000", "temporal_error_mc"}) {
    double sum = 0;
    int n = 0;
    for (const auto& r : rows) {
      const std::string& cell = r.at(std::string("floor_") + m);
      if (cell.empty()) continue;  // a temporal metric at the sequence's start
      sum += std::stod(cell);
      ++n;
    }
    ASSERT_GT(n, 0) << m;
    EXPECT_NEAR(sum / n, ref["floor"][m].get<double>(), 1e-6 * ref["floor"][m].get<double>()) << m;
  }
}

}  // namespace

TEST(NoiseFloor, TheFloorPredictsTheTruthAgainstFourTimesItsSamplesOnTheDunesFlight) {
  check_floor("default", 160, 90, 4);
}

TEST(NoiseFloor, TheFloorPredictsTheTruthAgainstFourTimesItsSamplesOnTheOrbit) {
  check_floor("glint-flicker-orbit", 320, 180, 4);  // its own footprint (at 160x90 a pixel holds 4x the glints)
}

// "reference": {"floor": {...}}: the truth grows until the named metric's floor is at most the fraction
// of the smallest variant value, each step recorded; the run uses the grid that met it.
TEST(NoiseFloor, AFloorTargetSizesTheTruth) {
  const test::TempDir tmp("noise_floor_target");
  json e = read_json(fs::path(GLINTLAB_SOURCE_DIR) / "experiments" / "data" / "default.json");
  e["resolution"] = {160, 90};
  e["frames"] = 2;
  e["variants"] = json::array({e["variants"][0]});  // no-aa
  e["output"] = {{"exr", false}, {"png", false}};
  e["reference"] = {{"grid", 2}, {"floor", {{"deltaE2000", 0.1}}}, {"max_grid", 32}};
  run(e, tmp.path(), "sized");
  const json s = read_json(tmp.path() / "sized" / "summary.json");
  const json& sizing = s["reference_sizing"];
  ASSERT_TRUE(sizing["met"].get<bool>()) << sizing.dump();
  const int grid = sizing["grid"];
  EXPECT_GT(grid, 2);
  EXPECT_EQ(s["references"][0]["spp"], grid * grid);
  const double floor = s["references"][0]["floor"]["deltaE2000"], value = s["variants"][0]["metrics"]["deltaE2000"]["mean"];
  std::printf("sized truth: %dx%d, deltaE2000 floor %.4g against no-aa's %.4g (%zu steps)\n", grid, grid, floor, value,
              sizing["steps"].size());
  EXPECT_LE(floor, 0.1 * value);
  const json& steps = sizing["steps"];
  ASSERT_GE(steps.size(), 2u);
  for (size_t i = 0; i < steps.size(); ++i) {
    EXPECT_EQ(steps[i]["met"].get<bool>(), i + 1 == steps.size()) << steps.dump();
    if (i > 0) {
      EXPECT_GT(steps[i]["grid"].get<int>(), steps[i - 1]["grid"].get<int>());
      EXPECT_LT(steps[i]["floor"]["deltaE2000"].get<double>(), steps[i - 1]["floor"]["deltaE2000"].get<double>());
    }
  }
  EXPECT_EQ(steps.back()["grid"], grid);
}

TEST(NoiseFloor, AFloorTargetOfAMetricWithoutFloorOrNotMeasuredIsExitCode2) {
  const test::TempDir tmp("noise_floor_target_bad");
  json e = read_json(fs::path(GLINTLAB_SOURCE_DIR) / "experiments" / "data" / "default.json");
  e["frames"] = 1;
  auto expect_2 = [&](const json& reference, const std::string& words) {
    e["reference"] = reference;
    std::ofstream(tmp.path() / "bad.json") << e.dump(2);
    RunOptions opt;
    opt.experiment = (tmp.path() / "bad.json").string();
    opt.out_dir = (tmp.path() / "out").string();
    std::ostringstream log;
    EXPECT_EQ(run_experiment(opt, log), 2) << reference.dump();
    EXPECT_NE(log.str().find(words), std::string::npos) << log.str();
    EXPECT_FALSE(fs::exists(tmp.path() / "out" / "records.jsonl")) << "nothing before the input is checked";
  };
  expect_2({{"grid", 4}, {"floor", {{"flicker_ratio", 0.1}}}}, "reference.floor.flicker_ratio");
  expect_2({{"grid", 4}, {"floor", {{"deltaEITP", 0.1}}}}, "does not measure deltaEITP");
  expect_2({{"grid", 4}, {"floor", {{"deltaE2000", 0}}}}, "reference.floor.deltaE2000");
  expect_2({{"grid", 1}, {"floor", {{"deltaE2000", 0.1}}}}, "at least 2");
  expect_2({{"grid", 8}, {"floor", {{"deltaE2000", 0.1}}}, {"max_grid", 4}}, "max_grid");
  expect_2({{"grid", 8}, {"max_grid", 16}}, "max_grid");  // the limit belongs to a floor target
}

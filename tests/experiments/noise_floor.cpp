// The truth's noise floor (experiments/runner/frame_loop.cpp): every rendered truth is also kept as
// its two checkerboard halves, and every metric is measured for half B against half A; for the
// metrics that are means of differences, summary.json's references[].floor is half of that (two
// halves differ by twice the whole truth's noise). Checked here against what it predicts: the same
// metric measured between the truth and a truth with 4x the samples (the truth's own error, plus a
// quarter as much of the better one's, in quadrature: 1.12 x the floor for noise alone), within a
// factor of 2, on small versions of `default` (Kajs glints, a dunes flight) and
// `glint-flicker-orbit` (an orbit over a wavy plane). A truth measured against itself scores 0,
// below its floor. Real runs on lavapipe, validation on.
#include "experiments/runner/runner.h"

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
  json e = read_json(fs::path(GLINTLAB_SOURCE_DIR) / "experiments" / (experiment + ".json"));
  e["resolution"] = {width, height};
  e["frames"] = frames;
  e["variants"] = json::array({e["variants"][0]});  // no-aa
  e["output"] = {{"exr", true}, {"png", false}, {"every", 1}, {"motion", true}};
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
}

}  // namespace

TEST(NoiseFloor, TheFloorPredictsTheTruthAgainstFourTimesItsSamplesOnTheDunesFlight) {
  check_floor("default", 160, 90, 4);
}

TEST(NoiseFloor, TheFloorPredictsTheTruthAgainstFourTimesItsSamplesOnTheOrbit) {
  check_floor("glint-flicker-orbit", 320, 180, 4);  // its own footprint (at 160x90 a pixel holds 4x the glints)
}

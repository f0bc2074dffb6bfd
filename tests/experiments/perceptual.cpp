// temporal_score in a whole run, against the perceptual anchor: the first 24 frames of the anchor's
// orbit (experiments/data/perceptual/orbit.json) with five of its variants, rendered on lavapipe with
// validation on, must rank as ColorVideoVDP ranked the full 48-frame run (its transient JOD, committed in
// tests/data/perceptual/anchor.csv by experiments/perceptual/anchor.py): the renderer and the metric of
// today against the verdict the table holds. tests/python/test_perceptual_anchor.py checks the table.
#include "experiments/runner/runner.h"

#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

// jod_transient of the anchor table's rows of one scene and truth, by variant.
std::map<std::string, double> anchor_jods(const std::string& scene, const std::string& truth) {
  std::ifstream in(fs::path(GLINTLAB_SOURCE_DIR) / "tests" / "data" / "perceptual" / "anchor.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
    return out;
  };
  header = split(line);
  const auto col = [&](const char* name) { return std::find(header.begin(), header.end(), name) - header.begin(); };
  std::map<std::string, double> out;
  while (std::getline(in, line)) {
    const auto cells = split(line);
    if (cells.at(col("scene")) == scene && cells.at(col("truth")) == truth)
      out[cells.at(col("variant"))] = std::stod(cells.at(col("jod_transient")));
  }
  return out;
}

// Spearman's ρ of two equally long lists without ties.
double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  auto ranks = [](const std::vector<double>& v) {
    std::vector<double> r(v.size());
    for (size_t i = 0; i < v.size(); ++i)
      r[i] = double(std::count_if(v.begin(), v.end(), [&](double x) { return x < v[i]; }));
    return r;
  };
  const auto ra = ranks(a), rb = ranks(b);
  double d2 = 0;
  for (size_t i = 0; i < a.size(); ++i) d2 += (ra[i] - rb[i]) * (ra[i] - rb[i]);
  const double n = double(a.size());
  return 1.0 - 6.0 * d2 / (n * (n * n - 1.0));
}

}  // namespace

TEST(PerceptualAnchor, TemporalScoreRanksTheOrbitAsColorVideoVdp) {
  const std::vector<std::string> names = {"no-aa", "ssaa-2x2", "ssaa-4x4", "taa", "taa-clamp-none"};
  const std::map<std::string, double> jod = anchor_jods("orbit", "reference-kajs");
  for (const std::string& n : names) ASSERT_TRUE(jod.count(n)) << n << " is not in the anchor table";

  const test::TempDir dir("perceptual_orbit");
  RunOptions opt;
  opt.experiment = "perceptual/orbit";
  opt.out_dir = (dir.path() / "out").string();
  opt.cache_dir = (dir.path() / "cache").string();
  opt.variants = names;
  opt.max_frames = 24;
  opt.report = false;
  opt.validation = true;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir.path() / "out" / "summary.json"));
  EXPECT_EQ(summary.at("temporal_score_view"), "sRGB/ACES 1.0 SDR-video");

  std::map<std::string, double> score;
  for (const auto& v : summary.at("variants"))
    score[v.at("name")] = v.at("metrics").at("temporal_score").at("mean").get<double>();
  std::vector<double> s, j;
  for (const std::string& n : names) {
    std::printf("%-16s temporal_score %.4f   anchor's transient JOD %.3f\n", n.c_str(), score.at(n), jod.at(n));
    s.push_back(-score.at(n));  // lower score = better, higher JOD = better
    j.push_back(jod.at(n));
  }
  // Measured: the same order as the JODs (ρ = 1; the un-clamped TAA, which converges slowly, 7 % below 2x2
  // SSAA, and above it over the first 16 frames); one neighbouring swap (ρ 0.9) is allowed for other CPUs.
  EXPECT_GE(spearman(s, j), 0.9);
  // The supersampling ladder, and 4x4 SSAA steadier than Falcor's TAA (as ColorVideoVDP has it, where
  // flicker_excess and temporal_error_mc had TAA steadier).
  EXPECT_GT(score.at("no-aa"), score.at("ssaa-2x2"));
  EXPECT_GT(score.at("ssaa-2x2"), score.at("ssaa-4x4"));
  EXPECT_GT(score.at("taa"), score.at("ssaa-4x4"));
}

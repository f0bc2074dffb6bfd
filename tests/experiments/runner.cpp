// `glintlab run` end to end on lavapipe (validation on): every metric for
// every frame and variant in frames.csv, the summary, the reference cache
// (reuse, corruption detected and rebuilt), and bad input.
#include "experiments/sources/reference_cache.h"
#include "experiments/runner/runner.h"
#include "experiments/runner/density_sweep.h"
#include "metrics/color/image_io.h"

#include "tests/support/csv.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

#include "core/util/json_check.h"

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) rows.push_back(test::split_csv_line(line));
  return rows;
}

const char* kTiny = R"({
  "name": "tiny",
  "resolution": [64, 36],
  "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 16, "amplitude": 0.4, "wavelength": 5}},
  "camera_path": {"type": "orbit", "fps": 30, "frames": 3, "center": [0, 0, 0], "radius": 3.6,
                  "height": 1.7, "start_deg": 180, "end_deg": 190, "fov": 40},
  "material": {"preset": "thesis-default", "noise_scale": 400, "glint_sigma": 0.002, "sigmoid_b": 6},
  "variants": [{"name": "no-aa"}, {"name": "ssaa", "aa": "ssaa", "ssaa_grid": 2}],
  "reference": {"grid": 3},
  "output": {"exr": true, "png": true, "every": 2, "contact_sheet": true}
})";

// The options of a run of DIR/FILE into DIR/out with its own cache (no report: report.cpp tests it).
RunOptions run_options(const fs::path& dir, const std::string& file, bool validation = true) {
  RunOptions opt;
  opt.report = false;
  opt.experiment = (dir / file).string();
  opt.out_dir = (dir / "out").string();
  opt.cache_dir = (dir / "cache").string();
  opt.validation = validation;
  return opt;
}

}  // namespace

TEST(Runner, RunWritesEveryMetricForEveryFrameAndVariant) {
  const glintlab::test::TempDir dir_tmp("run");
  const fs::path dir = dir_tmp.path();
  std::ofstream(dir / "tiny.json") << kTiny;
  RunOptions opt = run_options(dir, "tiny.json");
  std::ostringstream log;
  // Exit code 0 also means the validation layer reported nothing.
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();

  auto rows = read_csv(dir / "out" / "frames.csv");
  ASSERT_EQ(rows.size(), 1u + 2u * 3u);  // header + variants x frames
  const auto& h = rows[0];
  auto col = [&](const std::string& name) {
    auto it = std::find(h.begin(), h.end(), name);
    EXPECT_NE(it, h.end()) << name;
    return size_t(it - h.begin());
  };
  for (const char* m : {"deltaE2000", "deltaEITP", "flip", "psnr", "relative", "gpu_ms", "temporal_error",
                        "flicker_ratio", "pooled_bias_8", "glint_density_ref", "nan_px"})
    col(m);
  for (size_t r = 1; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].size(), h.size()) << "row " << r;
    int frame = std::stoi(rows[r][col("frame")]);
    for (const char* m : {"deltaE2000", "deltaEITP", "flip", "relative"}) {
      double v = std::stod(rows[r][col(m)]);
      EXPECT_TRUE(std::isfinite(v) && v >= 0) << m << " row " << r;
    }
    EXPECT_GT(std::stod(rows[r][col("gpu_ms")]), 0.0);
    EXPECT_EQ(rows[r][col("nan_px")], "0");
    EXPECT_EQ(rows[r][col("negative_px")], "0");
    // Temporal metrics need a previous frame.
    EXPECT_EQ(rows[r][col("flicker_ratio")].empty(), frame == 0) << "row " << r;
    EXPECT_EQ(rows[r][col("reference_cached")], "0");
  }
  // Supersampling gets closer to the footprint integral than one sample.
  auto summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  ASSERT_EQ(summary["variants"].size(), 2u);  // an array in run order
  EXPECT_EQ(summary["variants"][0]["name"], "no-aa");
  double e1 = summary["variants"][0]["metrics"]["deltaE2000"]["mean"];
  double e4 = summary["variants"][1]["metrics"]["deltaE2000"]["mean"];
  EXPECT_LT(e4, e1);
  EXPECT_EQ(summary["references"][0]["spp"], 9);
  EXPECT_EQ(summary["references"][0]["frames_rendered"], 3);
  EXPECT_TRUE(fs::exists(dir / "out" / "no-aa" / "frame_0000.exr"));
  EXPECT_TRUE(fs::exists(dir / "out" / "no-aa" / "frame_0002.png"));
  EXPECT_FALSE(fs::exists(dir / "out" / "no-aa" / "frame_0001.png"));  // every = 2
  for (const auto& e : fs::directory_iterator(dir / "out"))  // atomic writes leave no temporaries
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  // Contact sheet: rows reference, no-aa, ssaa; columns the saved frames 0 and 2 (64x36 tiles,
  // 4 px gaps, 20 px labels; layout of experiments/runner/contact_sheet.h).
  Image sheet = metrics::read_image((dir / "out" / "contact_sheet.png").string());
  EXPECT_EQ(sheet.width, 4 + 2 * (64 + 4));
  EXPECT_EQ(sheet.height, 4 + 3 * (20 + 36 + 4));

  // Second run: every reference frame comes from the cache, same numbers.
  std::ostringstream log2;
  ASSERT_EQ(run_experiment(opt, log2), 0) << log2.str();
  auto rows2 = read_csv(dir / "out" / "frames.csv");
  for (size_t r = 1; r < rows2.size(); ++r) {
    EXPECT_EQ(rows2[r][col("reference_cached")], "1");
    EXPECT_EQ(rows2[r][col("deltaE2000")], rows[r][col("deltaE2000")]);
  }

  // Corrupt one cache entry: detected, reported, rebuilt; results unchanged.
  fs::path victim;
  for (const auto& e : fs::directory_iterator(dir / "cache")) victim = e.path();
  ASSERT_FALSE(victim.empty());
  {
    std::fstream f(victim, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x7f');
  }
  std::ostringstream log3;
  ASSERT_EQ(run_experiment(opt, log3), 0) << log3.str();
  EXPECT_NE(log3.str().find("corrupt reference cache entry"), std::string::npos) << log3.str();
  auto rows3 = read_csv(dir / "out" / "frames.csv");
  for (size_t r = 1; r < rows3.size(); ++r) EXPECT_EQ(rows3[r][col("deltaE2000")], rows[r][col("deltaE2000")]);
}

TEST(Runner, BadExperimentIsExitCodeTwoWithFileAndKey) {
  const glintlab::test::TempDir dir_tmp("bad");
  const fs::path dir = dir_tmp.path();
  nlohmann::json j = nlohmann::json::parse(kTiny);
  j["variants"][1]["ssaa_grid"] = 99;
  std::ofstream(dir / "bad.json") << j.dump();
  RunOptions opt;
  opt.report = false;  // the report has its own test (report.cpp)
  opt.experiment = (dir / "bad.json").string();
  opt.out_dir = (dir / "out").string();
  std::ostringstream log;
  EXPECT_EQ(run_experiment(opt, log), 2);
  EXPECT_NE(log.str().find("bad.json"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("variants[1].ssaa_grid"), std::string::npos) << log.str();
  EXPECT_FALSE(fs::exists(dir / "out" / "frames.csv"));
}

TEST(ReferenceCache, RoundTripIsExactAndTruncationIsDetected) {
  const glintlab::test::TempDir dir_tmp("cache");
  const fs::path dir = dir_tmp.path();
  ReferenceCache cache(dir.string());
  Image img(5, 3, 4);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i) * 0.37f - 3.0f;
  std::string key(32, 'a');
  cache.store(key, img);
  bool corrupt = true;
  auto back = cache.load(key, &corrupt);
  ASSERT_TRUE(back.has_value());
  EXPECT_FALSE(corrupt);
  EXPECT_EQ(back->data, img.data);
  EXPECT_FALSE(cache.load(std::string(32, 'b')).has_value());  // absent is not corrupt
  fs::resize_file(cache.path_of(key), fs::file_size(cache.path_of(key)) - 4);
  EXPECT_FALSE(cache.load(key, &corrupt).has_value());
  EXPECT_TRUE(corrupt);
  EXPECT_FALSE(fs::exists(cache.path_of(key)));  // removed so it is rebuilt
  // The header is covered by the checksum: width and height swapped (the same pixel count) is corrupt.
  cache.store(key, img);
  {
    std::fstream f(cache.path_of(key), std::ios::in | std::ios::out | std::ios::binary);
    int32_t wh[2];
    f.seekg(8);
    f.read(reinterpret_cast<char*>(wh), sizeof wh);
    std::swap(wh[0], wh[1]);
    f.seekp(8);
    f.write(reinterpret_cast<const char*>(wh), sizeof wh);
  }
  EXPECT_FALSE(cache.load(key, &corrupt).has_value());
  EXPECT_TRUE(corrupt);
}

TEST(Runner, StaticCameraGivesIdenticalFramesAndNoFlicker) {
  // With a static camera every frame is the same picture: the reference is a
  // fixed quadrature and SSAA a fixed pattern, so nothing may change between
  // frames and the flicker ratio is exactly 1 (both sequences static).
  const glintlab::test::TempDir dir_tmp("static");
  const fs::path dir = dir_tmp.path();
  nlohmann::json j = nlohmann::json::parse(kTiny);
  j["camera_path"] = {{"type", "static"}, {"fps", 30}, {"frames", 3}, {"position", {0.5, 1.5, 3.0}},
                      {"target", {0, 0, 0}}, {"fov", 40}};
  j["output"] = {{"exr", true}, {"png", false}, {"every", 1}};
  std::ofstream(dir / "static.json") << j.dump();
  RunOptions opt = run_options(dir, "static.json");
  std::ostringstream log;
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  for (const char* d : {"reference", "no-aa", "ssaa"}) {
    Image f0 = metrics::read_image((dir / "out" / d / "frame_0000.exr").string());
    Image f2 = metrics::read_image((dir / "out" / d / "frame_0002.exr").string());
    EXPECT_EQ(f0.data, f2.data) << d;
  }
  auto summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  for (const auto& v : summary["variants"]) {
    EXPECT_EQ(v["metrics"]["flicker_ratio"]["mean"], 1.0) << v["name"];
    EXPECT_EQ(v["metrics"]["temporal_error"]["mean"], 0.0) << v["name"];
    EXPECT_EQ(v["metrics"]["temporal_error_mc"]["mean"], 0.0) << v["name"];
  }
}

// An environment map that is not a regular file (a device that never ends, a FIFO whose open
// blocks) is bad input before anything renders, not a hang.
TEST(Runner, EnvironmentMapMustBeARegularFile) {
  const glintlab::test::TempDir dir_tmp("run_hdri");
  const fs::path dir = dir_tmp.path();
  ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
  for (const std::string& hdri : {std::string("/dev/zero"), (dir / "fifo.exr").string()}) {
    nlohmann::json e = nlohmann::json::parse(kTiny);
    e["scene"]["sky"] = {{"hdri", hdri}};
    std::ofstream(dir / "hdri.json") << e.dump();
    RunOptions opt = run_options(dir, "hdri.json", false);
    std::ostringstream log;
    EXPECT_EQ(run_experiment(opt, log), 2) << hdri << " accepted";
    EXPECT_NE(log.str().find("not a regular file"), std::string::npos) << log.str();
  }
}

// The matched parameter of a density sweep: where ln(glint density ratio) crosses 0, linear between the
// neighbours that bracket it (the first crossing by value); a point at exactly 1 is its own match; no
// crossing extrapolates the end pair nearest to 1, at most two steps past the end; NaN points are left
// out and fewer than two usable points give NaN.
TEST(DensitySweep, MatchedValueInterpolatesLnRatioToZero) {
  using glintlab::SweepPoint;
  bool br = false;
  // ratio 0.5 at 6 and 2 at 8: ln crosses 0 halfway
  EXPECT_NEAR(glintlab::matched_value({{8, std::log(2.0)}, {6, std::log(0.5)}}, &br), 7.0, 1e-12);
  EXPECT_TRUE(br);
  // the first crossing by value, not by order given; NaN left out
  EXPECT_NEAR(glintlab::matched_value({{5, -1.0}, {7, NAN}, {6, 1.0}, {9, -1.0}}, &br), 5.5, 1e-12);
  EXPECT_TRUE(br);
  EXPECT_EQ(glintlab::matched_value({{5, -1.0}, {6, 0.0}, {7, 1.0}}, &br), 6.0);
  // decreasing ratios cross too
  EXPECT_NEAR(glintlab::matched_value({{1, 0.4}, {2, -0.4}}, &br), 1.5, 1e-12);
  // no crossing: extrapolated from the end nearer to 1, clamped at two steps
  EXPECT_NEAR(glintlab::matched_value({{5, -0.6}, {6, -0.4}, {7, -0.2}}, &br), 8.0, 1e-12);
  EXPECT_FALSE(br);
  EXPECT_NEAR(glintlab::matched_value({{5, -0.9}, {6, -0.8}, {7, -0.7}}, &br), 9.0, 1e-12);
  EXPECT_NEAR(glintlab::matched_value({{5, 0.2}, {6, 0.4}}, &br), 4.0, 1e-12);
  EXPECT_TRUE(std::isnan(glintlab::matched_value({{5, 0.2}, {6, 0.2}}, &br)));
  // the ratio turns back below 1 inside the sweep, or the end pair leads away: nothing to match
  EXPECT_TRUE(std::isnan(glintlab::matched_value({{5, -0.5}, {6, -0.2}, {7, -0.4}}, &br)));
  EXPECT_NEAR(glintlab::matched_value({{5, -0.2}, {6, -0.4}, {7, -0.5}, {8, -0.45}}, &br), 4.0, 1e-12);
  EXPECT_TRUE(std::isnan(glintlab::matched_value({{5, -0.4}, {6, -0.2}, {7, -0.3}}, &br)));
  EXPECT_TRUE(std::isnan(glintlab::matched_value({{5, 0.2}, {6, NAN}}, &br)));
}

// A density sweep renders the variant again at each value against the run's own truth: every row has
// the truth's glint density of the main run (the truth does not follow the swept parameter), the row
// at the variant's own value is the main run's variant to the last bit (the same material, the same
// truth), and the matched round is written where it says.
TEST(DensitySweep, RowsAreTheVariantAgainstTheRunsOwnTruth) {
  const glintlab::test::TempDir dir_tmp("sweep");
  const fs::path dir = dir_tmp.path();
  nlohmann::json j = nlohmann::json::parse(kTiny);
  j["variants"] = {{{"name", "z"}, {"material", {{"glint_model", "zirr"}, {"glints", {{"log_density", 6}}}}}}};
  j["density_sweep"] = {{"z", {{"parameter", "log_density"}, {"values", {5, 6, 7}}}}};
  j["output"] = {{"exr", false}, {"png", false}};
  std::ofstream(dir / "sweep.json") << j.dump();
  RunOptions opt = run_options(dir, "sweep.json");
  std::ostringstream log;
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  const auto& main = summary["variants"][0]["metrics"];
  const auto& rows = summary["density_sweep"]["z"];
  ASSERT_EQ(rows.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(rows[i]["parameter"], "log_density");
    EXPECT_EQ(rows[i]["value"], 5.0 + double(i));
    EXPECT_EQ(rows[i]["glint_density_ref"], main["glint_density_ref"]["mean"]) << i;
  }
  for (const char* m : {"deltaE2000", "flicker_excess", "temporal_error_mc", "glint_density_test"})
    EXPECT_EQ(rows[1][m], main[m]["mean"]) << m;
  EXPECT_NE(rows[0]["deltaE2000"], rows[2]["deltaE2000"]);  // the parameter does act
  const auto& matched = summary["matched_density"]["z"];
  EXPECT_EQ(matched["parameter"], "log_density");
  if (matched["value"].is_number()) {
    EXPECT_GE(matched["rounds"].get<int>(), 1);
    EXPECT_TRUE(fs::exists(dir / "out" / "matched-density" / "round-1" / "summary.json"));
  } else {
    EXPECT_TRUE(matched["reason"].is_string()) << matched.dump();
  }
  EXPECT_TRUE(fs::exists(dir / "out" / "density-sweep" / "z" / "summary.json"));
}

// A floor target of a temporal metric in a one-frame run has nothing to measure: exit 2 before any
// rendering, not a truth grown to max_grid on an infinite floor.
TEST(Runner, AFloorTargetTheRunCannotMeasureIsBadInput) {
  const glintlab::test::TempDir dir_tmp("floor1");
  const fs::path dir = dir_tmp.path();
  nlohmann::json j = nlohmann::json::parse(kTiny);
  j["reference"] = {{"grid", 2}, {"floor", {{"temporal_error_mc", 0.5}}}, {"max_grid", 4}};
  std::ofstream(dir / "f.json") << j.dump();
  RunOptions opt = run_options(dir, "f.json", false);
  opt.max_frames = 1;
  std::ostringstream log;
  EXPECT_EQ(run_experiment(opt, log), 2) << log.str();
  EXPECT_NE(log.str().find("reference.floor.temporal_error_mc"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("1 frame"), std::string::npos) << log.str();
  EXPECT_FALSE(fs::exists(dir / "out" / "sizing")) << "no sizing run";
}

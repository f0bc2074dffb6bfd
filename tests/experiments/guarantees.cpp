// What a run folder guarantees against careless and hostile use: one writer at a time (a lock), a
// resume or merge only of provably the same run (the content of every input file, the OCIO config
// and the device in the journal's header), journal records checked against the run, and a truth with
// NaN/Inf/negative pixels counted and never measured against.
#include "experiments/cli/check.h"
#include "experiments/runner/journal.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/runner/runner.h"
#include "metrics/color/image_io.h"

#include "core/util/json_check.h"
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

// A 4-frame orbit whose camera path is a file beside the experiment.
const char* kPath = R"({"type": "orbit", "fps": 30, "frames": 4, "center": [0, 0, 0], "radius": 3.6,
                        "height": 1.7, "start_deg": 180, "end_deg": 186, "fov": 40})";
const char* kExperiment = R"({
  "name": "guarantees",
  "resolution": [48, 27],
  "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 8, "amplitude": 0.4, "wavelength": 5}},
  "camera_path": "path.json",
  "material": {"preset": "thesis-default", "noise_scale": 400, "glint_sigma": 0.002, "sigmoid_b": 6},
  "variants": [{"name": "no-aa"}, {"name": "taa", "aa": "taa"}],
  "reference": {"grid": 2},
  "metrics": ["deltaE2000"],
  "output": {"exr": false, "png": false}
})";

struct Folder {
  test::TempDir dir{"guarantees"};
  Folder() {
    std::ofstream(dir / "path.json") << kPath;
    std::ofstream(dir / "e.json") << kExperiment;
  }
  RunOptions options(const std::string& out) const {
    RunOptions o;
    o.experiment = (dir / "e.json").string();
    o.out_dir = (dir / out).string();
    o.cache_dir = (dir / "cache").string();
    o.validation = true;
    o.report = false;
    return o;
  }
};

int run(const RunOptions& o, std::string* log_text) {
  std::ostringstream log;
  const int rc = run_experiment(o, log);
  *log_text = log.str();
  return rc;
}

}  // namespace

TEST(Guarantees, ARunFolderHasOneWriterAtATime) {
  const test::TempDir dir("lock");
  const nlohmann::json header = {{"type", "run"}};
  Journal first(dir.path(), header, false);
  try {
    Journal second(dir.path(), header, false);
    ADD_FAILURE() << "a second writer got the folder";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("another glintlab run is writing this folder"), std::string::npos) << e.what();
  }
  // Once the first is done, the folder is free again.
  { Journal moved(std::move(first)); }
  EXPECT_NO_THROW(Journal(dir.path(), header, false));
}

TEST(Guarantees, ResumeRefusesAChangedCameraPathOrOcioConfig) {
  Folder f;
  std::string log;
  RunOptions o = f.options("out");
  ASSERT_EQ(run(o, &log), 0) << log;
  o.resume = true;
  ASSERT_EQ(run(o, &log), 0) << log;  // the same inputs: nothing to do, fine
  // The camera path's file edited after the run: its frames would mix two paths.
  std::ofstream(f.dir / "path.json") << std::string(kPath).replace(std::string(kPath).find("186"), 3, "190");
  EXPECT_EQ(run(o, &log), 2) << log;
  EXPECT_NE(log.find("inputs.camera_path"), std::string::npos) << log;
  std::ofstream(f.dir / "path.json") << kPath;
  ASSERT_EQ(run(o, &log), 0) << log;
  // Another OCIO config (the shipped one with one more comment line).
  {
    std::ifstream in(GLINTLAB_OCIO_CONFIG);
    std::ofstream(f.dir / "config.ocio") << std::string(std::istreambuf_iterator<char>(in), {}) << "\n# edited\n";
  }
  o.ocio_config = (f.dir / "config.ocio").string();
  EXPECT_EQ(run(o, &log), 2) << log;
  EXPECT_NE(log.find("inputs.ocio_config"), std::string::npos) << log;
}

TEST(Guarantees, MergeRefusesShardsOfOtherInputs) {
  Folder f;
  std::string log;
  RunOptions a = f.options("shard1"), b = f.options("shard2");
  a.shard_index = 0, a.shard_count = 2;
  b.shard_index = 1, b.shard_count = 2;
  {
    std::ifstream in(GLINTLAB_OCIO_CONFIG);
    std::ofstream(f.dir / "config.ocio") << std::string(std::istreambuf_iterator<char>(in), {}) << "\n# edited\n";
  }
  b.ocio_config = (f.dir / "config.ocio").string();
  ASSERT_EQ(run(a, &log), 0) << log;
  ASSERT_EQ(run(b, &log), 0) << log;
  std::ostringstream mlog;
  EXPECT_EQ(merge_runs({a.out_dir, b.out_dir}, (f.dir / "merged").string(), false, mlog), 2) << mlog.str();
  EXPECT_NE(mlog.str().find("ocio_config"), std::string::npos) << mlog.str();
}

TEST(Guarantees, AJournalRecordOutsideTheRunIsRefused) {
  Folder f;
  std::string log;
  RunOptions o = f.options("out");
  ASSERT_EQ(run(o, &log), 0) << log;
  // A record of frame 19 of a 4-frame run (from another run's journal, or damaged).
  std::string line;
  {
    std::ifstream in(fs::path(o.out_dir) / "records.jsonl");
    std::string l;
    while (std::getline(in, l))
      if (l.find("\"type\":\"frame\"") != std::string::npos) line = l;
  }
  nlohmann::json rec = nlohmann::json::parse(line);
  rec["frame"] = 19;
  std::ofstream(fs::path(o.out_dir) / "records.jsonl", std::ios::app) << rec.dump() << "\n";
  o.resume = true;
  EXPECT_EQ(run(o, &log), 2) << log;
  EXPECT_NE(log.find("outside this run"), std::string::npos) << log;
}

// An environment map of 3e38: the truth overflows to Inf. The reference frames are scanned, their
// counts are in frames.csv, every metric measured against them is NaN, and the run exits 1 — also
// for a TAA-only run, whose resolve would otherwise turn the Inf away.
TEST(Guarantees, ANonFiniteTruthIsCountedNotHidden) {
  Folder f;
  metrics::write_exr_data((f.dir / "sky.exr").string(), Image(32, 16, 4, 3e38f));
  nlohmann::json e = nlohmann::json::parse(kExperiment);
  e["scene"]["sky"] = {{"hdri", "sky.exr"}};
  e["variants"] = nlohmann::json::array({{{"name", "taa"}, {"aa", "taa"}}});
  std::ofstream(f.dir / "e.json") << e.dump();
  std::string log;
  RunOptions o = f.options("out");
  EXPECT_EQ(run(o, &log), 1) << log;
  EXPECT_NE(log.find("measured against a reference frame with NaN, Inf or negative pixels"), std::string::npos) << log;
  std::ifstream in(fs::path(o.out_dir) / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  const auto& m = s["variants"][0]["metrics"];
  EXPECT_GT(m["reference_nonfinite_px"]["max"].get<double>(), 0.0) << m.dump();
  EXPECT_TRUE(m["deltaE2000"]["mean"].is_null()) << m.dump();
  // The TAA resolve passes the infinite current samples through instead of clamping them to 0.
  EXPECT_GT(m["nonfinite_pixels"]["max"].get<double>(), 0.0) << m.dump();
}

// Bad input is exit 2 (a ConfigError), never "a bug": a JSON file nested 10^5 deep (refused before
// any message prints it), an experiment file that is a FIFO, a missing or broken OCIO config, a
// missing or NaN-holding HDRI, a `check` file whose fields have the wrong types.
TEST(Guarantees, BadInputIsAConfigErrorNotABug) {
  Folder f;
  {
    std::string deep = "{\"metrics\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
    std::ofstream(f.dir / "deep.json") << deep;
    EXPECT_THROW(read_json_file((f.dir / "deep.json").string()), ConfigError);
    try {
      ExperimentSpec::from_json(nlohmann::json::parse(deep), "deep.json");
      ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("nested more than 64"), std::string::npos) << e.what();
    }
  }
  ASSERT_EQ(::mkfifo((f.dir / "fifo.json").c_str(), 0600), 0);
  EXPECT_THROW(read_json_file((f.dir / "fifo.json").string()), ConfigError);  // no hang

  std::string log;
  RunOptions o = f.options("out");
  o.ocio_config = (f.dir / "no-such.ocio").string();
  EXPECT_EQ(run(o, &log), 2) << log;  // bad input (exit 2), not an internal error (5)
  std::ofstream(f.dir / "broken.ocio") << "ocio_profile_version: 2.1\nroles: [this is not a config\n";
  o.ocio_config = (f.dir / "broken.ocio").string();
  EXPECT_EQ(run(o, &log), 2) << log;

  for (const char* sky : {"missing.exr", "nan.exr"}) {
    Image nan_sky(32, 16, 4, 1.0f);
    nan_sky.at(3, 3, 1) = std::nanf("");
    metrics::write_exr_data((f.dir / "nan.exr").string(), nan_sky);
    nlohmann::json e = nlohmann::json::parse(kExperiment);
    e["scene"]["sky"] = {{"hdri", sky}};
    std::ofstream(f.dir / "sky.json") << e.dump();
    RunOptions so = f.options("out-sky");
    so.experiment = (f.dir / "sky.json").string();
    EXPECT_EQ(run(so, &log), 2) << sky << ": " << log;
  }

  nlohmann::json summary = {{"schema", "glintlab-summary/1"}, {"experiment", "x"},
                            {"variants", {{{"name", 5}, {"metrics", {{"flip", {{"mean", "high"}}}}}}}}};
  std::ofstream(f.dir / "summary.json") << summary.dump();
  std::ostringstream out, err;
  EXPECT_EQ(run_check((f.dir / "summary.json").string(), (f.dir / "summary.json").string(), {}, out, err), 2)
      << err.str();
  EXPECT_NE(err.str().find("summary.json"), std::string::npos) << err.str();
}

// What the fuzzers found (tests/fuzz/crashes/): a journal whose header's "type" is a number, a
// variant name in --variants that is not UTF-8 (the journal header could not be written), a summary
// whose variant has a metric without "mean". Each is bad input or simply not a number, not a crash.
TEST(Guarantees, FuzzFindingsStayFixed) {
  const test::TempDir dir("fuzz_findings");
  std::ofstream(dir / "records.jsonl") << "{\"type\":1,\"name\":\"\"}\n{\"type\":\"frame\"}\n";
  EXPECT_THROW(Journal::load(dir.path()), ConfigError);
  // A frame index of 6.7e32 is not converted to int: the line is dropped, as a torn one is.
  {
    FrameRecord r;
    r.name = "a";
    nlohmann::json line = to_json(r);
    line["frame"] = 6.66667e32;
    std::ofstream(dir / "records.jsonl") << "{\"type\":\"run\"}\n" << line.dump() << "\n";
    const Journal j = Journal::load(dir.path());
    EXPECT_EQ(j.frames().size(), 0u);
    EXPECT_EQ(j.dropped_lines(), 1u);
  }
  // A shard header with a shard index of 6.7e32 or a "file" that is a number: merge says what it is.
  {
    const test::TempDir shard("fuzz_merge_header");
    std::ofstream(shard / "records.jsonl") << R"({"type":"run","shard":[6.7e32,2],"file":1})" << "\n";
    std::ostringstream mlog;
    EXPECT_EQ(merge_runs({shard.path().string()}, shard.path().string() + "-out", false, mlog), 2);
    EXPECT_NE(mlog.str().find("not one `glintlab run` writes"), std::string::npos) << mlog.str();
  }

  Folder f;
  RunOptions o = f.options("out");
  o.variants = {"no-aa", std::string("\x80\x80", 2)};
  std::string log;
  EXPECT_EQ(run(o, &log), 2) << log;
  EXPECT_NE(log.find("--variants"), std::string::npos) << log;

  const nlohmann::json s = {{"schema", "glintlab-summary/1"},
                            {"experiment", "x"},
                            {"variants", {{{"name", "a"}, {"metrics", {{"flip", nlohmann::json::object()}}}}}}};
  // A metric entry without a mean: bad input (exit 2 from the command), not a crash.
  EXPECT_THROW(check_summary(s, s, default_check_tolerances()), std::invalid_argument);
}

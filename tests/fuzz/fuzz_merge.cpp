// libFuzzer harness: `glintlab merge DIR... --out DIR` (glintlab::merge_runs: the shards' journals,
// their identity, completeness and disjointness, the shape of their records, the joined frames.csv
// and summary.json).
//
// Input: the records of two shards of one run, separated by a NUL byte, one JSON line each. Each
// shard's journal gets a fixed header (a tiny 3-frame experiment, shard 1/2 and 2/2, the OCIO config
// of the build) unless its part starts with '{"type":"run"', which then replaces the header (a shard
// of another run, or a damaged one). Seeds: tests/fuzz/corpus/merge/.
//
// Oracle (anything else is a finding, see fuzz_common.h): merge_runs returns 0 or 2 (or 4 for an
// output it cannot write) and throws nothing; when it returns 0, frames.csv has one row per variant
// and frame of the run.

#include "core/util/content_hash.h"
#include "experiments/runner/runner.h"
#include "experiments/sources/sequence.h"
#include "tests/fuzz/fuzz_common.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>

using namespace glintlab_fuzz;

namespace {

std::string g_dir;
nlohmann::json g_header;

const char* kExperiment = R"({"name": "fuzz-merge", "resolution": [8, 4],
  "scene": {"mesh": {"type": "plane", "size": 4, "tessellation": 2}},
  "camera_path": {"type": "static", "fps": 30, "frames": 3, "position": [0, 2, -4], "target": [0, 0, 0], "fov": 40},
  "variants": [{"name": "a"}, {"name": "b"}], "reference": {"grid": 1}, "metrics": ["deltaE2000"],
  "output": {"exr": false, "png": false}})";

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = make_temp_dir("merge");
  const nlohmann::json source = nlohmann::json::parse(kExperiment);
  g_header = {{"type", "run"},
              {"glintlab_version", "0.1.0"},
              {"command", "run"},
              {"file", g_dir + "/e.json"},
              {"source", source},
              {"content_hash", glintlab::core::hash_hex(source.dump())},
              {"overrides", nlohmann::json::object()},
              {"shard", {0, 2}},
              {"inputs", {{"ocio_config", glintlab::file_content_hash(GLINTLAB_OCIO_CONFIG)}}},
              {"device", "fuzz"}};
  write_file(g_dir + "/e.json", kExperiment);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 64 * 1024) return -1;
  const std::string in(reinterpret_cast<const char*>(data), size);
  const size_t nul = in.find('\0');
  const std::string parts[2] = {in.substr(0, nul), nul == std::string::npos ? std::string() : in.substr(nul + 1)};
  std::vector<std::string> dirs;
  for (int k = 0; k < 2; ++k) {
    const std::string d = g_dir + "/shard" + std::to_string(k + 1);
    fs::remove_all(d);
    fs::create_directories(d);
    nlohmann::json h = g_header;
    h["shard"] = {k, 2};
    const bool own_header = parts[k].rfind("{\"type\":\"run\"", 0) == 0;
    write_file(d + "/records.jsonl", (own_header ? std::string() : h.dump() + "\n") + parts[k]);
    write_file(d + "/summary.json", nlohmann::json({{"ocio_config", GLINTLAB_OCIO_CONFIG}}).dump());
    dirs.push_back(d);
  }
  const std::string out = g_dir + "/merged";
  fs::remove_all(out);
  std::ostringstream log;
  int rc = -1;
  try {
    rc = glintlab::merge_runs(dirs, out, /*report=*/false, log);
  } catch (...) {
    finding("merge-throws", current_exception_text());
    return 0;
  }
  if (rc != 0 && rc != 2 && rc != 4) finding("merge-exit-code", "merge_runs returned " + std::to_string(rc) + ": " + log.str());
  if (rc == 0) {
    std::ifstream csv(out + "/frames.csv");
    int lines = 0;
    for (std::string l; std::getline(csv, l);) ++lines;
    if (lines != 1 + 2 * 3) finding("merge-rows", "frames.csv has " + std::to_string(lines) + " lines, not 7");
  }
  return 0;
}

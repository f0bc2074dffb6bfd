// libFuzzer harness: every command's options, as a user types them (the CLI11 wiring of
// experiments/cli/*: run, render, merge, report, check, compare, measure, list, stress).
//
// Input: byte 0 picks the command, the rest is its arguments, one a line (at most 24 of at most 200
// bytes). Placeholders become files of the harness's temp folder: @img (a 48x27 EXR), @seq (a folder
// of three such frames), @vec (three 48x27 motion frames in the `pixels` convention), @sum (a
// summary.json: the CI baseline), @exp (a tiny experiment file), @run (a run folder whose journal holds
// only its header), @out (a fresh output folder). An argument with a '/' of its own is skipped (the
// harness writes nowhere but its temp folder), and run, render, measure and merge get --out @out
// unless they have one. Vulkan is made unavailable (VK_ICD_FILENAMES points nowhere), so commands that
// render stop at the device, after every option and file has been validated; the report's python is
// /nonexistent (exit 4 at once).
//
// Oracle (anything else is a finding, see fuzz_common.h): the exit code is 0, 1, 2, 3 or 4 — never 5
// ("an internal error") and nothing escapes the command; ASan/UBSan reports, timeouts and
// out-of-memory are findings too. The dictionary (tests/fuzz/options.dict) holds every option name
// and the values at the edges of their ranges.

#include "core/util/image.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "metrics/color/image_io.h"
#include "tests/fuzz/fuzz_common.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace glintlab_fuzz;

namespace {

std::string g_dir;
std::map<std::string, std::string> g_places;
unsigned long g_out = 0;

const char* const kCommands[] = {"run", "render", "merge", "report", "check", "compare", "measure", "list", "stress"};

const char* kExperiment = R"({"name": "fuzz-options", "resolution": [48, 27],
  "scene": {"mesh": {"type": "plane", "size": 4, "tessellation": 2}},
  "camera_path": {"type": "static", "fps": 30, "frames": 3, "position": [0, 2, -4], "target": [0, 0, 0], "fov": 40},
  "variants": [{"name": "no-aa"}], "reference": {"grid": 2}, "metrics": ["deltaE2000"],
  "output": {"exr": false, "png": false}})";

void make_places() {
  glintlab::Image img(48, 27, 4, 0.5f);
  for (int y = 0; y < 27; ++y)
    for (int x = 0; x < 48; ++x) img.at(x, y, 0) = 0.2f + 0.01f * float(x), img.at(x, y, 1) = 0.3f + 0.01f * float(y);
  const std::array<float, 8> rec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  glintlab::metrics::write_exr(g_dir + "/img.exr", img, rec709);
  fs::create_directories(g_dir + "/seq");
  fs::create_directories(g_dir + "/vec");
  glintlab::Image motion(48, 27, 4, 1.0f);
  for (size_t i = 0; i < motion.pixel_count(); ++i) motion.data[4 * i] = 0.5f, motion.data[4 * i + 1] = 0.25f;
  for (int k = 0; k < 3; ++k) {
    glintlab::metrics::write_exr(g_dir + "/seq/frame_000" + std::to_string(k) + ".exr", img, rec709);
    glintlab::metrics::write_exr_data(g_dir + "/vec/frame_000" + std::to_string(k) + ".exr", motion);
  }
  {
    std::ifstream in(std::string(GLINTLAB_SOURCE_DIR) + "/results/baselines/regression.json");
    write_file(g_dir + "/summary.json", std::string(std::istreambuf_iterator<char>(in), {}));
  }
  write_file(g_dir + "/exp.json", kExperiment);
  fs::create_directories(g_dir + "/run");
  nlohmann::json header = {{"type", "run"}, {"glintlab_version", "0.1.0"}, {"command", "run"},
                           {"file", g_dir + "/exp.json"}, {"source", nlohmann::json::parse(kExperiment)},
                           {"content_hash", "0"}, {"overrides", nlohmann::json::object()}, {"shard", {0, 1}}};
  write_file(g_dir + "/run/records.jsonl", header.dump() + "\n");
  g_places = {{"@img", g_dir + "/img.exr"}, {"@seq", g_dir + "/seq"},       {"@vec", g_dir + "/vec"},
              {"@sum", g_dir + "/summary.json"}, {"@exp", g_dir + "/exp.json"}, {"@run", g_dir + "/run"}};
}

// The token with its placeholders replaced, or "" when it names a path of its own.
bool expand(std::string& t) {
  if (t.find("@out") != std::string::npos) {
    const std::string out = g_dir + "/out/" + std::to_string(g_out++);
    t.replace(t.find("@out"), 4, out);
  }
  for (const auto& [k, v] : g_places) {
    const size_t at = t.find(k);
    if (at != std::string::npos) t.replace(at, k.size(), v);
  }
  if (t.find('/') != std::string::npos && t.find(g_dir) == std::string::npos) return false;
  return t.find('\0') == std::string::npos;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = make_temp_dir("options");
  ::setenv("VK_ICD_FILENAMES", "/nonexistent.json", 1);
  ::setenv("VK_DRIVER_FILES", "/nonexistent.json", 1);
  ::setenv("GLINTLAB_PYTHON", "/nonexistent", 1);
  ::unsetenv("OCIO");
  ::unsetenv("GLINTLAB_VALIDATION");
  make_places();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > 8192) return -1;
  const std::string command = kCommands[data[0] % (sizeof kCommands / sizeof *kCommands)];
  std::vector<std::string> args = {command};
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  std::string line;
  bool has_out = false;
  while (std::getline(lines, line)) {
    if (args.size() > 24 || line.size() > 200) return -1;
    if (!expand(line)) return -1;
    has_out = has_out || line.rfind("--out", 0) == 0;
    args.push_back(line);
  }
  if (!has_out && (command == "run" || command == "render" || command == "measure" || command == "merge")) {
    args.push_back("--out");
    args.push_back(g_dir + "/out/" + std::to_string(g_out++));
  }
  CLI::App app{"glintlab"};
  app.require_subcommand(1);
  int exit_code = glintlab::kExitOk;
  glintlab::add_all_commands(app, exit_code);
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 parses a reversed vector
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e) == 0 ? glintlab::kExitOk : glintlab::kExitBadInput;
  } catch (...) {
    finding("options-throws", command + ": " + current_exception_text());
  }
  if (exit_code < 0 || exit_code > 4) {
    std::string all;
    for (const auto& a : args) all += " " + a;
    finding("options-exit-code", "exit " + std::to_string(exit_code) + " for:" + all);
  }
  std::error_code ec;
  fs::remove_all(g_dir + "/out", ec);
  return 0;
}

// libFuzzer harness: the experiment-file reader (ExperimentSpec::from_json over JsonReader, and
// read_json_file for input that does not parse), the way `glintlab run FILE` reads a file.
//
// Oracle (anything else is a finding, see fuzz_common.h):
//   * input that nlohmann::json does not parse (with comments allowed, as read_json_file) must make
//     read_json_file throw glintlab::ConfigError -- tried on the bytes written to the experiment file;
//   * input that parses must make ExperimentSpec::from_json return or throw ConfigError whose
//     message names the experiment file (or the camera path file it refers to);
//     std::invalid_argument counts as a clean rejection too (the CLI maps both to exit code 2),
//     unless GLINTLAB_FUZZ_STRICT=1;
//   * an accepted spec must be usable: values within their documented ranges, every variant's
//     material passes SandParams::validate() and pack(), its debug output has a shader define, and
//     the camera path gives a camera for the first, middle and last frame at the spec's resolution;
//   * optional (GLINTLAB_FUZZ_ORACLES=ocio): every colour space, display and view named by an
//     accepted spec exists in the shipped OCIO config (the reader leaves those strings unchecked).
//
// Files: the harness works in a private temp directory ($TMPDIR/glintlab-fuzz-experiment-*); the
// experiment file is <tmp>/fuzz.json, so a camera path given as a file name is looked up in <tmp>
// (which holds a few fixtures: cam.json, cut.json, bad.json, array.json, empty.json) and in the
// project's experiments/ folder. Inputs whose "camera_path" names an absolute path or one with a
// ".." component are skipped (return -1), so nothing outside those two folders is ever read; the
// reader writes nothing.
//
// Mutation: structure-aware (json_mutator.h) with the dictionary given by -dict=, which
// tests/fuzz/run.sh generates from the reader's sources (make_dict.sh).

#include "core/material/sand_material.h"
#include "core/util/json_check.h"
#include "experiments/spec/experiment_spec.h"
#include "metrics/color/color_manager.h"
#include "metrics/color/measurement_space.h"
#include "metrics/metric_registry.h"
#include "tests/fuzz/fuzz_common.h"
#include "tests/fuzz/json_mutator.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

using namespace glintlab_fuzz;

namespace {

constexpr size_t kMaxInput = 64 * 1024;

std::string g_dir;       // private temp directory
std::string g_exp_file;  // <g_dir>/fuzz.json
JsonMutator g_mutator;
bool g_strict = false;
std::unique_ptr<glintlab::metrics::ColorManager> g_cm;  // GLINTLAB_FUZZ_ORACLES=ocio

struct Counts {
  unsigned long accepted = 0, config_error = 0, invalid_argument = 0, unparseable = 0, outside = 0;
} g_counts;

const char* kFixtures[][2] = {
    {"cam.json", R"({"type": "keyframes", "fps": 24, "frames": 5, "interpolation": "linear",
  "keyframes": [{"time": 0, "position": [0, 1, -4], "target": [0, 0, 0]},
                {"time": 0.2, "position": [1, 1, -4], "orientation": {"yaw_deg": 90, "pitch_deg": -10}, "fov": 30}]})"},
    {"cut.json", R"({"type": "keyframes", "fps": 10, "frames": 20,
  "keyframes": [{"time": 0, "position": [0, 1, -4], "target": [0, 0, 0]},
                {"time": 0.5, "position": [4, 1, 0], "target": [0, 0, 0], "cut": true},
                {"time": 1.0, "position": [0, 1, 4], "target": [0, 0, 0]}]})"},
    {"bad.json", "{\"type\": \"static\", "},
    {"array.json", "[1, 2, 3]"},
    {"empty.json", ""},
};

// True when a camera path file name stays inside the two folders the reader looks in.
bool confined(const std::string& name) {
  fs::path p(name);
  if (p.has_root_name() || p.has_root_directory()) return false;
  for (const auto& part : p)
    if (part == "..") return false;
  return true;
}

void unexpected(const std::string& where) {
  finding("exception", where + " threw " + current_exception_text());
}

void require(bool ok, const std::string& what) {
  if (!ok) finding("accepted-invalid", what);
}

void check_names_file(const std::string& message) {
  if (message.find(g_dir) == std::string::npos && message.find(GLINTLAB_EXPERIMENT_DIR) == std::string::npos)
    finding("error-without-file", "ConfigError does not name the experiment file: " + message);
}

void check_ocio_names(const glintlab::ExperimentSpec& s) {
  auto has_view = [&](const std::string& display, const std::string& view) {
    auto ds = g_cm->displays();
    if (std::find(ds.begin(), ds.end(), display) == ds.end()) return false;
    auto vs = g_cm->views(display);
    return std::find(vs.begin(), vs.end(), view) != vs.end();
  };
  if (!g_cm->has_space(s.sky.sun.color_space))
    finding("ocio-names", "accepted scene.sky.sun_color_space \"" + s.sky.sun.color_space + "\" is not in the OCIO config");
  if (!s.sky.hdri_color_space.empty() && !g_cm->has_space(s.sky.hdri_color_space))
    finding("ocio-names", "accepted scene.sky.hdri_color_space \"" + s.sky.hdri_color_space + "\" is not in the OCIO config");
  if ((s.output.png || s.output.contact_sheet) && !has_view(s.output.display, s.output.view))
    finding("ocio-names", "accepted output display/view \"" + s.output.display + "\"/\"" + s.output.view +
                              "\" is not in the OCIO config");
  if (!s.metric_options.display_view.empty()) {
    auto dv = glintlab::metrics::parse_display_view(s.metric_options.display_view);
    if (!has_view(dv.first, dv.second))
      finding("ocio-names", "accepted metric_options.view \"" + s.metric_options.display_view +
                                "\" is not in the OCIO config");
  }
}

// Invariants of an accepted spec (experiment_spec.h and the headers it cites).
void check_spec(const glintlab::ExperimentSpec& s, const nlohmann::json& j) {
  require(s.source == j, "spec.source differs from the JSON read");
  require(s.width >= 1 && s.width <= 16384 && s.height >= 1 && s.height <= 16384, "resolution out of range");
  require(s.working_space == "lin_rec709" || s.working_space == "ACEScg", "working_space " + s.working_space);
  require(s.path.frames() >= 1 && s.frames >= 1 && s.frames <= s.path.frames(),
          "frames " + std::to_string(s.frames) + " outside [1, path frames " + std::to_string(s.path.frames()) + "]");
  require(s.path.fps() > 0, "camera path fps <= 0");
  require(!s.variants.empty() && s.variants.size() <= 64, "variant count " + std::to_string(s.variants.size()));
  std::set<std::string> names;
  for (const auto& v : s.variants) {
    require(!v.name.empty() && names.insert(v.name).second, "variant name \"" + v.name + "\" empty or repeated");
    require(v.ssaa_grid >= 1 && v.ssaa_grid <= 16 && v.samples_per_pixel() >= 1, "ssaa_grid " + std::to_string(v.ssaa_grid));
    require(v.aa == glintlab::AaMethod::Ssaa || v.ssaa_grid == 1, "ssaa_grid set without ssaa");
    for (size_t i = 0; i < v.taa.values.size(); ++i) {
      const auto& p = v.taa.resolve->parameters[i];
      require(v.taa.values[i] >= p.lo && v.taa.values[i] <= p.hi, "taa." + p.name + " out of range");
    }
    try {
      v.material.validate();
      (void)v.material.pack();
      (void)glintlab::core::SandParams::debug_output_define(v.debug);
    } catch (...) {
      finding("accepted-invalid", "variant \"" + v.name + "\" was accepted, but its material or debug output fails: " +
                                      current_exception_text());
    }
  }
  require(s.reference.grid >= 1 && s.reference.grid <= 64, "reference.grid out of range");
  require(s.output.every >= 1, "output.every < 1");
  require(s.output.contact_sheet_columns >= 1 && s.output.contact_sheet_columns <= 64, "contact_sheet_columns");
  const auto allowed = glintlab::metrics::metric_names();
  for (const auto& m : s.metrics)
    require(std::find(allowed.begin(), allowed.end(), m) != allowed.end(), "unknown metric " + m);
  require(s.metric_options.itp_luminance_nits > 0 && s.metric_options.flip_ppd >= 1, "metric options out of range");
  for (int k : {0, s.frames / 2, s.frames - 1}) {
    try {
      (void)s.path.frame(k, s.width, s.height);
    } catch (...) {
      finding("accepted-invalid", "camera path \"" + s.path_name + "\" was accepted, but frame " + std::to_string(k) +
                                      " at " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                      " fails: " + current_exception_text());
    }
  }
  if (g_cm) check_ocio_names(s);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  g_dir = make_temp_dir("experiment");
  g_exp_file = g_dir + "/fuzz.json";
  for (const auto& f : kFixtures) write_file(g_dir + "/" + f[0], std::string(f[1]));
  fs::create_directory(g_dir + "/dir.json");  // a name that exists but is no file
  const std::string dict = fuzzer_flag(*argc, *argv, "dict");
  if (!dict.empty()) g_mutator.tokens = dictionary_strings(dict);
  const char* strict = std::getenv("GLINTLAB_FUZZ_STRICT");
  g_strict = strict && std::string(strict) == "1";
  const char* oracles = std::getenv("GLINTLAB_FUZZ_ORACLES");
  if (oracles && std::string(oracles).find("ocio") != std::string::npos)
    g_cm = std::make_unique<glintlab::metrics::ColorManager>(GLINTLAB_OCIO_CONFIG);
  std::atexit([] {
    std::fprintf(stderr,
                 "glintlab fuzz: experiment: %lu accepted, %lu ConfigError, %lu invalid_argument, %lu unparseable, "
                 "%lu skipped (camera path outside the sandbox); %zu dictionary strings\n",
                 g_counts.accepted, g_counts.config_error, g_counts.invalid_argument, g_counts.unparseable,
                 g_counts.outside, g_mutator.tokens.size());
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > kMaxInput) return -1;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception&) {
    // Not JSON: the file reader must say so as a ConfigError naming the file.
    ++g_counts.unparseable;
    write_file(g_exp_file, data, size);
    try {
      (void)glintlab::read_json_file(g_exp_file);
      finding("parse-mismatch", "read_json_file accepted a file that nlohmann::json::parse rejects");
    } catch (const glintlab::ConfigError& e) {
      check_names_file(e.what());
    } catch (...) {
      unexpected("read_json_file");
    }
    return 0;
  }
  if (j.is_object()) {
    auto it = j.find("camera_path");
    if (it != j.end() && it->is_string() && !confined(it->get<std::string>())) {
      ++g_counts.outside;
      return -1;
    }
  }
  try {
    glintlab::ExperimentSpec s = glintlab::ExperimentSpec::from_json(j, g_exp_file);
    ++g_counts.accepted;
    check_spec(s, j);
  } catch (const glintlab::ConfigError& e) {
    ++g_counts.config_error;
    check_names_file(e.what());
  } catch (const std::invalid_argument& e) {
    ++g_counts.invalid_argument;
    if (g_strict) finding("invalid-argument", std::string("ExperimentSpec::from_json threw std::invalid_argument: ") + e.what());
  } catch (...) {
    unexpected("ExperimentSpec::from_json");
  }
  return 0;
}

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size, unsigned int seed) {
  std::mt19937_64 rng(seed);
  if (rng() % 6 != 0) {
    try {
      nlohmann::json j = nlohmann::json::parse(data, data + size, nullptr, true, true);
      g_mutator.mutate(j, rng);
      if (size_t n = write_json(j, data, max_size, rng() % 8 == 0)) return n;
    } catch (const nlohmann::json::exception&) {
    }
  }
  return LLVMFuzzerMutate(data, size, max_size);
}

extern "C" size_t LLVMFuzzerCustomCrossOver(const uint8_t* d1, size_t s1, const uint8_t* d2, size_t s2, uint8_t* out,
                                            size_t max_out, unsigned int seed) {
  std::mt19937_64 rng(seed);
  try {
    nlohmann::json a = nlohmann::json::parse(d1, d1 + s1, nullptr, true, true);
    nlohmann::json b = nlohmann::json::parse(d2, d2 + s2, nullptr, true, true);
    g_mutator.cross_over(a, b, rng);
    if (size_t n = write_json(a, out, max_out, false)) return n;
  } catch (const nlohmann::json::exception&) {
  }
  // Not both JSON: one-point byte crossover.
  size_t n1 = s1 ? rng() % (s1 + 1) : 0, n2 = s2 ? rng() % (s2 + 1) : 0;
  size_t n = std::min(max_out, n1 + (s2 - n2));
  std::memcpy(out, d1, std::min(n, n1));
  if (n > n1) std::memcpy(out + n1, d2 + n2, n - n1);
  return n;
}

// libFuzzer harness: `glintlab check SUMMARY BASELINE [--tolerance metric=x ...]` (glintlab::run_check:
// read_json_file of both, check_summary, the table).
//
// Input: up to three parts separated by a NUL byte: the summary file, the baseline file (default: the
// summary again) and tolerance arguments, one a line. Seeds: results/baselines/*.json.
//
// Oracle (anything else is a finding, see fuzz_common.h): run_check returns 0, 1 or 2 and throws
// nothing — a field of the wrong type, a missing key, a number where a string belongs or a JSON
// nested 10^5 deep are bad input (2), not a crash or an internal error. When it compares (0 or 1),
// what it accepted is checked here, independently of check.cpp: every --tolerance line is
// "name=x" with x a whole finite decimal >= 0 and no name twice; both files are JSON objects whose
// variant names are unique; no metric mean of either is a string or a negative ΔE00; every gated
// metric of the baseline (the defaults and those given) has a number for its mean where it has a
// mean; the baseline's floors (references[].floor) are numbers >= 0 of metrics that have a floor, of
// uniquely named truths, no larger than the largest mean of the metric measured against that truth
// (a floor widens what the gate allows); and the last line counts the checks.

#include "experiments/cli/check.h"
#include "metrics/metric_registry.h"
#include "tests/fuzz/fuzz_common.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace glintlab_fuzz;

namespace {
std::string g_dir;

// What a comparison (exit 0 or 1) must not have accepted; "" when nothing.
std::string accepted_bad_input(const std::string& summary, const std::string& baseline,
                               const std::vector<std::string>& tolerances, const std::string& out) {
  std::set<std::string> gated, named;
  for (const auto& [m, x] : glintlab::default_check_tolerances()) gated.insert(m);
  for (const std::string& t : tolerances) {
    const size_t eq = t.find('=');
    if (eq == std::string::npos || eq == 0) return "tolerance without a name: " + t;
    const std::string value = t.substr(eq + 1);
    char* end = nullptr;
    const double x = value.empty() || std::isspace(static_cast<unsigned char>(value[0])) ? -1 : std::strtod(value.c_str(), &end);
    if (!end || *end != '\0' || !std::isfinite(x) || x < 0) return "tolerance not a plain number >= 0: " + t;
    if (!named.insert(t.substr(0, eq)).second) return "tolerance given twice: " + t;
    gated.insert(t.substr(0, eq));
  }
  for (const std::string* text : {&summary, &baseline}) {
    const nlohmann::json j = nlohmann::json::parse(*text, nullptr, false, true);
    if (!j.is_object() || !j.contains("variants") || !j["variants"].is_array()) return "not a summary";
    std::set<std::string> names;
    for (const auto& v : j["variants"]) {
      if (!v.is_object() || !v.contains("name") || !v["name"].is_string()) return "a variant without a name";
      if (!names.insert(v["name"].get<std::string>()).second) return "a variant named twice";
      if (!v.contains("metrics") || !v["metrics"].is_object()) return "a variant without metrics";
      for (const auto& [metric, entry] : v["metrics"].items()) {
        if (!entry.is_object() || !entry.contains("mean")) continue;
        const auto& mean = entry["mean"];
        if (mean.is_string()) return "a mean that is a string: " + metric;
        if (metric == "deltaE2000" && mean.is_number() && mean.get<double>() < 0) return "a negative deltaE2000";
        if (text == &baseline && gated.count(metric) && !mean.is_number()) return "a gated baseline mean not a number";
      }
    }
  }
  const nlohmann::json base = nlohmann::json::parse(baseline, nullptr, false, true);
  if (base.contains("references") && base["references"].is_array()) {
    std::set<std::string> truths;
    for (const auto& r : base["references"]) {
      if (!r.is_object() || !r.contains("name") || !r["name"].is_string()) return "a truth without a name";
      if (!truths.insert(r["name"].get<std::string>()).second) return "two truths of one name";
      if (!r.contains("floor")) continue;
      if (!r["floor"].is_object()) return "a floor that is not an object";
      for (const auto& [metric, f] : r["floor"].items()) {
        if (!glintlab::metrics::has_noise_floor(metric)) return "a floor of a metric without one: " + metric;
        if (!f.is_number() || !std::isfinite(f.get<double>()) || f.get<double>() < 0)
          return "a floor that is not a number >= 0: " + metric;
        double largest = -1;
        for (const auto& v : base["variants"])
          if (v.is_object() && v.value("reference", nlohmann::json()) == r["name"] && v["metrics"].contains(metric) &&
              v["metrics"][metric].is_object() && v["metrics"][metric].value("mean", nlohmann::json()).is_number())
            largest = std::max(largest, v["metrics"][metric]["mean"].get<double>());
        if (largest >= 0 && f.get<double>() > largest) return "a floor above every mean measured against it: " + metric;
      }
    }
  }
  if (out.find(" checks against ") == std::string::npos) return "no count of checks";
  return "";
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = make_temp_dir("check");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 256 * 1024) return -1;
  const std::string in(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  size_t start = 0;
  while (parts.size() < 2) {
    const size_t nul = in.find('\0', start);
    if (nul == std::string::npos) break;
    parts.push_back(in.substr(start, nul - start));
    start = nul + 1;
  }
  parts.push_back(in.substr(start));
  const std::string summary = g_dir + "/summary.json", baseline = g_dir + "/baseline.json";
  write_file(summary, parts[0]);
  write_file(baseline, parts.size() > 1 ? parts[1] : parts[0]);
  std::vector<std::string> tolerances;
  if (parts.size() > 2) {
    std::istringstream lines(parts[2]);
    std::string line;
    while (std::getline(lines, line) && tolerances.size() < 16) tolerances.push_back(line);
  }
  std::ostringstream out, err;
  int rc = -1;
  try {
    rc = glintlab::run_check(summary, baseline, tolerances, out, err);
  } catch (...) {
    finding("check-throws", current_exception_text());
    return 0;
  }
  if (rc < 0 || rc > 2) finding("check-exit-code", "run_check returned " + std::to_string(rc) + ": " + err.str());
  if (rc == 0 || rc == 1) {
    const std::string why = accepted_bad_input(parts[0], parts.size() > 1 ? parts[1] : parts[0], tolerances, out.str());
    if (!why.empty()) finding("check-accepted-bad-input", why);
  }
  return 0;
}

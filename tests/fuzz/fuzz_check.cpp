// libFuzzer harness: `glintlab check SUMMARY BASELINE [--tolerance metric=x ...]` (glintlab::run_check:
// read_json_file of both, check_summary, the table).
//
// Input: up to three parts separated by a NUL byte: the summary file, the baseline file (default: the
// summary again) and tolerance arguments, one a line. Seeds: results/baselines/*.json.
//
// Oracle (anything else is a finding, see fuzz_common.h): run_check returns 0, 1 or 2 and throws
// nothing — a field of the wrong type, a missing key, a number where a string belongs or a JSON
// nested 10^5 deep are bad input (2), not a crash or an internal error.

#include "experiments/cli/check.h"
#include "tests/fuzz/fuzz_common.h"

#include <sstream>
#include <string>
#include <vector>

using namespace glintlab_fuzz;

namespace {
std::string g_dir;
}

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
  return 0;
}

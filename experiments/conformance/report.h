// The report of a conformance suite (`glintlab glint-test`, `glintlab taa-test`): checks, each a
// figure with a bound, declared by the file under test (checks=) or declared as the published
// design's own failures (fails=: run, expected to fail, flagged when they pass), and figures without a
// bound. One report type, one text and one JSON form for both suites.
#pragma once

#include "core/vk/vk_context.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace glintlab {

struct ConformanceCheck {
  std::string name;
  bool applies = true;  // declared by the file (figures always apply)
  // Declared in fails=: the published method fails it by design; the suite
  // passes when it fails and flags it when it passes.
  bool expected_failure = false;
  bool figure_only = false;
  bool pass = true;
  double figure = 0.0;
  double bound = 0.0;
  std::string unit;    // how figure and bound read
  std::string detail;  // what was evaluated
};

struct ConformanceReport {
  std::string suite;        // "glint-test", "taa-test"
  std::string subject_key;  // the JSON key of the subject: "model", "resolve"
  std::string subject, file, device;
  nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
  std::vector<ConformanceCheck> checks;
  bool all_pass() const;  // every applying pass/fail check passes (declared failures fail)
  nlohmann::ordered_json json() const;
  std::string text() const;
  const ConformanceCheck* check(const std::string& name) const;
};

// Marks `c` as applying, expected to fail or not, from a declaration's checks= and fails= lists.
void apply_declaration(ConformanceCheck& c, const std::vector<std::string>& checks, const std::vector<std::string>& fails);

// A conformance command: `NAME SUBJECT [--parameters k=v ...] [--json] [--device D] [--validation]`.
// `prepare` checks the subject and its parameters before any device is opened (ConfigError: exit 2;
// ShaderCompileError: exit 3) and returns the suite to run on the device; the command prints the
// report (text, or JSON with --json) and exits 1 when a check fails or the validation layer spoke.
// `extra_options` adds the suite's own options to the command.
struct ConformanceCommandOptions {
  std::string subject, device;
  std::vector<std::string> parameters;
};
using ConformanceSuite = std::function<ConformanceReport(core::VkContext&)>;
void add_conformance_command(CLI::App& app, int& exit_code, const std::string& name, const std::string& description,
                             const std::string& subject_name, const std::string& subject_help,
                             std::function<ConformanceSuite(const ConformanceCommandOptions&)> prepare,
                             const std::function<void(CLI::App&)>& extra_options = {});

}  // namespace glintlab

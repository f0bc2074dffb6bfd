// `glintlab stress`: the numerical-stability suite (stiff and extreme
// inputs). Every case drives the real shader
// code on extreme inputs -- through the renderer (core::SurfaceRenderer,
// core::FrameGraph, build_variant, core::TaaPass) at a small resolution, or
// through the compute harness (core::run_compute) against the fp64 twins of
// core/testkit -- and reports the pixels (or outputs) that are not
// finite or negative, the largest relative error against the fp64 reference
// where one exists, and the energy or range bounds that apply. The cases, their
// bounds and what they found are listed in experiments/stress/README.md.
//
//   StressOptions o;  o.fast = true;
//   StressReport r = run_stress(o, std::cerr);   // progress on the stream
//   std::cout << stress_json(r).dump(2);          // {"cases": [...], ...}
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

struct StressOptions {
  bool fast = false;         // the CI subset (< 30 s on two cores); else every case (< 5 min)
  bool validation = false;   // Vulkan validation layers (a message fails the case that caused it)
  std::string device;        // "" = lavapipe (core::ContextOptions::device)
  std::vector<std::string> only;  // non-empty: only the cases whose name contains one of these
};

struct StressCaseResult {
  std::string name;
  std::string category;  // "sand", "glint", "math", "render", "taa"
  size_t nonfinite = 0;  // outputs (pixels) that are NaN or infinite
  size_t negative = 0;   // outputs (pixels) below zero where the quantity is non-negative
  // Largest relative error against the fp64 reference (null: none exists for the case).
  std::optional<double> max_rel_error;
  std::optional<double> bound;  // the stated bound on max_rel_error
  bool pass = false;
  std::string detail;            // what was compared, the bounds, why it failed
  size_t items = 0;              // outputs (pixels x frames, or evaluations) checked
  size_t compared = 0;           // of which compared against the fp64 reference
  nlohmann::json extra = nlohmann::json::object();  // energy ratios, ranges, ...
  double ms = 0;                 // wall time of the case
};

struct StressReport {
  std::vector<StressCaseResult> cases;
  double wall_s = 0;
  std::string device;
  bool fast = false;
  bool validation = false;
  bool all_pass() const;
};

// The names of the cases run_stress would run (in order).
std::vector<std::string> stress_case_names(bool fast);

// Runs the suite on a fresh Vulkan context. Progress (one line per case) goes
// to `progress`. Throws what the renderer throws when the device fails.
StressReport run_stress(const StressOptions& options, std::ostream& progress);

// {"cases": [{"name", "nonfinite", "negative", "max_rel_error", "pass", then "bound", "category", "items",
// "compared", "detail", "ms" and the case's own keys (energy_ratio, range_ratio, ...)}]}; null for a
// missing or non-finite number.
nlohmann::ordered_json stress_json(const StressReport& report);
// One line per case and a summary (with the wall time).
void print_stress_text(const StressReport& report, std::ostream& out);

}  // namespace glintlab

// `glintlab check SUMMARY BASELINE [--tolerance metric=x ...]`: the
// regression gate. Compares the per-variant metric means of a run's
// summary.json with a committed baseline (results/baselines/*.json, a
// summary.json of the same experiment) and fails when one got worse by more
// than its tolerance.
//
// "Worse" per metric: larger for errors (deltaE2000, flip, temporal_error,
// temporal_error_mc, temporal_score, pooled_error, deltaEITP, relative, glint_hist_emd_oct, and
// flicker_contrast, the flicker of a test alone that `measure` gives without a reference);
// farther from 1 for flicker_ratio and frame_diff_ratio, measured as
// |log(ratio)|; smaller for psnr; any increase of nonfinite_pixels or
// negative_pixels (tolerance 0). A variant or metric of the baseline that the
// summary lacks is a regression too; a metric that is null (not finite) in the
// summary but finite in the baseline is one.
//
// Tolerance of a metric: the worsening allowed, relative to the baseline
// value (|log| for ratios: 0.05 allows a 5 % move away from 1). The defaults
// (kDefaultTolerances) are set from the spread of the CI regression
// experiment between repeated runs and lavapipe thread counts (experiments/README.md,
// "Regression check"); --tolerance metric=x overrides one.
#pragma once

#include <nlohmann/json.hpp>

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

struct CheckRow {
  std::string variant, metric;
  double baseline = 0, current = 0;
  double change = 0;      // worsening in the metric's own sense (> 0 worse), relative or |log|
  double tolerance = 0;
  bool regression = false;
  bool skipped = false;   // the baseline's variant does not have the metric: nothing to guard
  std::string note;       // why, when it is not a number comparison
  double floor = 0;       // > 0: the tolerance was raised to the truth's noise floor (relative to the baseline)
};

// Default tolerances by metric (see above).
const std::map<std::string, double>& default_check_tolerances();

// The default tolerances with `args` ("metric=x") applied. Throws std::invalid_argument for a
// metric the gate cannot guard (not declared in metrics/metric_registry.h, exactly as spelled, or
// pooled_bias_<s>, which is signed), a value that is not a finite decimal number >= 0 with nothing
// after it, or a metric given twice.
std::map<std::string, double> parse_check_tolerances(const std::vector<std::string>& args);

// Validates both files, then compares `summary` with `baseline`. Only metrics with a tolerance are
// checked; a metric the baseline's variant lacks gives a row marked `skipped`.
// Throws std::invalid_argument naming the file (`summary_file`, `baseline_file`) when either is not a
// glintlab summary (schema glintlab-summary/1, a string "experiment", "variants" with unique non-empty
// names, metric entries with a "mean"), when a mean is neither null nor a finite number in the metric's
// declared range (metrics::value_range), when the baseline's mean of a gated metric is null (it cannot
// gate it), or when the experiments differ. A null mean in the summary (a NaN frame of the run) is a
// regression, not an error.
std::vector<CheckRow> check_summary(const nlohmann::json& summary, const nlohmann::json& baseline,
                                    const std::map<std::string, double>& tolerances,
                                    const std::string& summary_file = "the summary",
                                    const std::string& baseline_file = "the baseline");

// The CLI: prints a table to `out`; 0 no regression, 1 a regression, 2 bad input (exit_codes.h).
int run_check(const std::string& summary_path, const std::string& baseline_path,
              const std::vector<std::string>& tolerance_args, std::ostream& out, std::ostream& err);

}  // namespace glintlab

// `glintlab tune`: a multi-objective search over the options of one variant of an experiment, on
// Optuna (experiments/tune/glintlab_tune.py drives it; every trial is a `glintlab run` of the
// experiment with only that variant, its references from the shared cache).
//
// This side checks everything before any trial runs and fixes the study's definition:
//   - the experiment loads; --base names one of its variants (a rendered one, not "frames");
//   - every --space KEY=RANGE: KEY a dotted path into the variant ("taa.alpha", "ssaa_grid",
//     "material.glint_sigma"); RANGE "lo:hi" (numbers, lo < hi; integers when both are), "lo:hi:log"
//     (lo > 0), or "a,b,..." (choices, each JSON or a bare string). The variant with each end of the
//     range (each choice) set at KEY must pass the experiment schema: the schema's message names the
//     key and what it allows;
//   - every objective is a metric of the summary or gpu_ms (objective_names()); the command line
//     defaults to temporal_score,deltaE2000,gpu_ms (temporal stability as a viewer ranks it, colour
//     error, cost);
//   - the study folder: DIR/study.json holds the definition; a folder holding another study (other
//     experiment, base, space or objectives) is refused; the same definition is joined (several
//     workers, on one machine or under a scheduler, share one study).
// Then it writes DIR/study.json (atomically, under DIR/.tune.lock) and DIR/experiment.json (the
// experiment as it was when the study began) and runs the Python driver.
#pragma once

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

struct TuneOptions {
  std::string experiment;            // a file or a built-in name
  std::string base;                  // the variant whose options are searched
  std::vector<std::string> space;    // KEY=RANGE
  std::vector<std::string> objectives;
  int trials = 0;                    // the study's total of finished trials
  std::string study_dir;             // default results/tune/<experiment>-<base>
  int workers = 1;
  bool resume = false;
  int seed = 1;
  std::string sampler = "tpe";       // tpe (multi-objective TPE) or nsga2
  std::string storage = "sqlite";    // sqlite (one machine) or journal (a shared file system)
  std::string cache_dir;             // reference cache (default results/cache/reference)
  std::string device;
};

// Objectives a study may minimise: flicker_ratio and glint_density_ratio as |ln ratio|, gpu_ms, and
// every per-frame metric of the summary as its mean.
std::vector<std::string> objective_names();

// The checked definition of a study (what DIR/study.json holds, without its paths), or a ConfigError.
nlohmann::json tune_definition(const TuneOptions& o, const nlohmann::json& experiment, const std::string& file);

// Checks, writes the study folder's definition and runs the driver; an exit code (exit_codes.h).
int tune(const TuneOptions& o, std::ostream& log);

}  // namespace glintlab

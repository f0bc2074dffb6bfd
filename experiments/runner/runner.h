// Runs an experiment: builds the scene once, plans the variants and their
// references, renders and measures the frames this invocation owns (all of
// them, a --shard, or what a --resume still lacks), journals every record as
// it finishes (experiments/runner/journal.h) and writes frames.csv,
// summary.json, images and the report from the journal.
#pragma once

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

struct RunOptions {
  std::string experiment;     // built-in name or file
  std::string out_dir;        // created if missing
  std::string device;         // "" = default (lavapipe)
  std::string ocio_config;    // "" = $OCIO, else the shipped config
  std::string cache_dir;      // "" = results/cache in the source tree
  bool measure = true;        // false: `render` (no reference, no metrics)
  bool validation = false;    // Vulkan validation layers (tests, CI)
  int max_frames = 0;         // > 0: only the first n frames
  std::vector<std::string> variants;  // non-empty: only these variants, in this order
  int width = 0, height = 0;          // > 0: override the experiment's resolution
  int shard_index = 0, shard_count = 1;  // --shard k/n (k counted from 1 on the command line)
  bool resume = false;        // continue the run in out_dir (journal) instead of starting over
  bool report = true;         // write report.html at the end
  // > 0: the truth's grid instead of the experiment's (the runs that size a truth by its noise floor,
  // "reference": {"floor": ...}, and the run at the grid they chose; recorded as an override).
  int reference_grid = 0;
  bool images = true;         // false: no EXR or PNG (the sizing runs)
  // Not null: the experiment's JSON instead of the file's content (the runs of a density sweep, whose
  // variants are derived from the file's); `experiment` still names the file (relative paths, messages).
  nlohmann::json source;
  bool density_sweep = true;  // false: skip the experiment's "density_sweep" (the truth's sizing runs)
};

// Returns the process exit code (experiments/cli/exit_codes.h): 0 ok, 1 a
// frame had NaN/Inf/negative pixels or the validation layer reported something
// (the run still completes and reports them), 2 bad input, 3 the device, 4 I/O,
// 5 internal (what the run throws, mapped by run_guarded and printed on `log`).
int run_experiment(const RunOptions& options, std::ostream& log);

// The default output folder of a run: results_path(<the experiment's name>) (core/util/data_dir.h).
// Throws ConfigError when the experiment cannot be loaded.
std::string default_run_dir(const std::string& experiment);

// --resolution "WxH" into `options` (width, height); "" when it is one, else the message that says
// what is allowed.
std::string set_resolution(const std::string& text, RunOptions& options);

// `glintlab merge DIR... --out DIR`: joins the journals of the shards of one
// run into frames.csv, summary.json, images and the report, identical in
// metrics to a single run. Exit 2 when the shards are not of one run, are
// missing or overlap.
int merge_runs(const std::vector<std::string>& shard_dirs, const std::string& out_dir, bool report, std::ostream& log);

}  // namespace glintlab

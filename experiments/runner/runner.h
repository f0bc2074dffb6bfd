// Runs an experiment: builds the scene once, renders every variant's frames
// (and, for `run`, the cached ground-truth reference), measures every frame
// and writes frames.csv, summary.json and the requested images.
#pragma once

#include <ostream>
#include <string>

namespace glintlab {

struct RunOptions {
  std::string experiment;     // built-in name or file
  std::string out_dir;        // created if missing
  std::string device;         // "" = default (lavapipe)
  std::string ocio_config;    // "" = $OCIO, else the shipped config
  std::string cache_dir;      // "" = results/cache in the source tree
  bool measure = true;        // false: `render` (no reference, no metrics)
  bool validation = false;    // Vulkan validation layers (tests, CI)
  int max_frames = 0;         // > 0: render only the first n frames
};

// Returns the process exit code (experiments/cli/exit_codes.h): 0 ok, 1 a
// frame had NaN/Inf/negative pixels or the validation layer reported something
// (the run still completes and reports them), 2 bad input. Device and I/O
// failures throw (core::VulkanError, IoError).
int run_experiment(const RunOptions& options, std::ostream& log);

}  // namespace glintlab

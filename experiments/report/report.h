// The run report: DIR/report.html, one self-contained page (plots inline as
// SVG, images and animations as data URIs, nothing fetched) with error against
// GPU cost and its Pareto fronts, per-frame curves, the table of means, crops of
// one automatically chosen glint region and side-by-side sequences; every plot
// also as DIR/figures/*.svg|pdf. Written by experiments/report/glintlab_report.py
// (matplotlib, PIL, numpy; MP4 through ffmpeg where it is installed), which
// write_report runs with Debian's python3. `glintlab report DIR` calls it for an
// existing run (add_report_command, declared in experiments/cli/commands.h).
#pragma once

#include <ostream>
#include <string>

namespace glintlab {

// Writes run_dir/report.html and run_dir/figures/ for the run in run_dir;
// the script's progress and errors go to `log`. Returns an exit code
// (experiments/cli/exit_codes.h) and throws nothing:
//   0  written
//   2  bad input: run_dir is not a directory, has no summary.json, or its
//      summary.json / frames.csv is not a glintlab run's (the message names
//      the file and the key)
//   4  I/O failure: a file could not be read or written, or the report cannot
//      run here: no python3, python3 without numpy / matplotlib / PIL (the
//      message names the Debian packages to install), the script is missing
//   5  internal error: the script failed (its trace is in `log`)
// Interpreter: $GLINTLAB_PYTHON if set, else /usr/bin/python3 (where Debian's
// python3-matplotlib lives), else python3 on PATH. Script:
// $GLINTLAB_REPORT_SCRIPT if set, else report_script_path().
int write_report(const std::string& run_dir, std::ostream& log);

// The report script in the source tree (experiments/report/glintlab_report.py).
std::string report_script_path();

}  // namespace glintlab

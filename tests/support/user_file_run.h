// What the tests of a user's shader file (glint model, TAA resolve) share: the options of a small run
// of an experiment file (validation on, no report, its truths cached beside its output), and writing
// and reading the files they change (tests/support/temp_dir.h).
#pragma once

#include "experiments/runner/runner.h"
#include "tests/support/temp_dir.h"  // write_text, read_text

#include <filesystem>

namespace glintlab::test {

inline RunOptions user_file_run_options(const std::filesystem::path& exp, const std::filesystem::path& out) {
  RunOptions o;
  o.experiment = exp.string();
  o.out_dir = out.string();
  o.cache_dir = (out.parent_path() / "cache").string();
  o.validation = true;
  o.report = false;
  return o;
}

}  // namespace glintlab::test

// What the tests of a user's shader file (glint model, TAA resolve) share: the options of a small run
// of an experiment file (validation on, no report, its truths cached beside its output), and writing
// and reading the files they change.
#pragma once

#include "experiments/runner/runner.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

inline void write_text(const std::filesystem::path& p, const std::string& text) { std::ofstream(p) << text; }

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace glintlab::test

// The glintlab commands. Each adds its subcommand (options, help) to the app
// and, when it was chosen, runs from CLI11's callback and stores its exit code
// (experiments/cli/exit_codes.h) in `exit_code`. main() only wires them up.
#pragma once

#include <CLI/CLI.hpp>

namespace glintlab {

void add_run_commands(CLI::App& app, int& exit_code);      // render, run
void add_compare_command(CLI::App& app, int& exit_code);   // compare (experiments/cli/compare.cpp)
void add_measure_command(CLI::App& app, int& exit_code);   // measure (experiments/sources/)
void add_list_command(CLI::App& app, int& exit_code);      // list
void add_check_command(CLI::App& app, int& exit_code);     // check (experiments/cli/check.cpp)
void add_report_command(CLI::App& app, int& exit_code);    // report (experiments/report/report.cpp)
void add_stress_command(CLI::App& app, int& exit_code);    // stress (experiments/stress/)
void add_tune_command(CLI::App& app, int& exit_code);      // tune (experiments/tune/)
void add_glint_test_command(CLI::App& app, int& exit_code);  // glint-test (experiments/glint_test/)
void add_taa_test_command(CLI::App& app, int& exit_code);    // taa-test (experiments/taa_test/)

// Every command above, in the order `glintlab --help` lists them (the options fuzzer).
void add_all_commands(CLI::App& app, int& exit_code);

// What main adds: where the first argument names a command, that command alone (a process builds the
// options of the one command it runs, not of all nine: a fifth of `compare`'s start-up on a small image
// pair), else every command (`--help`, `--version`, a misspelt name: all answer as before).
void add_commands_for(CLI::App& app, int& exit_code, int argc, const char* const* argv);

}  // namespace glintlab

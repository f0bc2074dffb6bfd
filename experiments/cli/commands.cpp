#include "experiments/cli/commands.h"

namespace glintlab {

void add_all_commands(CLI::App& app, int& exit_code) {
  add_run_commands(app, exit_code);
  add_compare_command(app, exit_code);
  add_measure_command(app, exit_code);
  add_list_command(app, exit_code);
  add_check_command(app, exit_code);
  add_report_command(app, exit_code);
  add_stress_command(app, exit_code);
  add_tune_command(app, exit_code);
  add_glint_test_command(app, exit_code);
}

}  // namespace glintlab

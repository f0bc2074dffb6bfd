#include "experiments/cli/commands.h"

#include <cstring>

namespace glintlab {

namespace {

// Every command, in the order `glintlab --help` lists them, with the names each adds.
struct CommandGroup {
  const char* names[3];
  void (*add)(CLI::App&, int&);
};
constexpr CommandGroup kCommands[] = {
    {{"render", "run", "merge"}, &add_run_commands}, {{"compare"}, &add_compare_command},
    {{"measure"}, &add_measure_command},              {{"list"}, &add_list_command},
    {{"check"}, &add_check_command},                  {{"report"}, &add_report_command},
    {{"stress"}, &add_stress_command},                {{"tune"}, &add_tune_command},
    {{"glint-test"}, &add_glint_test_command},        {{"taa-test"}, &add_taa_test_command},
};

}  // namespace

void add_all_commands(CLI::App& app, int& exit_code) {
  for (const CommandGroup& g : kCommands) g.add(app, exit_code);
}

void add_commands_for(CLI::App& app, int& exit_code, int argc, const char* const* argv) {
  if (argc >= 2)
    for (const CommandGroup& g : kCommands)
      for (const char* name : g.names)
        if (name && std::strcmp(name, argv[1]) == 0) return g.add(app, exit_code);
  add_all_commands(app, exit_code);
}

}  // namespace glintlab

// glintlab command line. Each command lives in its own module
// (experiments/cli/commands.h); main only wires them up.
#include "core/util/allocator.h"
#include "core/util/data_dir.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/version.h"

#include <iostream>

int main(int argc, char** argv) {
  glintlab::tune_allocator_for_rendering();
  CLI::App app{"glintlab: temporal anti-aliasing and glint stability experiments (headless Vulkan)"};
  // "glintlab 0.1.0 (commit 2f79422)", then the data folder the program reads and why that one.
  app.set_version_flag("--version", [] {
    const glintlab::DataLocations& d = glintlab::data_locations();
    const std::string problem = glintlab::data_dir_problem(d);
    return std::string("glintlab ") + glintlab::version() + " (commit " + glintlab::commit() + ")\ndata: " + d.data +
           " (" + d.why + ")" + (problem.empty() ? "" : "\nerror: " + problem);
  }, "print the version, the commit and the data folder, and exit");
  app.require_subcommand(1);
  int exit_code = glintlab::kExitOk;
  glintlab::add_commands_for(app, exit_code, argc, argv);
  if (argc < 2) {  // no command: what the commands are, not only that one is required
    std::cout << app.help();
    return glintlab::kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);  // prints help / the parse error
    return code == 0 ? glintlab::kExitOk : glintlab::kExitBadInput;
  }
  return exit_code;
}

// glintlab command line. Each command lives in its own module
// (experiments/cli/commands.h); main only wires them up.
#include "core/util/allocator.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/version.h"

int main(int argc, char** argv) {
  glintlab::tune_allocator_for_rendering();
  CLI::App app{"glintlab: temporal anti-aliasing and glint stability experiments (headless Vulkan)"};
  app.set_version_flag("--version", std::string(glintlab::version()));
  app.require_subcommand(1);
  int exit_code = glintlab::kExitOk;
  glintlab::add_all_commands(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);  // prints help / the parse error
    return code == 0 ? glintlab::kExitOk : glintlab::kExitBadInput;
  }
  return exit_code;
}

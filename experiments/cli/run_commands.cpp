// `glintlab render` and `glintlab run`: the experiment runner from the command line.
#include "core/vk/vk_context.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/runner.h"

#include <iostream>
#include <memory>

namespace glintlab {

void add_run_commands(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<RunOptions>();
  opt->validation = core::VkContext::validation_requested_by_env();
  auto add_options = [opt](CLI::App* c) {
    c->add_option("experiment", opt->experiment, "experiment file, or the name of a built-in one (see `list`)")
        ->required();
    c->add_option("--out", opt->out_dir, "output folder (created if missing)")->required();
    c->add_option("--device", opt->device, "Vulkan device: index or part of its name (default: lavapipe)");
    c->add_option("--ocio-config", opt->ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
    c->add_option("--cache", opt->cache_dir, "reference cache folder (default: results/cache/reference)");
    c->add_option("--frames", opt->max_frames, "render only the first N frames")->check(CLI::PositiveNumber);
    c->add_flag("--validation", opt->validation, "enable Vulkan validation layers (also GLINTLAB_VALIDATION=1)");
  };
  CLI::App* render = app.add_subcommand("render", "render every variant's frames (EXR + PNG), no metrics");
  add_options(render);
  render->callback([opt, &exit_code] {
    opt->measure = false;
    exit_code = run_guarded([&] { return run_experiment(*opt, std::cerr); }, std::cerr);
  });
  CLI::App* run = app.add_subcommand("run", "render variants and the reference; write frames.csv and summary.json");
  add_options(run);
  run->callback([opt, &exit_code] {
    opt->measure = true;
    exit_code = run_guarded([&] { return run_experiment(*opt, std::cerr); }, std::cerr);
  });
}

}  // namespace glintlab

// glintlab command line: render / run experiments, compare images, list what
// is built in. CLI11 parses; each command is a function of its own module.
#include "core/scene/camera_path.h"
#include "core/util/json_check.h"
#include "core/material/sand_material.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/compare.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/runner/runner.h"
#include "experiments/runner/version.h"
#include "metrics/metric_registry.h"

#include <CLI/CLI.hpp>

#include <iostream>

using namespace glintlab;

int main(int argc, char** argv) {
  CLI::App app{"glintlab: temporal anti-aliasing and glint stability experiments (headless Vulkan)"};
  app.set_version_flag("--version", std::string(version()));
  app.require_subcommand(1);

  RunOptions run_opt;
  run_opt.validation = core::VkContext::validation_requested_by_env();
  auto add_run_options = [&](CLI::App* c) {
    c->add_option("experiment", run_opt.experiment, "experiment file, or the name of a built-in one (see `list`)")
        ->required();
    c->add_option("--out", run_opt.out_dir, "output folder (created if missing)")->required();
    c->add_option("--device", run_opt.device, "Vulkan device: index or part of its name (default: lavapipe)");
    c->add_option("--ocio-config", run_opt.ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
    c->add_option("--cache", run_opt.cache_dir, "reference cache folder (default: results/cache/reference)");
    c->add_option("--frames", run_opt.max_frames, "render only the first N frames")->check(CLI::PositiveNumber);
    c->add_flag("--validation", run_opt.validation, "enable Vulkan validation layers (also GLINTLAB_VALIDATION=1)");
  };
  CLI::App* render = app.add_subcommand("render", "render every variant's frames (EXR + PNG), no metrics");
  add_run_options(render);
  CLI::App* run = app.add_subcommand("run", "render variants and the reference; write frames.csv and summary.json");
  add_run_options(run);

  CompareOptions cmp;
  CLI::App* compare = app.add_subcommand("compare", "compare a test image with a reference image");
  compare->add_option("test", cmp.test, "test image (any format OpenImageIO reads)")->required();
  compare->add_option("ref", cmp.ref, "reference image")->required();
  compare->add_option("--space", cmp.space, "OCIO colour space of both inputs (default: file tag, else scene_linear)");
  compare->add_option("--metric", cmp.metrics, "metric(s) to report (default: all)");
  compare->add_option("--map", cmp.map_path, "write the first metric's per-pixel map as a 1-channel EXR");
  compare->add_flag("--json", cmp.json, "print {\"metrics\": {name: {\"mean\", \"max\"}}}");
  compare->add_option("--ocio-config", cmp.ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
  compare->add_option("--itp-nits", cmp.itp_nits, "cd/m^2 of Y = 1 for deltaEITP (default 100)");
  compare->add_option("--view", cmp.display_view,
                      "measure display-referred, as this OCIO DISPLAY/VIEW shows the images (e.g. sRGB/Standard)");
  compare->add_flag("--flip-ldr", cmp.flip_ldr, "LDR-FLIP instead of HDR-FLIP");

  CLI::App* list = app.add_subcommand("list", "list built-in experiments, camera paths, presets, metrics, devices");

  CLI11_PARSE(app, argc, argv);

  try {
    if (*render || *run) {
      run_opt.measure = bool(*run);
      return run_experiment(run_opt, std::cerr);
    }
    if (*compare) return run_compare(cmp, std::cout, std::cerr);
    if (*list) {
      auto print = [](const char* title, const std::vector<std::string>& xs) {
        std::cout << title << ":\n";
        for (const auto& x : xs) std::cout << "  " << x << "\n";
      };
      print("experiments", builtin_experiment_names());
      print("camera paths", core::CameraPath::builtin_names());
      print("scenes (mesh types)", {"plane", "wavy", "sphere", "dunes"});
      print("material presets", core::SandParams::preset_names());
      print("debug outputs", core::SandParams::debug_output_names());
      print("metrics", metrics::metric_names());
      std::cout << "devices:\n";
      for (const auto& d : core::VkContext::list_devices())
        std::cout << "  " << d.index << ": " << d.name << " (" << d.type << ", Vulkan " << d.api_version << ")\n";
      return 0;
    }
  } catch (const ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

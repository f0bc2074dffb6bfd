// `glintlab render`, `glintlab run` and `glintlab merge`: the experiment runner
// from the command line.
#include "core/util/data_dir.h"
#include "core/util/json_check.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/runner.h"
#include "experiments/spec/experiment_spec.h"

#include <iostream>
#include <memory>
#include <regex>

namespace glintlab {

namespace {

// "k/n" -> (k, n).
bool parse_pair(const std::string& s, const char* sep, int& a, int& b) {
  std::smatch m;
  if (!std::regex_match(s, m, std::regex(std::string("([0-9]{1,5})") + sep + "([0-9]{1,5})"))) return false;
  a = std::stoi(m[1]);
  b = std::stoi(m[2]);
  return true;
}

}  // namespace

void add_run_commands(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<RunOptions>();
  auto resolution = std::make_shared<std::string>(), shard = std::make_shared<std::string>();
  auto no_report = std::make_shared<bool>(false);
  opt->validation = core::VkContext::validation_requested_by_env();
  auto add_options = [=](CLI::App* c) {
    c->add_option("experiment", opt->experiment, "experiment file, or the name of a built-in one (see `list`)")
        ->required();
    c->add_option("--out", opt->out_dir, "output folder (default: results/<experiment name>)");
    c->add_option("--variants", opt->variants, "only these variants (comma-separated names), in this order")
        ->delimiter(',');
    c->add_option("--frames", opt->max_frames, "only the first N frames")->check(CLI::PositiveNumber);
    c->add_option("--resolution", *resolution, "override the resolution, WxH (e.g. 320x180)");
    c->add_option("--shard", *shard, "do shard k of n (k/n, 1 <= k <= n): frames [(k-1) F/n, k F/n); join with merge");
    c->add_flag("--resume", opt->resume, "continue the run in --out: do only what its journal lacks");
    c->add_option("--cache", opt->cache_dir, "reference cache folder (default: results/cache/reference)");
    c->add_option("--device", opt->device, "Vulkan device: index or part of its name (default: lavapipe)");
    c->add_option("--ocio-config", opt->ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
    c->add_flag("--no-report", *no_report, "do not write report.html");
    c->add_flag("--validation", opt->validation, "enable Vulkan validation layers (also GLINTLAB_VALIDATION=1)");
  };
  auto body = [=](bool measure) {
    return [=]() {
      opt->measure = measure;
      opt->report = !*no_report;
      if (!resolution->empty()) {
        if (const std::string problem = set_resolution(*resolution, *opt); !problem.empty()) {
          std::cerr << "error: " << problem << "\n";
          return int(kExitBadInput);
        }
      }
      if (!shard->empty()) {
        int k = 0, n = 0;
        if (!parse_pair(*shard, "/", k, n) || n < 1 || k < 1 || k > n) {
          std::cerr << "error: --shard: expected k/n with 1 <= k <= n (e.g. 2/4), got \"" << *shard << "\"\n";
          return int(kExitBadInput);
        }
        opt->shard_index = k - 1;
        opt->shard_count = n;
      }
      if (opt->out_dir.empty()) opt->out_dir = default_run_dir(opt->experiment);
      return run_experiment(*opt, std::cerr);
    };
  };
  CLI::App* render = app.add_subcommand("render", "render every variant's frames (EXR + PNG), no metrics");
  add_options(render);
  render->callback([=, &exit_code] { exit_code = run_guarded(body(false), std::cerr); });
  CLI::App* run = app.add_subcommand(
      "run", "render variants and the reference; write frames.csv, summary.json, images and report.html");
  add_options(run);
  run->callback([=, &exit_code] { exit_code = run_guarded(body(true), std::cerr); });

  auto dirs = std::make_shared<std::vector<std::string>>();
  auto merge_out = std::make_shared<std::string>();
  CLI::App* merge = app.add_subcommand("merge", "join the --shard outputs of one run into one run folder");
  merge->add_option("dirs", *dirs, "the shards' --out folders")->required();
  merge->add_option("--out", *merge_out, "the merged run folder")->required();
  merge->add_flag("--no-report", *no_report, "do not write report.html");
  merge->callback([=, &exit_code] {
    exit_code = run_guarded([=] { return merge_runs(*dirs, *merge_out, !*no_report, std::cerr); }, std::cerr);
  });
}

}  // namespace glintlab

// `glintlab tune`: a multi-objective search over one variant's options (experiments/tune/tune.h).
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/tune/tune.h"

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace glintlab {

void add_tune_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<TuneOptions>();
  CLI::App* c = app.add_subcommand(
      "tune", "multi-objective search over one variant's options on Optuna: trials.csv, pareto.json, tune_report.html");
  c->add_option("experiment", o->experiment, "experiment file, or the name of a built-in one (see `list`)")->required();
  c->add_option("--base", o->base, "the variant whose options are searched")->required();
  c->add_option("--space", o->space,
                "KEY=RANGE (repeatable): KEY a dotted option path (taa.alpha, ssaa_grid, material.glint_sigma), "
                "RANGE lo:hi, lo:hi:log or a,b,... (choices); material.glints.NAME alone: the declared range of a parameter of "
                "the base variant's glint model")
      ->required();
  // Split here, not by CLI11 (which drops empty items): "deltaE2000,,flip" is refused, not read as two.
  auto objectives = std::make_shared<std::vector<std::string>>();
  c->add_option("--objectives", *objectives,
                "metrics to minimise, comma-separated: a metric of the summary (flicker_ratio and glint_density_ratio "
                "as |ln ratio|) or gpu_ms (default: temporal_score,deltaE2000,gpu_ms)");
  c->add_option("--trials", o->trials, "the study's total of finished trials (every worker stops there)")
      ->required()
      ->check(CLI::Range(1, 100000));
  c->add_option("--study", o->study_dir, "study folder (default: results/tune/<experiment>-<base>)");
  c->add_option("--workers", o->workers, "worker processes on this machine (default 1)")->check(CLI::Range(1, 64));
  c->add_flag("--resume", o->resume, "continue the study in --study (also with a new --trials budget)");
  c->add_option("--seed", o->seed, "the sampler's seed (default 1)");
  c->add_option("--sampler", o->sampler, "tpe (multi-objective TPE, default) or nsga2")
      ->check(CLI::IsMember({"tpe", "nsga2"}));
  c->add_option("--storage", o->storage, "sqlite (one machine, default) or journal (a shared file system)")
      ->check(CLI::IsMember({"sqlite", "journal"}));
  c->add_option("--cache", o->cache_dir, "reference cache folder (default: results/cache/reference)");
  c->add_option("--device", o->device, "Vulkan device: index or part of its name (default: lavapipe)");
  c->callback([o, objectives, &exit_code] {
    o->objectives.clear();
    if (objectives->empty()) *objectives = {"temporal_score,deltaE2000,gpu_ms"};
    for (const std::string& list : *objectives)
      for (size_t at = 0;;) {
        const size_t comma = list.find(',', at);
        o->objectives.push_back(list.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        if (comma == std::string::npos) break;
        at = comma + 1;
      }
    exit_code = run_guarded([&] { return tune(*o, std::cerr); }, std::cerr);
  });
}

}  // namespace glintlab

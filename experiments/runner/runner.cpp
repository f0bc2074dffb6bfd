#include "experiments/runner/runner.h"

#include "core/render/scene_gpu.h"
#include "core/util/json_check.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/frame_loop.h"
#include "experiments/runner/output_writers.h"
#include "experiments/runner/plan.h"
#include "experiments/runner/reference_cache.h"
#include "experiments/runner/schema.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"

#include <filesystem>
#include <iomanip>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

// The table printed at the end of a run: per variant GPU time and the headline metrics.
void print_table(std::ostream& log, const nlohmann::json& summary) {
  auto mean = [](const nlohmann::json& stats) -> std::string {
    if (!stats.is_object() || !stats.contains("mean") || stats["mean"].is_null()) return "-";
    std::ostringstream o;
    o << std::fixed << std::setprecision(stats["mean"].get<double>() < 10 ? 3 : 1) << stats["mean"].get<double>();
    return o.str();
  };
  log << "  " << std::left << std::setw(20) << "variant" << std::right << std::setw(12) << "gpu ms/frame"
      << std::setw(12) << "deltaE2000" << std::setw(15) << "flicker_ratio" << std::setw(16) << "temporal_error"
      << "\n";
  for (const auto& v : summary["variants"]) {
    const auto& m = v["metrics"];
    auto metric = [&](const char* n) { return m.contains(n) ? mean(m[n]) : std::string("-"); };
    log << "  " << std::left << std::setw(20) << v["name"].get<std::string>() << std::right << std::setw(12)
        << mean(v["gpu_ms"]) << std::setw(12) << metric("deltaE2000") << std::setw(15) << metric("flicker_ratio")
        << std::setw(16) << metric("temporal_error") << "\n";
  }
  for (const auto& r : summary["references"])
    log << "  " << r["name"].get<std::string>() << ": " << r["frames_rendered"] << " rendered (" << mean(r["gpu_ms"])
        << " ms/frame GPU at " << r["spp"] << " spp), " << r["frames_cached"] << " cached\n";
}

}  // namespace

int run_experiment(const RunOptions& opt, std::ostream& log) {
  ExperimentSpec spec;
  try {
    spec = ExperimentSpec::load(resolve_experiment_path(opt.experiment));
  } catch (const ConfigError& e) {
    log << "error: " << e.what() << "\n";
    return kExitBadInput;
  }
  const int frames = opt.max_frames > 0 ? std::min(opt.max_frames, spec.frames) : spec.frames;
  const bool measure = opt.measure && spec.reference.enabled;
  if (opt.measure && !spec.reference.enabled)
    log << "note: " << spec.file << ": reference.enabled is false; metrics are skipped\n";

  metrics::ColorManager cm(opt.ocio_config.empty() ? metrics::ColorManager::default_config_path() : opt.ocio_config);
  const fs::path out_dir(opt.out_dir);
  fs::create_directories(out_dir);

  // ---- the scene, built once; the plan; the renderer
  SceneData data = build_scene(spec, cm);
  core::VkContext ctx(core::ContextOptions{opt.device, opt.validation});
  log << "device: " << ctx.info().name << " (" << ctx.info().type << ", Vulkan " << ctx.info().api_version << ")\n";
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  const RunPlan plan = make_plan(spec, frames, measure, cm, data, ctx.info().name);
  ReferenceCache cache(opt.cache_dir.empty() ? std::string(GLINTLAB_RESULTS_DIR "/cache/reference") : opt.cache_dir);
  FrameLoop loop(ctx, scene, plan, data, cm, cache, log);

  // ---- the consumers of its records
  const FrameSchema schema(loop.metric_names(), loop.pass_names());
  CsvWriter csv(out_dir / "frames.csv", schema);
  SummaryWriter summary(out_dir / "summary.json", plan, schema, RunInfo{ctx.info().name, cm.config_path(), 1});
  ImageWriter images(out_dir, plan, cm);
  const std::vector<RecordSink*> sinks = {&csv, &summary, &images};

  loop.run(sinks);
  for (RecordSink* s : sinks) s->finish();

  log << "wrote " << (out_dir / "frames.csv").string() << ", " << (out_dir / "summary.json").string()
      << (spec.output.contact_sheet ? " and " + (out_dir / "contact_sheet.png").string() : std::string()) << "\n";
  print_table(log, summary.summary());
  int status = kExitOk;
  if (loop.defects()) {
    log << "error: some frames had NaN, Inf or negative pixels (see frames.csv)\n";
    status = kExitDefect;
  }
  if (ctx.validation_enabled() && ctx.validation_message_count() > 0) {
    log << "error: the Vulkan validation layer reported " << ctx.validation_message_count() << " message(s)\n";
    status = kExitDefect;
  }
  return status;
}

}  // namespace glintlab

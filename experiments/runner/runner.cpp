#include "experiments/runner/runner.h"

#include "core/material/glint_table.h"

#include "core/render/scene_gpu.h"
#include "core/util/content_hash.h"
#include "core/util/data_dir.h"
#include "core/util/json_check.h"
#include "core/render/taa_pass.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/density_sweep.h"
#include "experiments/runner/measure.h"
#include "experiments/report/report.h"
#include "experiments/runner/frame_loop.h"
#include "experiments/runner/journal.h"
#include "experiments/runner/output_writers.h"
#include "experiments/runner/plan.h"
#include "experiments/sources/reference_cache.h"
#include "experiments/runner/schema.h"
#include "experiments/runner/version.h"
#include "experiments/runner/work_schedule.h"
#include "experiments/sources/file_sources.h"
#include "experiments/sources/rendered_sources.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"
#include "metrics/metric_registry.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <regex>
#include <set>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

// The table printed at the end of a run: per variant GPU time and the headline metrics.
void print_table(std::ostream& log, const nlohmann::json& summary) {
  auto mean = [](const nlohmann::json& stats) -> std::string {
    if (!stats.is_object() || !stats.contains("mean") || stats["mean"].is_null()) return "-";
    std::ostringstream o;
    const double x = stats["mean"].get<double>();
    if (std::abs(x) < 0.1 && x != 0.0)
      o << std::setprecision(3) << x;  // three significant digits of small values (0.00868)
    else
      o << std::fixed << std::setprecision(x < 10 ? 3 : 1) << x;
    return o.str();
  };
  log << "  " << std::left << std::setw(20) << "variant" << std::right << std::setw(12) << "gpu ms/frame"
      << std::setw(12) << "deltaE2000" << std::setw(15) << "flicker_ratio" << std::setw(16) << "temporal_score"
      << std::setw(16) << "flicker_excess" << std::setw(14) << "temporal_lag" << "\n";
  for (const auto& v : summary["variants"]) {
    const auto& m = v["metrics"];
    auto metric = [&](const char* n) { return m.contains(n) ? mean(m[n]) : std::string("-"); };
    log << "  " << std::left << std::setw(20) << v["name"].get<std::string>() << std::right << std::setw(12)
        << mean(v["gpu_ms"]) << std::setw(12) << metric("deltaE2000") << std::setw(15) << metric("flicker_ratio")
        << std::setw(16) << metric("temporal_score") << std::setw(16) << metric("flicker_excess") << std::setw(14)
        << metric("temporal_lag") << "\n";
  }
  for (const auto& r : summary["references"]) {
    if (r.contains("frames") && r["frames"].is_string()) {  // a truth read from files renders nothing
      log << "  " << r["name"].get<std::string>() << ": read from " << r["frames"].get<std::string>() << "\n";
      continue;
    }
    log << "  " << r["name"].get<std::string>() << ": " << r["frames_rendered"] << " rendered (" << mean(r["gpu_ms"])
        << " ms/frame GPU at " << r["spp"] << " spp), " << r["frames_cached"] << " cached\n";
  }
}

// The content of every file the run reads besides the experiment file (whose JSON is in the header):
// the camera-path file, the HDRI, the OCIO config, the glint model and TAA resolve files, the frames of frame sources. A resume or a merge
// with any of them changed is refused, naming it.
nlohmann::json run_input_hashes(const ExperimentSpec& spec, const metrics::ColorManager& cm) {
  nlohmann::json out = nlohmann::json::object();
  if (!spec.path_file.empty()) out["camera_path " + spec.path_file] = file_content_hash(spec.path_file);
  if (!spec.sky.hdri.empty() && fs::is_regular_file(spec.sky.hdri))
    out["hdri " + spec.sky.hdri] = file_content_hash(spec.sky.hdri);
  out["ocio_config"] = file_content_hash(cm.config_path());
  for (const auto& v : spec.variants)
    for (const core::SandParams* m : {&v.material, v.truth_material ? &*v.truth_material : nullptr})
      if (m && m->glint_file && !m->glint_file->builtin)  // the file (its declarations) and what it includes
        out["glint_model " + m->glint_file->file] =
            file_content_hash(m->glint_file->file) + " " +
            core::default_shader_compiler().source_hash(m->glint_file->file, core::ShaderStage::Compute);
  for (const auto& v : spec.variants)  // a user's TAA resolve file and what it includes
    if (v.aa == AaMethod::Taa && !v.taa.resolve->builtin)
      out["taa_resolve " + v.taa.resolve->file] =
          file_content_hash(v.taa.resolve->file) + " " +
          core::default_shader_compiler().source_hash(v.taa.resolve->file, core::ShaderStage::Fragment, v.taa.defines());
  auto add = [&](const std::string& seq, const std::string& what) {
    if (seq.empty()) return;
    const std::vector<int> numbers = first_frame_numbers(seq, spec.frames, what);
    for (const auto& f : list_frames(parse_sequence(seq, what), what))
      if (std::find(numbers.begin(), numbers.end(), f.number) != numbers.end()) out[f.path] = file_content_hash(f.path);
  };
  for (const auto& v : spec.variants) add(v.frames, spec.file + ": variant " + v.name + ": frames");
  add(spec.reference.frames, spec.file + ": reference: frames");
  return out;
}

// The spec as this run uses it: the file, then the command line's overrides.
ExperimentSpec effective_spec(const nlohmann::json& source, const std::string& file, const nlohmann::json& overrides) {
  ExperimentSpec spec = ExperimentSpec::from_json(source, file);
  if (overrides.contains("resolution")) {
    spec.width = overrides["resolution"][0].get<int>();
    spec.height = overrides["resolution"][1].get<int>();
  }
  if (overrides.contains("frames")) spec.frames = std::min(spec.frames, overrides["frames"].get<int>());
  if (overrides.contains("reference_grid")) spec.reference.grid = overrides["reference_grid"].get<int>();
  if (overrides.contains("variants")) {
    std::vector<VariantSpec> chosen;
    std::set<std::string> seen;
    for (const auto& name : overrides["variants"]) {
      const std::string n = name.get<std::string>();
      if (const std::string why = variant_name_problem(n); !why.empty()) throw ConfigError(file + ": --variants: " + why);
      if (!seen.insert(n).second)
        throw ConfigError(file + ": --variants: \"" + n + "\" is given twice (each variant runs once)");
      auto it = std::find_if(spec.variants.begin(), spec.variants.end(),
                             [&](const VariantSpec& v) { return v.name == name.get<std::string>(); });
      if (it == spec.variants.end()) {
        std::string all;
        for (const auto& v : spec.variants) all += (all.empty() ? "" : ", ") + v.name;
        throw ConfigError(file + ": --variants: no variant named \"" + n + "\"; the experiment has " + all);
      }
      chosen.push_back(*it);
    }
    spec.variants = std::move(chosen);
  }
  return spec;
}


// The truth sized by its noise floor ("reference": {"floor": {METRIC: FRACTION}}): runs the experiment
// (no images, no report) in DIR/sizing/grid-G from the experiment's grid on; where a metric's floor is
// above FRACTION of the smallest value of it among the variants measured against that truth, the grid
// grows by the ratio (the floor of a mean of differences falls as 1 / sqrt(samples), so as 1 / grid;
// at least by one, at most to max_grid) and the experiment runs again. Sets *grid to the first grid that
// meets every target (or max_grid) and *sizing to the account summary.json keeps as
// "reference_sizing". Returns an exit code (0, or the sizing run's 2, 3, 4 or 5).
int size_reference(const RunOptions& opt, const ExperimentSpec& spec, std::ostream& log, int* grid,
                   nlohmann::json* sizing) {
  const ReferenceSpec& ref = spec.reference;
  nlohmann::json steps = nlohmann::json::array();
  bool met = false;
  int g = ref.grid;
  for (;;) {
    RunOptions o = opt;
    o.out_dir = (fs::path(opt.out_dir) / "sizing" / ("grid-" + std::to_string(g))).string();
    o.report = false;
    o.images = false;
    o.density_sweep = false;
    o.reference_grid = g;
    o.resume = opt.resume && fs::exists(fs::path(o.out_dir) / "records.jsonl");
    log << "reference sizing: " << g << "x" << g << " samples per pixel, in " << o.out_dir << "\n";
    const int status = run_experiment(o, log);
    if (status != kExitOk && status != kExitDefect) return status;  // bad input, the device, I/O
    const nlohmann::json summary = read_json_file((fs::path(o.out_dir) / "summary.json").string());
    double worst = 0;  // the largest floor / (fraction x smallest value) over metrics and truths
    nlohmann::json step = {{"grid", g}, {"spp", g * g}, {"floor", nlohmann::json::object()},
                           {"smallest", nlohmann::json::object()}};
    for (const auto& [metric, fraction] : ref.floor_target)
      for (const auto& r : summary.at("references")) {
        const nlohmann::json floor = r.contains("floor") ? r["floor"].value(metric, nlohmann::json()) : nlohmann::json();
        double smallest = std::numeric_limits<double>::infinity();
        for (const auto& v : summary.at("variants"))
          if (v.value("reference", "") == r.at("name").get<std::string>() && v["metrics"].contains(metric) &&
              v["metrics"][metric]["mean"].is_number())
            smallest = std::min(smallest, v["metrics"][metric]["mean"].get<double>());
        if (!floor.is_number()) {  // growing the truth cannot give a floor the run does not measure
          log << "error: " << spec.file << ": reference.floor." << metric << ": the run at " << g << "x" << g
              << " measured no floor of " << metric << " for " << r.at("name").get<std::string>()
              << " (every frame's is undefined); the truth cannot be sized by it\n";
          return kExitBadInput;
        }
        const double f = floor.get<double>();
        step["floor"][metric] = floor;
        step["smallest"][metric] = std::isfinite(smallest) ? nlohmann::json(smallest) : nlohmann::json(nullptr);
        const double ratio = smallest > 0 && std::isfinite(smallest) ? f / (fraction * smallest)
                                                                     : std::numeric_limits<double>::infinity();
        worst = std::max(worst, ratio);
        log << "reference sizing: " << r.at("name").get<std::string>() << " at " << g << "x" << g << ": " << metric
            << " floor " << f << ", smallest variant " << smallest << ", target " << fraction << " of it: "
            << (ratio <= 1 ? "met" : "not met") << "\n";
      }
    step["met"] = worst <= 1;
    steps.push_back(step);
    if (worst <= 1) {
      met = true;
      break;
    }
    if (g >= ref.max_grid) {
      log << "warning: reference sizing: the floor target is not met at max_grid " << ref.max_grid
          << "; the run uses that grid (its floors are in summary.json)\n";
      break;
    }
    const double next = std::isfinite(worst) ? std::ceil(g * worst) : double(ref.max_grid);
    g = int(std::clamp(next, double(g + 1), double(ref.max_grid)));
  }
  *grid = g;
  nlohmann::json target = nlohmann::json::object();
  for (const auto& [metric, fraction] : ref.floor_target) target[metric] = fraction;
  *sizing = {{"target", target}, {"max_grid", ref.max_grid}, {"grid", g}, {"met", met}, {"steps", steps}};
  return kExitOk;
}

}  // namespace

// An experiment whose every source is files: the measurement `glintlab measure` makes of its options.
static int run_frames_only(const RunOptions& opt, const ExperimentSpec& spec, const std::string& file,
                           std::ostream& log) {
  MeasureOptions m;
  m.file = file;
  m.name = spec.name;
  m.reference = spec.reference.frames;
  m.reference_space = spec.reference.frames_space;
  m.reference_b = spec.reference.frames_b;
  for (const auto& v : spec.variants) m.tests.push_back({v.name, v.frames, v.frames_space});
  m.out_dir = opt.out_dir;
  m.motion = spec.frames_only.motion;
  m.motion_from = spec.frames_only.motion_from;
  m.motion_convention = spec.frames_only.motion_convention;
  m.depth = spec.frames_only.depth;
  m.metrics = spec.metrics;
  m.first = spec.frames_only.first;
  m.last = spec.frames_only.last;
  if (opt.max_frames > 0) {
    if (m.first == INT_MIN) {
      log << "error: --frames N: a frames-only experiment takes its frames by number; set \"frame_range\" in "
          << file << "\n";
      return kExitBadInput;
    }
    m.last = std::min(m.last, m.first + opt.max_frames - 1);
  }
  m.fps = spec.frames_only.fps;
  m.ocio_config = opt.ocio_config;
  m.resume = opt.resume;
  m.report = opt.report;
  m.display = spec.output.display;
  m.view = spec.output.view;
  m.exposure = spec.output.exposure;
  if (!opt.measure) {
    log << "error: " << file << ": an experiment without \"scene\" has nothing to render; use `run`\n";
    return kExitBadInput;
  }
  if (opt.shard_count > 1 || opt.width > 0) {
    log << "error: " << file << ": --shard and --resolution do not apply to frames read from files\n";
    return kExitBadInput;
  }
  return measure_sequences(m, log);
}

// The sources of a rendered run: each variant's frame graph (or its files), each truth (rendered or
// cached, or read), the motion pass where the run measures or writes motion.
static LoopSources rendered_sources(const core::VkContext& ctx, const SceneGpus& scenes, const RunPlan& plan,
                             const metrics::ColorManager& cm, const ReferenceCache& cache, RenderedFrames& frames,
                             const metrics::FrameMetrics* frame_metrics, std::ostream& log) {
  const ExperimentSpec& spec = *plan.spec;
  LoopSources s;
  for (const auto& v : plan.variants)
    s.variants.push_back(v.files ? file_sequence(*v.files, cm, spec.working_space)
                                 : rendered_variant(ctx, scenes.of(*v.spec), *v.spec, v.program, frames));
  const core::SceneGpu& scene = scenes.display();  // the truth's and the motion's
  if (plan.measure || spec.output.motion) s.motion = rendered_motion(ctx, scene, frames);
  for (size_t r = 0; plan.measure && r < plan.references.size(); ++r) {
    const RunPlan::Reference& ref = plan.references[r];
    s.references.push_back(ref.files ? file_reference(*ref.files, std::nullopt, cm, spec.working_space,
                                                      frame_metrics, ref.variants.size() > 1)
                                     : rendered_reference(
                                           ctx, scene, ref.program,
                                           [&plan, r](const core::FrameUniforms& u) { return plan.reference_key(int(r), u); },
                                           cache, frames, log));
  }
  s.clock = [&spec](int k) {
    const core::FrameCamera cam = spec.path.frame(k, spec.width, spec.height);
    return FrameClock{cam.time, cam.cut, k};
  };
  return s;
}

// run_experiment, with further summary.json keys (the reference sizing's account).
static int run_with(const RunOptions& opt, std::ostream& log, const nlohmann::json& extra) {
  // ---- the experiment and this invocation's share of it
  nlohmann::json source, overrides = nlohmann::json::object();
  std::string file;
  ExperimentSpec spec;
  file = resolve_experiment_path(opt.experiment);
  source = opt.source.is_null() ? read_json_file(file) : opt.source;
  if (opt.width > 0 || opt.height > 0) {
    if (opt.width < 1 || opt.height < 1 || opt.width > 16384 || opt.height > 16384)
      throw ConfigError("--resolution: " + std::to_string(opt.width) + "x" + std::to_string(opt.height) +
                        " is outside 1x1 ... 16384x16384");
    overrides["resolution"] = {opt.width, opt.height};
  }
  if (opt.max_frames > 0) overrides["frames"] = opt.max_frames;
  if (!opt.variants.empty()) overrides["variants"] = opt.variants;
  if (opt.reference_grid > 0) overrides["reference_grid"] = opt.reference_grid;
  if (opt.shard_count < 1 || opt.shard_index < 0 || opt.shard_index >= opt.shard_count)
    throw ConfigError("--shard: expected k/n with 1 <= k <= n");
  spec = effective_spec(source, file, overrides);
  if (spec.frames_only.enabled) return run_frames_only(opt, spec, file, log);  // every source is files
  const bool measured = opt.measure && spec.reference.enabled;
  if (opt.measure && !spec.reference.enabled)
    log << "note: " << spec.file << ": reference.enabled is false; metrics are skipped\n";
  nlohmann::json summary_extra = extra;
  if (measured && !spec.reference.floor_target.empty() && opt.reference_grid == 0) {
    for (const auto& [metric, fraction] : spec.reference.floor_target) {
      const metrics::MetricInfo* info = metrics::metric_info(metric);
      if (spec.frames < 2 && info && std::string(info->group) == "flicker")
        throw ConfigError(file + ": reference.floor." + metric + ": " + metric + " compares consecutive frames and this "
                          "run has 1 frame: it has no floor to size the truth by (run 2 frames or more, or name a "
                          "per-frame metric)");
    }
    if (opt.shard_count > 1) {
      log << "error: " << file << ": reference.floor sizes the truth by whole runs; run it unsharded once, then "
          << "shard with the \"grid\" it chose (summary.json reference_sizing.grid)\n";
      return kExitBadInput;
    }
    int grid = 0;
    nlohmann::json sizing;
    if (const int status = size_reference(opt, spec, log, &grid, &sizing); status != kExitOk) return status;
    RunOptions sized = opt;
    sized.reference_grid = grid;
    summary_extra["reference_sizing"] = sizing;
    log << "reference sizing: the run uses " << grid << "x" << grid << " samples per pixel\n";
    return run_with(sized, log, summary_extra);
  }

  if (measured && opt.density_sweep && spec.density_sweep.enabled()) {
    if (opt.shard_count > 1) {
      log << "error: " << file << ": a density sweep chooses its matched parameters from whole runs; run it "
          << "unsharded\n";
      return kExitBadInput;
    }
    if (const int status = run_density_sweep(opt, source, spec, log, &summary_extra); status != kExitOk) return status;
  }

  const metrics::ColorManager cm = load_color_manager(opt.ocio_config);
  check_color_names(spec, cm);  // before anything is written or rendered
  // A user's resolve file compiles before anything is written (ShaderCompileError naming its line: exit 3).
  for (const auto& v : spec.variants)
    if (v.aa == AaMethod::Taa && !v.taa.resolve->builtin) core::TaaPass::compile(v.taa);
  // ---- the device: part of what identifies the run (a resume or merge on another device is refused)
  core::VkContext ctx(core::ContextOptions{opt.device, opt.validation});
  const fs::path out_dir(opt.out_dir);
  fs::create_directories(out_dir);

  // ---- the journal: what this folder already holds, and what it is a run of
  nlohmann::json header = {{"type", "run"},
                                 {"glintlab_version", version()},
                                 {"command", measured ? "run" : "render"},
                                 {"file", file},
                                 {"source", source},
                                 {"content_hash", core::hash_hex(dump_json(source))},
                                 {"overrides", overrides},
                                 {"shard", {opt.shard_index, opt.shard_count}}};
  header["inputs"] = run_input_hashes(spec, cm);
  header["device"] = ctx.info().name;
  auto journal = std::make_unique<Journal>(out_dir, header, opt.resume);
  if (journal->dropped_lines() > 0)
    log << "note: dropped " << journal->dropped_lines() << " incomplete line(s) of the journal (a killed run)\n";

  // ---- the scene, built once; the plan; the work; the renderer
  SceneData data = build_scene(spec, cm);
  log << "device: " << ctx.info().name << " (" << ctx.info().type << ", Vulkan " << ctx.info().api_version << ")\n";
  log << "mesh: " << spec.mesh.type << ", " << data.mesh.indices.size() / 3 << " triangles";
  if (spec.mesh.max_edge_px > 0.0f) {
    log << " (grid adapted to the camera path at " << spec.width << "x" << spec.height << ", max_edge_px "
        << spec.mesh.max_edge_px;
    if (spec.mesh.max_error_px > 0.0f) log << ", max_error_px " << spec.mesh.max_error_px;
    log << "; the full grid has " << 2 * size_t(spec.mesh.tessellation) * spec.mesh.tessellation << ")";
  }
  log << "\n";
  for (const auto& [scale, mesh] : data.render_lods)
    log << "mesh at render scale " << scale << ": " << mesh.indices.size() / 3 << " triangles (mesh_lod \"render\")\n";
  if (!opt.images) spec.output.exr = spec.output.png = spec.output.contact_sheet = spec.output.motion = spec.output.halves = false;
  const RunPlan plan = make_plan(spec, spec.frames, measured, cm, data, ctx.info().name, &log);
  const auto [begin, end] = shard_range(spec.frames, opt.shard_index, opt.shard_count);
  journal->check_shape(int(plan.variants.size()), plan.frames, int(plan.references.size()));
  const WorkSchedule work = schedule_work(plan, *journal, begin, end);
  if (opt.shard_count > 1)
    log << "shard " << opt.shard_index + 1 << "/" << opt.shard_count << ": frames " << begin << " to " << end - 1
        << "\n";
  if (opt.resume)
    log << "resume: " << journal->frames().size() << " frame record(s) done, " << work.emitted_frames()
        << " to go\n";

  ImageWriter images(out_dir, plan, cm);
  if (work.last_frame >= 0) {
    const SceneGpus scenes(ctx, data);
    const std::string cache_dir = opt.cache_dir.empty() ? results_path("cache/reference") : opt.cache_dir;
    ReferenceCache cache(cache_dir);
    core::set_glint_table_cache_dir(cache_dir);  // a glint model's data table, beside the truths
    RenderedFrames frames(spec, data);
    std::unique_ptr<metrics::FrameMetrics> frame_metrics;
    if (plan.measure)
      frame_metrics = std::make_unique<metrics::FrameMetrics>(cm, spec.working_space, spec.metrics,
                                                                     spec.measured_metric_options());
    FrameLoop loop(plan, rendered_sources(ctx, scenes, plan, cm, cache, frames, frame_metrics.get(), log),
                   frame_metrics.get(), log);
    loop.run(work, {journal.get(), &images});
  }

  // ---- outputs, from the journal
  int report_status = kExitOk;
  const nlohmann::json summary =
      write_run_outputs(out_dir, plan, {journal.get()}, RunInfo{ctx.info().name, cm.config_path(), 1, summary_extra}, images,
                    opt.report, &report_status, log);
  print_table(log, summary);
  int status = report_status;  // a failed report is a failed run, unless the run's own defects say more
  DefectCount defects;
  journal->replay(defects);
  if (defects.frames > 0) {
    log << "error: " << defects.frames << " frame(s) had NaN, Inf or negative pixels (see frames.csv)\n";
    status = kExitDefect;
  }
  if (defects.reference_frames > 0) {
    log << "error: " << defects.reference_frames << " variant frame(s) were measured against a reference frame with "
        << "NaN, Inf or negative pixels (reference_nonfinite_px, reference_negative_px in frames.csv): their metrics "
           "are NaN\n";
    status = kExitDefect;
  }
  if (ctx.validation_enabled() && ctx.validation_message_count() > 0) {
    log << "error: the Vulkan validation layer reported " << ctx.validation_message_count() << " message(s)\n";
    status = kExitDefect;
  }
  return status;
}

// The exit codes of experiments/cli/exit_codes.h, in one place: what the run throws is mapped there.
int run_experiment(const RunOptions& opt, std::ostream& log) {
  return run_guarded([&] { return run_with(opt, log, nlohmann::json::object()); }, log);
}

// A journal header as `run` writes it, checked before merge reads its fields (a header is input: a
// shard index of 6.7e32 must not be converted to int, a "file" that is a number must not throw).
void check_run_header(const nlohmann::json& h, const std::string& dir) {
  auto bad = [&](const std::string& what) {
    throw ConfigError(dir + ": the journal's header is not one `glintlab run` writes (" + what + ")");
  };
  auto is_int = [](const nlohmann::json& x, long long lo, long long hi) {
    return x.is_number_integer() && x.get<long long>() >= lo && x.get<long long>() <= hi;
  };
  if (!h.contains("shard") || !h["shard"].is_array() || h["shard"].size() != 2 ||
      !is_int(h["shard"][1], 1, 1000000) || !is_int(h["shard"][0], 0, h["shard"][1].get<long long>() - 1))
    bad("\"shard\" must be [k, n] with 0 <= k < n <= 1000000");
  if (!h.contains("file") || !h["file"].is_string()) bad("\"file\" must be a string");
  if (!h.contains("source") || !h["source"].is_object()) bad("\"source\" must be an experiment object");
  if (!h.contains("command") || !h["command"].is_string()) bad("\"command\" must be a string");
  if (h["command"] == "measure") bad("it is a `measure` folder: measure runs are not sharded");
  if (!h.contains("overrides") || !h["overrides"].is_object()) bad("\"overrides\" must be an object");
  const auto& o = h["overrides"];
  if (o.contains("resolution") && !(o["resolution"].is_array() && o["resolution"].size() == 2 &&
                                    is_int(o["resolution"][0], 1, 16384) && is_int(o["resolution"][1], 1, 16384)))
    bad("\"overrides.resolution\" must be [w, h] in 1 ... 16384");
  if (o.contains("frames") && !is_int(o["frames"], 1, 1000000)) bad("\"overrides.frames\" must be a count");
  if (o.contains("reference_grid") && !is_int(o["reference_grid"], 1, 64))
    bad("\"overrides.reference_grid\" must be a grid in 1 ... 64");
  if (o.contains("variants")) {
    if (!o["variants"].is_array()) bad("\"overrides.variants\" must be an array of names");
    for (const auto& v : o["variants"])
      if (!v.is_string()) bad("\"overrides.variants\" must be an array of names");
  }
}

static int merge_with(const std::vector<std::string>& dirs, const std::string& out, bool report, std::ostream& log) {
  if (dirs.empty()) {
    log << "error: merge: name the shard folders to join\n";
    return kExitBadInput;
  }
  // The merged run is written into --out, and each shard's image folders are copied there: --out
  // must be neither a shard folder nor inside one.
  for (const auto& d : dirs) {
    std::error_code ec;
    const fs::path rel = fs::weakly_canonical(out, ec).lexically_relative(fs::weakly_canonical(d, ec));
    if (!ec && !rel.empty() && *rel.begin() != "..") {
      log << "error: merge: --out " << out << " is " << (rel == "." ? "" : "inside ") << "the shard folder " << d
          << ", which merge reads; give another --out (e.g. beside the shards)\n";
      return kExitBadInput;
    }
  }
  std::vector<Journal> journals;
  for (const auto& d : dirs) {
    journals.push_back(Journal::load(d));
    check_run_header(journals.back().header(), d);
  }
  // One run: the same experiment, options and shard count; every shard once.
  nlohmann::json first = journals[0].header();
  const int count = first["shard"][1].get<int>();
  std::set<int> seen;
  for (size_t i = 0; i < journals.size(); ++i) {
    nlohmann::json h = journals[i].header();
    const int k = h["shard"][0].get<int>();
    if (h["shard"][1] != count) {
      log << "error: merge: " << dirs[i] << " is a shard of " << h["shard"][1] << ", " << dirs[0] << " of " << count
          << "\n";
      return kExitBadInput;
    }
    h["shard"] = first["shard"];
    if (h != first) {
      log << "error: merge: " << dirs[i] << " is a run of another experiment, or with other options, inputs or "
          << "device than " << dirs[0] << " (" << Journal::header_difference(first, h) << " differ)\n";
      return kExitBadInput;
    }
    if (!seen.insert(k).second) {
      log << "error: merge: shard " << k + 1 << "/" << count << " is given twice (" << dirs[i] << ")\n";
      return kExitBadInput;
    }
  }
  if (int(seen.size()) != count) {
    std::string missing;
    for (int k = 0; k < count; ++k)
      if (!seen.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k + 1) + "/" + std::to_string(count);
    log << "error: merge: shard(s) " << missing << " missing\n";
    return kExitBadInput;
  }
  const ExperimentSpec spec = effective_spec(first["source"], first["file"].get<std::string>(), first["overrides"]);
  // The shards' own OCIO config (their summaries name it; the journal headers hold its content).
  std::string ocio_path = metrics::ColorManager::default_config_path();
  try {
    std::ifstream in(fs::path(dirs.front()) / "summary.json");
    ocio_path = nlohmann::json::parse(in).value("ocio_config", ocio_path);
  } catch (const std::exception&) {
  }
  const std::string want = first.contains("inputs") ? first["inputs"].value("ocio_config", "") : "";
  if (!want.empty() && (!fs::is_regular_file(ocio_path) || file_content_hash(ocio_path) != want)) {
    log << "error: merge: the shards ran with an OCIO config that is no longer at " << ocio_path
        << " with the same content; merge where it is\n";
    return kExitBadInput;
  }
  metrics::ColorManager cm(ocio_path);
  const SceneData data = build_scene(spec, cm);
  const RunPlan plan = make_plan(spec, spec.frames, first["command"] == "run" && spec.reference.enabled, cm, data, "");
  for (const Journal& j : journals) j.check_shape(int(plan.variants.size()), plan.frames, int(plan.references.size()));
  // Every frame of every variant exactly once.
  for (size_t v = 0; v < plan.variants.size(); ++v)
    for (int k = 0; k < plan.frames; ++k) {
      int n = 0;
      for (const Journal& j : journals) n += j.has_frame(int(v), k);
      if (n != 1) {
        log << "error: merge: " << plan.variants[v].spec->name << " frame " << k << " is recorded " << n
            << " times (an unfinished shard? resume it first)\n";
        return kExitBadInput;
      }
    }
  const fs::path out_dir(out);
  fs::create_directories(out_dir);
  // Images: each shard's folders are copied over (every file once).
  for (const auto& d : dirs)
    for (const auto& e : fs::directory_iterator(d))
      if (e.is_directory())
        fs::copy(e.path(), out_dir / e.path().filename(),
                 fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::vector<const Journal*> js;
  for (const Journal& j : journals) js.push_back(&j);
  ImageWriter images(out_dir, plan, cm);
  const std::string device = first.value("device", "");  // one device: the headers are equal
  int report_status = kExitOk;
  const nlohmann::json summary =
      write_run_outputs(out_dir, plan, js, RunInfo{device, cm.config_path(), 1}, images, report, &report_status, log);
  print_table(log, summary);
  return report_status;
}

int merge_runs(const std::vector<std::string>& dirs, const std::string& out, bool report, std::ostream& log) {
  return run_guarded(
      [&] {
        try {
          return merge_with(dirs, out, report, log);
        } catch (const ConfigError& e) {  // which command the message is from: the shards are its input
          throw ConfigError(std::string("merge: ") + e.what());
        }
      },
      log);
}

std::string default_run_dir(const std::string& experiment) {
  return results_path(ExperimentSpec::load(resolve_experiment_path(experiment)).name);
}

std::string set_resolution(const std::string& text, RunOptions& options) {
  std::smatch m;
  if (std::regex_match(text, m, std::regex("([0-9]{1,5})x([0-9]{1,5})"))) {
    const int w = std::stoi(m[1]), h = std::stoi(m[2]);
    if (w >= 1 && h >= 1 && w <= 16384 && h <= 16384) {
      options.width = w;
      options.height = h;
      return "";
    }
  }
  return "--resolution: expected WxH with each in 1 ... 16384 (e.g. 320x180), got \"" + text + "\"";
}

}  // namespace glintlab

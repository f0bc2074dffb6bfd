#include "experiments/runner/runner.h"

#include "core/util/content_hash.h"
#include "core/util/json_check.h"
#include "core/scene/mesh.h"
#include "core/render/surface_pass.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/vk_context.h"
#include "experiments/runner/contact_sheet.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/runner/reference_cache.h"
#include "experiments/spec/scene_setup.h"
#include "experiments/runner/version.h"
#include "metrics/color/color_manager.h"
#include "metrics/flicker.h"
#include "metrics/glint_stats.h"
#include "metrics/color/image_io.h"
#include "metrics/color/measurement_space.h"
#include "metrics/metric_registry.h"
#include "metrics/pixel_scan.h"
#include "metrics/pooled_error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void write_text_atomic(const fs::path& path, const std::string& text) {
  fs::path tmp = path;
  tmp += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write");
  }
  fs::rename(tmp, path);
}

// A number for summary.json: non-finite values become null (JSON has no inf/NaN).
nlohmann::json num(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

struct Stat {
  std::vector<double> v;
  void add(double x) { v.push_back(x); }
  double mean() const {
    double s = 0;
    size_t n = 0;
    for (double x : v)
      if (std::isfinite(x)) s += x, ++n;
    return n ? s / double(n) : NAN;
  }
  double percentile(double p) const {
    std::vector<double> f;
    for (double x : v)
      if (!std::isnan(x)) f.push_back(x);
    if (f.empty()) return NAN;
    std::sort(f.begin(), f.end());
    size_t i = size_t(std::ceil(p * double(f.size()))) ;
    return f[std::min(f.size() - 1, i == 0 ? 0 : i - 1)];  // nearest-rank
  }
  double max() const {
    double m = -INFINITY;
    for (double x : v)
      if (!std::isnan(x)) m = std::max(m, x);
    return v.empty() ? NAN : m;
  }
  nlohmann::json summary() const {
    return {{"mean", num(mean())}, {"p95", num(percentile(0.95))}, {"max", num(max())}};
  }
};

std::string csv_num(double x) {
  if (std::isnan(x)) return "";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::ostringstream o;
  o << std::setprecision(7) << x;
  return o.str();
}

// One line of progress on stderr: rewritten in place on a terminal, every
// ~10 % otherwise (CI logs).
class Progress {
 public:
  Progress(std::ostream& log, std::string label, int total)
      : log_(log), label_(std::move(label)), total_(total), tty_(isatty(STDERR_FILENO)) {}
  void update(int done, const std::string& detail) {
    if (tty_) {
      log_ << "\r" << label_ << " " << done << "/" << total_ << "  " << detail << "\033[K" << std::flush;
      if (done == total_) log_ << "\n";
    } else if (done == total_ || done == 1 || done * 10 / total_ != (done - 1) * 10 / total_) {
      log_ << label_ << " " << done << "/" << total_ << "  " << detail << "\n" << std::flush;
    }
  }

 private:
  std::ostream& log_;
  std::string label_;
  int total_;
  bool tty_;
};

// Sub-pixel sample patterns are the same in every frame: a reference is then a
// fixed quadrature of the pixel footprint (a static camera gives identical
// frames, so its own estimator noise never shows up as flicker), and SSAA is
// the fixed-pattern supersampling a renderer would ship.
constexpr uint32_t kReferencePatternSeed = 0x5eed0001u;
constexpr uint32_t kSsaaPatternSeed = 17u;

std::vector<core::SamplePush> make_samples(const ExperimentSpec& spec, int frame, int grid, uint32_t seed) {
  std::vector<core::SamplePush> out;
  std::vector<glm::vec2> offsets = grid <= 1 ? std::vector<glm::vec2>{glm::vec2(0.0f)}
                                             : core::stratified_offsets(grid, seed);
  float w = 1.0f / float(offsets.size());
  for (size_t i = 0; i < offsets.size(); ++i) {
    core::FrameCamera cam = spec.path.frame(frame, spec.width, spec.height, offsets[i]);
    out.push_back({cam.view_proj, {offsets[i].x, offsets[i].y, w, float(i)}});
  }
  return out;
}

// The material shader a variant or its reference needs.
struct ShaderConfig {
  core::SurfaceShader shader;
  std::string material_key;  // hash of packed params + defines
};

ShaderConfig make_shader(const core::SandParams& params, const std::string& debug, const core::SandFeatures& range,
                         bool reference) {
  core::SandFeatures needs = range;
  needs.debug_output = debug;
  std::vector<std::string> defines = core::shader_defines(params, needs);
  if (reference) {
    // Ground truth = footprint integral of the *micro* model: no far field,
    // no close-to-far transition (DESIGN.md "Ground truth").
    defines.erase(std::remove_if(defines.begin(), defines.end(),
                                 [](const std::string& d) { return d.rfind("SAND_FAR=", 0) == 0 ||
                                                                   d.rfind("SAND_CLOSE=", 0) == 0; }),
                  defines.end());
    defines.push_back("SAND_FAR=0");
    defines.push_back("SAND_CLOSE=1");
  }
  ShaderConfig c;
  core::SandParamsGPU gpu = params.pack();
  c.shader.fragment = "passes/sand.frag";
  c.shader.defines = defines;
  c.shader.material.resize(sizeof gpu);
  std::memcpy(c.shader.material.data(), &gpu, sizeof gpu);
  core::ContentHash h;
  h.add(c.shader.material.data(), c.shader.material.size());
  for (const auto& d : defines) h.add(std::string_view(d));
  c.material_key = h.hex();
  return c;
}

// Display-encoded preview through the OCIO display/view, opaque (alpha is
// coverage in the render, which a preview should not show as transparency).
Image preview(const Image& scene_linear, const ExperimentSpec& spec, const metrics::ColorManager& cm) {
  Image out = cm.display(scene_linear, spec.working_space, spec.output.display, spec.output.view);
  if (out.channels == 4)
    for (size_t i = 3; i < out.data.size(); i += 4) out.data[i] = 1.0f;
  return out;
}

fs::path frame_path(const fs::path& dir, int frame, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.%s", frame, ext);
  return dir / name;
}

}  // namespace

int run_experiment(const RunOptions& opt, std::ostream& log) {
  ExperimentSpec spec;
  try {
    spec = ExperimentSpec::load(resolve_experiment_path(opt.experiment));
  } catch (const ConfigError& e) {
    log << "error: " << e.what() << "\n";
    return 2;
  }
  const int frames = opt.max_frames > 0 ? std::min(opt.max_frames, spec.frames) : spec.frames;
  const bool measure = opt.measure && spec.reference.enabled;
  if (opt.measure && !spec.reference.enabled)
    log << "note: " << spec.file << ": reference.enabled is false; metrics are skipped\n";

  metrics::ColorManager cm(opt.ocio_config.empty() ? metrics::ColorManager::default_config_path() : opt.ocio_config);
  fs::path out_dir(opt.out_dir);
  fs::create_directories(out_dir);

  // ---- scene, built once
  core::Mesh mesh = core::build_mesh(spec.mesh);
  core::Environment env = prepare_environment(spec, cm);
  core::EnvironmentTexture env_tex = environment_texture(env);
  core::SandFeatures range = distance_range(spec, mesh);

  core::VkContext ctx(core::ContextOptions{opt.device, opt.validation});
  log << "device: " << ctx.info().name << " (" << ctx.info().type << ", Vulkan " << ctx.info().api_version << ")\n";
  core::SceneGpu scene(ctx, mesh, env_tex);

  ReferenceCache cache(opt.cache_dir.empty() ? std::string(GLINTLAB_RESULTS_DIR "/cache/reference") : opt.cache_dir);
  std::array<float, 8> chroma = cm.chromaticities(spec.working_space);

  // Hash of everything about a reference frame except the material/shader and the frame.
  core::ContentHash scene_hash;
  scene_hash.add(std::string_view("glintlab-reference-v2"))
      .add(int64_t(kReferencePatternSeed))
      .add(spec.source.at("scene").dump())
      .add(spec.working_space)
      .add(std::string_view(ctx.info().name))
      .add(int64_t(spec.width))
      .add(int64_t(spec.height))
      .add(int64_t(spec.reference.grid))
      .add(env_tex.mips_rgba[0].data(), env_tex.mips_rgba[0].size() * 4)
      .add(env.sh_irradiance.data(), sizeof env.sh_irradiance)
      .add(core::default_shader_compiler().source_hash("passes/surface.vert", core::ShaderStage::Vertex));
  const std::string scene_key = scene_hash.hex();

  // ---- variants grouped by the reference they share
  struct VariantRun {
    const VariantSpec* spec;
    ShaderConfig shader;
    std::unique_ptr<core::SurfacePass> pass;
    metrics::FlickerTracker flicker;
    Stat gpu_ms, wall_ms;
    std::map<std::string, Stat> metric;
    size_t nan = 0, inf = 0, negative = 0;
  };
  struct RefGroup {
    ShaderConfig shader;
    std::unique_ptr<core::SurfacePass> pass;
    std::vector<VariantRun*> variants;
    std::string name;
    Stat gpu_ms, wall_ms;
    int rendered = 0, cached = 0, rebuilt = 0;
  };
  std::vector<std::unique_ptr<VariantRun>> runs;
  std::vector<std::unique_ptr<RefGroup>> groups;
  for (const VariantSpec& v : spec.variants) {
    auto run = std::make_unique<VariantRun>();
    run->spec = &v;
    core::SandParams params = to_working_space(v.material, spec.working_space, cm);
    run->shader = make_shader(params, v.debug, range, false);
    run->pass = std::make_unique<core::SurfacePass>(ctx, scene, spec.width, spec.height, run->shader.shader);
    if (measure) {
      ShaderConfig ref = make_shader(params, v.debug, range, true);
      auto it = std::find_if(groups.begin(), groups.end(),
                             [&](const auto& g) { return g->shader.material_key == ref.material_key; });
      if (it == groups.end()) {
        auto g = std::make_unique<RefGroup>();
        g->shader = ref;
        g->pass = std::make_unique<core::SurfacePass>(ctx, scene, spec.width, spec.height, ref.shader);
        groups.push_back(std::move(g));
        it = groups.end() - 1;
      }
      (*it)->variants.push_back(run.get());
    }
    runs.push_back(std::move(run));
  }
  for (auto& g : groups) g->name = groups.size() == 1 ? "reference" : "reference-" + g->variants.front()->spec->name;
  if (!measure) {  // one pseudo-group without a reference, so the loop below is shared
    auto g = std::make_unique<RefGroup>();
    for (auto& r : runs) g->variants.push_back(r.get());
    groups.push_back(std::move(g));
  }

  // Contact sheet rows: one per reference group and variant, in run order.
  std::map<std::string, std::vector<SheetTile>> sheet;
  std::vector<std::string> sheet_order;
  auto wants_tile = [&](const std::string& row) {
    return spec.output.contact_sheet &&
           (!sheet.count(row) || int(sheet[row].size()) < spec.output.contact_sheet_columns);
  };
  auto add_tile = [&](const std::string& row, int k, Image display_encoded) {
    if (!sheet.count(row)) sheet_order.push_back(row);
    sheet[row].push_back({row + " f" + std::to_string(k), std::move(display_encoded)});
  };

  // ---- CSV header
  std::vector<std::string> header = {"variant", "frame", "time_s", "spp", "gpu_ms", "wall_ms", "nan_px", "inf_px",
                                     "negative_px"};
  const auto& pool_sizes = metrics::default_pool_block_sizes();
  if (measure) {
    for (const auto& m : spec.metrics) {
      header.push_back(m);
      header.push_back(m + "_max");
    }
    header.insert(header.end(), {"temporal_error", "flicker_ratio", "glint_density_test", "glint_density_ref",
                                 "glint_hist_emd_oct"});
    for (int b : pool_sizes) {
      header.push_back("pooled_bias_" + std::to_string(b));
      header.push_back("pooled_rms_" + std::to_string(b));
    }
    header.push_back("reference_cached");
  }
  fs::path csv_path = out_dir / "frames.csv";
  fs::path csv_partial = out_dir / "frames.csv.partial";
  std::ofstream csv(csv_partial, std::ios::trunc);
  for (size_t i = 0; i < header.size(); ++i) csv << (i ? "," : "") << header[i];
  csv << "\n";

  Stat metric_ms;
  bool defects = false;
  const metrics::MetricOptions& mopt = spec.metric_options;
  int total_steps = frames * int(groups.size());
  Progress progress(log, spec.name, total_steps);
  int step = 0;

  for (auto& group : groups) {
    for (int k = 0; k < frames; ++k) {
      core::FrameCamera cam = spec.path.frame(k, spec.width, spec.height);
      core::FrameUniforms fu = frame_uniforms(cam, env, spec.width, spec.height, env_tex.mips_rgba.size());

      // -- reference of frame k (cached by content hash)
      Image ref_xyz, ref_metric_xyz;  // scene-referred; what per-pixel metrics use
      bool ref_cached = false;
      if (group->pass) {
        core::ContentHash kh;
        kh.add(std::string_view(scene_key)).add(std::string_view(group->shader.material_key))
            .add(group->pass->fragment_source_hash()).add(int64_t(k))
            .add(&cam.view_proj_unjittered, sizeof cam.view_proj_unjittered)
            .add(&fu, sizeof fu);
        std::string key = kh.hex();
        bool corrupt = false;
        std::optional<Image> ref = cache.load(key, &corrupt);
        if (corrupt) {
          log << "warning: corrupt reference cache entry " << cache.path_of(key) << " removed; re-rendering\n";
          ++group->rebuilt;
        }
        if (ref) {
          ref_cached = true;
          ++group->cached;
        } else {
          auto t0 = Clock::now();
          core::FrameOutput fo = group->pass->render(
              fu, make_samples(spec, k, spec.reference.grid, kReferencePatternSeed), "reference");
          group->wall_ms.add(ms_since(t0));
          group->gpu_ms.add(fo.timings[0].gpu_ms);
          ++group->rendered;
          cache.store(key, fo.color);
          ref = std::move(fo.color);
        }
        if (spec.output.exr && k % spec.output.every == 0) {
          fs::create_directories(out_dir / group->name);
          metrics::write_exr(frame_path(out_dir / group->name, k, "exr").string(), *ref, chroma);
        }
        if (k % spec.output.every == 0 && wants_tile(group->name)) add_tile(group->name, k, preview(*ref, spec, cm));
        ref_xyz = cm.to_xyz_d65(*ref, spec.working_space);
        ref_metric_xyz = mopt.display_view.empty() ? ref_xyz : metrics::metric_xyz(cm, *ref, spec.working_space, mopt);
      }

      // -- each variant of the group
      for (VariantRun* run : group->variants) {
        const VariantSpec& v = *run->spec;
        auto t0 = Clock::now();
        core::FrameOutput fo =
            run->pass->render(fu, make_samples(spec, k, v.aa == "ssaa" ? v.ssaa_grid : 1, kSsaaPatternSeed));
        double wall = ms_since(t0);
        run->wall_ms.add(wall);
        run->gpu_ms.add(fo.timings[0].gpu_ms);
        metrics::PixelScan scan = metrics::scan_pixels(fo.color, 3);
        run->nan += scan.nan;
        run->inf += scan.infinite;
        run->negative += scan.negative;
        if (!scan.clean()) {
          defects = true;
          log << "\nwarning: " << v.name << " frame " << k << ": " << scan.nan << " NaN, " << scan.infinite
              << " Inf, " << scan.negative << " negative pixels\n";
        }
        std::vector<std::string> row = {v.name, std::to_string(k), csv_num(cam.time),
                                        std::to_string(v.samples_per_pixel()), csv_num(fo.timings[0].gpu_ms),
                                        csv_num(wall), std::to_string(scan.nan), std::to_string(scan.infinite),
                                        std::to_string(scan.negative)};
        if (measure) {
          auto m0 = Clock::now();
          Image test_xyz = cm.to_xyz_d65(fo.color, spec.working_space);
          Image test_metric_xyz =
              mopt.display_view.empty() ? test_xyz : metrics::metric_xyz(cm, fo.color, spec.working_space, mopt);
          for (const auto& name : spec.metrics) {
            metrics::MetricResult r = metrics::evaluate_metric(name, test_metric_xyz, ref_metric_xyz, mopt);
            run->metric[name].add(r.mean);
            row.push_back(csv_num(r.mean));
            row.push_back(csv_num(r.max));
          }
          std::optional<metrics::FlickerFrame> fl = run->flicker.push(test_xyz, ref_xyz);
          row.push_back(fl ? csv_num(fl->temporal_error) : "");
          row.push_back(fl ? csv_num(fl->flicker_ratio) : "");
          if (fl) {
            run->metric["temporal_error"].add(fl->temporal_error);
            run->metric["flicker_ratio"].add(fl->flicker_ratio);
          }
          metrics::GlintComparison gc = metrics::compare_glints(test_xyz, ref_xyz);
          row.push_back(csv_num(gc.test.density_per_1000px));
          row.push_back(csv_num(gc.ref.density_per_1000px));
          row.push_back(csv_num(gc.emd_octaves));
          run->metric["glint_density_test"].add(gc.test.density_per_1000px);
          run->metric["glint_density_ref"].add(gc.ref.density_per_1000px);
          run->metric["glint_hist_emd_oct"].add(gc.emd_octaves);
          std::vector<metrics::PooledErrorScale> pooled = metrics::pooled_error(test_xyz, ref_xyz, 1);
          for (int b : pool_sizes) {
            auto it = std::find_if(pooled.begin(), pooled.end(), [&](const auto& p) { return p.block_size == b; });
            row.push_back(it != pooled.end() ? csv_num(it->bias) : "");
            row.push_back(it != pooled.end() ? csv_num(it->rms) : "");
            if (it != pooled.end()) {
              run->metric["pooled_bias_" + std::to_string(b)].add(it->bias);
              run->metric["pooled_rms_" + std::to_string(b)].add(it->rms);
            }
          }
          row.push_back(ref_cached ? "1" : "0");
          metric_ms.add(ms_since(m0));
        }
        for (size_t i = 0; i < row.size(); ++i) csv << (i ? "," : "") << row[i];
        csv << "\n" << std::flush;

        if (k % spec.output.every == 0) {
          fs::path dir = out_dir / v.name;
          if (spec.output.exr || spec.output.png) fs::create_directories(dir);
          if (spec.output.exr) metrics::write_exr(frame_path(dir, k, "exr").string(), fo.color, chroma);
          const bool tile = wants_tile(v.name);
          if (spec.output.png || tile) {
            Image shown = preview(fo.color, spec, cm);  // one display transform for the PNG and the sheet
            if (spec.output.png) metrics::write_png(frame_path(dir, k, "png").string(), shown);
            if (tile) add_tile(v.name, k, std::move(shown));
          }
        }
      }
      std::ostringstream detail;
      detail << std::fixed << std::setprecision(1);
      if (group->pass) detail << group->name << (ref_cached ? " (cached)" : "") << ", ";
      detail << group->variants.size() << " variant(s), last " << group->variants.back()->wall_ms.v.back()
             << " ms/frame";
      progress.update(++step, detail.str());
    }
  }
  csv.close();
  fs::rename(csv_partial, csv_path);
  if (spec.output.contact_sheet && !sheet_order.empty()) {
    std::vector<std::vector<SheetTile>> rows;
    for (const auto& name : sheet_order) rows.push_back(std::move(sheet[name]));
    metrics::write_png((out_dir / "contact_sheet.png").string(), make_contact_sheet(rows));
    log << "wrote " << (out_dir / "contact_sheet.png").string() << "\n";
  }

  // ---- summary.json
  nlohmann::json summary;
  summary["schema"] = "glintlab-summary/0";
  summary["glintlab_version"] = version();
  summary["experiment"] = spec.name;
  summary["file"] = spec.file;
  summary["device"] = ctx.info().name;
  summary["resolution"] = {spec.width, spec.height};
  summary["frames"] = frames;
  summary["working_space"] = spec.working_space;
  summary["ocio_config"] = cm.config_path();
  summary["measured"] = measure;
  summary["per_pixel_metrics_referred"] =
      mopt.display_view.empty() ? std::string("scene") : "display (" + mopt.display_view + ")";
  summary["units"] = {{"gpu_ms", "ms per frame, GPU timestamps"},
                      {"wall_ms", "ms per frame, submit to readback"},
                      {"deltaE2000", "CIEDE2000"},
                      {"deltaEITP", "BT.2124 dE_ITP, Y=1 at 100 cd/m2"},
                      {"flip", "FLIP error in [0,1]"},
                      {"psnr", "dB on luminance, peak 1"},
                      {"relative", "|Yt-Yr|/(Yr+0.01)"},
                      {"temporal_error", "mean|dT-dR| in PQ code values"},
                      {"flicker_ratio", "mean|dT|/mean|dR|"},
                      {"glint_density", "glint pixels per 1000 px"}};
  if (measure) {
    nlohmann::json refs = nlohmann::json::array();
    for (auto& g : groups) {
      refs.push_back({{"name", g->name},
                      {"spp", spec.reference.grid * spec.reference.grid},
                      {"frames_rendered", g->rendered},
                      {"frames_cached", g->cached},
                      {"corrupt_entries_rebuilt", g->rebuilt},
                      {"gpu_ms", g->gpu_ms.summary()},
                      {"wall_ms", g->wall_ms.summary()}});
    }
    summary["references"] = refs;
    summary["metric_ms_per_frame"] = metric_ms.summary();
  }
  nlohmann::json vs = nlohmann::json::object();
  for (auto& r : runs) {
    nlohmann::json j;
    j["aa"] = r->spec->aa;
    j["spp"] = r->spec->samples_per_pixel();
    j["debug"] = r->spec->debug;
    j["defines"] = r->shader.shader.defines;
    j["gpu_ms"] = r->gpu_ms.summary();
    j["wall_ms"] = r->wall_ms.summary();
    j["nonfinite"] = {{"nan_px", r->nan}, {"inf_px", r->inf}, {"negative_px", r->negative}};
    if (measure) {
      nlohmann::json m = nlohmann::json::object();
      for (auto& [name, st] : r->metric) m[name] = st.summary();
      j["metrics"] = m;
      j["flicker"] = {{"temporal_error_mean", num(r->flicker.mean_temporal_error())},
                      {"flicker_ratio_mean", num(r->flicker.mean_flicker_ratio())},
                      {"flicker_ratio_of_sums", num(r->flicker.ratio_of_sums())}};
    }
    vs[r->spec->name] = j;
  }
  summary["variants"] = vs;
  write_text_atomic(out_dir / "summary.json", summary.dump(2) + "\n");

  log << "wrote " << csv_path.string() << " and " << (out_dir / "summary.json").string() << "\n";
  for (auto& r : runs) {
    log << "  " << std::left << std::setw(16) << r->spec->name << std::right << std::fixed << std::setprecision(2)
        << " gpu " << r->gpu_ms.mean() << " ms/frame";
    if (measure && r->metric.count("deltaE2000")) log << ", deltaE2000 " << r->metric["deltaE2000"].mean();
    if (measure) log << ", flicker ratio " << r->flicker.ratio_of_sums();
    log << "\n";
  }
  if (measure)
    for (auto& g : groups)
      log << "  " << g->name << ": " << g->rendered << " rendered (" << std::setprecision(1) << g->gpu_ms.mean()
          << " ms/frame GPU at " << spec.reference.grid * spec.reference.grid << " spp), " << g->cached << " cached\n";
  int status = 0;
  if (defects) {
    log << "error: some frames had NaN, Inf or negative pixels (see frames.csv)\n";
    status = 1;
  }
  if (ctx.validation_enabled() && ctx.validation_message_count() > 0) {
    log << "error: the Vulkan validation layer reported " << ctx.validation_message_count() << " message(s)\n";
    status = 1;
  }
  return status;
}

}  // namespace glintlab

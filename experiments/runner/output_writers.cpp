#include "experiments/runner/output_writers.h"

#include "core/render/taa_resolve.h"
#include "core/util/atomic_file.h"
#include "core/util/json_check.h"
#include "experiments/runner/contact_sheet.h"
#include "experiments/report/report.h"
#include "experiments/runner/version.h"
#include "metrics/color/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

nlohmann::json num(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

fs::path frame_path(const fs::path& dir, int frame, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.%s", frame, ext);
  return dir / name;
}

// Collects what the journal holds for the schema: metric and floor names (in order), pass names (first seen).
struct RecordNames final : RecordSink {
  std::vector<std::string> metrics, passes, floors;
  void frame(const FrameRecord& r) override {
    if (metrics.empty())
      for (const auto& [n, v] : r.metrics) metrics.push_back(n);
    if (floors.empty())
      for (const auto& [n, v] : r.floor) floors.push_back(n);
    for (const auto& t : r.passes)
      if (std::find(passes.begin(), passes.end(), t.pass) == passes.end()) passes.push_back(t.pass);
  }
};

}  // namespace

nlohmann::json stats_json(const metrics::Statistics& s) {
  return {{"mean", num(s.mean())}, {"p95", num(s.p95())}, {"max", num(s.max())}, {"n", s.count()}};
}

void DefectCount::frame(const FrameRecord& r) {
  frames += !r.scan.clean();
  for (const auto& [n, v] : r.metrics)
    if ((n == "reference_nonfinite_px" || n == "reference_negative_px") && v > 0) {
      ++reference_frames;
      break;
    }
}

// ---------------------------------------------------------------- CsvWriter
CsvWriter::CsvWriter(fs::path path, const FrameSchema& schema) : path_(std::move(path)), schema_(schema) {}

void CsvWriter::frame(const FrameRecord& r) { rows_[{r.variant, r.frame}] = schema_.row(r); }

void CsvWriter::finish() {
  std::string text;
  const auto& cols = schema_.columns();
  for (size_t i = 0; i < cols.size(); ++i) text += (i ? "," : "") + cols[i].name;
  text += "\n";
  for (const auto& [key, cells] : rows_) {
    for (size_t i = 0; i < cells.size(); ++i) text += (i ? "," : "") + cells[i];
    text += "\n";
  }
  write_text_atomic(path_, text);
}

// ---------------------------------------------------------------- SummaryWriter
SummaryWriter::SummaryWriter(fs::path path, const RunPlan& plan, const FrameSchema& schema, RunInfo info)
    : path_(std::move(path)), plan_(plan), schema_(schema), info_(std::move(info)),
      variants_(plan.variants.size()), references_(plan.references.size()) {}

void SummaryWriter::reference(const ReferenceRecord& r) {
  ReferenceStats& s = references_.at(size_t(r.reference));
  for (const auto& [name, v] : r.halves_metrics)  // a temporal metric is undefined at a sequence's start
    if (!std::isnan(v)) s.halves[name].add(v);
  for (const auto& [name, v] : metrics::noise_floor(r.halves_metrics))
    if (!std::isnan(v)) s.floor[name].add(v);
  if (r.cached) {
    ++s.cached;
    return;
  }
  ++s.rendered;
  if (r.rebuilt) ++s.rebuilt;
  s.gpu_ms.add(r.gpu_ms);
  s.wall_ms.add(r.wall_ms);
}

void SummaryWriter::frame(const FrameRecord& r) {
  VariantStats& s = variants_.at(size_t(r.variant));
  if (r.frame >= info_.warmup_frames || plan_.frames <= info_.warmup_frames) {
    s.gpu_ms.add(r.gpu_ms);
    s.wall_ms.add(r.wall_ms);
    for (const auto& t : r.passes) s.per_pass[t.pass].add(t.gpu_ms);
  }
  for (const Column& c : schema_.columns())
    if (c.summarised) {
      const double v = schema_.value(r, c.name);
      // Temporal metrics have no value in a sequence's first frame: that is
      // "not defined", not a failed measurement.
      if (std::isnan(v) && r.sequence_start && r.scan.clean()) continue;
      s.columns[c.name].add(v);
    }
  if (!r.metric_cost_ms.empty()) {
    double total = 0;
    for (const auto& [name, ms] : r.metric_cost_ms) {
      metric_ms_per_metric_[name].add(ms);
      total += ms;
    }
    metric_ms_.add(total);
  }
}

void SummaryWriter::finish() {
  const ExperimentSpec& spec = *plan_.spec;
  nlohmann::json j;
  j["schema"] = kSummarySchema;
  j["glintlab_version"] = version();
  j["experiment"] = spec.name;
  j["file"] = spec.file;
  j["device"] = info_.device;
  j["resolution"] = {spec.width, spec.height};
  j["frames"] = plan_.frames;
  j["working_space"] = spec.working_space;
  j["ocio_config"] = info_.ocio_config;
  j["measured"] = plan_.measure;
  j["per_pixel_metrics_referred"] = spec.metric_options.display_view.empty()
                                        ? std::string("scene")
                                        : "display (" + spec.metric_options.display_view + ")";
  j["temporal_score_view"] = spec.measured_metric_options().temporal_view;  // what temporal_score saw
  j["timing_warmup_frames_excluded"] = info_.warmup_frames;
  for (auto it = info_.extra.begin(); it != info_.extra.end(); ++it) j[it.key()] = it.value();
  j["statistics"] = "per variant over frames: mean, p95 (nearest rank) and max; a NaN frame makes all three null "
                    "(and n counts it); +-inf is written as null";
  nlohmann::json units = nlohmann::json::object();
  for (const Column& c : schema_.columns())
    if (!c.unit.empty()) units[c.name] = c.unit;
  j["units"] = units;
  std::vector<std::string> metric_names;  // every summarised metric, and the ratio the report makes of two
  for (const Column& c : schema_.columns())
    if (c.summarised) metric_names.push_back(c.name);
  metric_names.push_back("glint_density_ratio");
  j["metric_info"] = metric_info_json(metric_names);

  nlohmann::json refs = nlohmann::json::array();
  for (size_t i = 0; i < plan_.references.size(); ++i) {
    const ReferenceStats& s = references_[i];
    refs.push_back({{"name", plan_.references[i].name},
                    {"spp", spec.reference.frames.empty() ? nlohmann::json(spec.reference.grid * spec.reference.grid)
                                                          : nlohmann::json(nullptr)},
                    {"frames", spec.reference.frames.empty() ? nlohmann::json(nullptr)
                                                             : nlohmann::json(spec.reference.frames)},
                    {"variants", [&] {
                       nlohmann::json v = nlohmann::json::array();
                       for (int k : plan_.references[i].variants) v.push_back(plan_.variants[size_t(k)].spec->name);
                       return v;
                     }()},
                    {"frames_rendered", s.rendered},
                    {"frames_cached", s.cached},
                    {"corrupt_entries_rebuilt", s.rebuilt},
                    {"gpu_ms", stats_json(s.gpu_ms)},
                    {"wall_ms", stats_json(s.wall_ms)}});
    if (!spec.reference.frames_b.empty()) refs.back()["frames_b"] = spec.reference.frames_b;
    if (!s.halves.empty()) {
      nlohmann::json halves, floor;
      for (const auto& [name, st] : s.halves) halves[name] = stats_json(st);
      for (const auto& [name, st] : s.floor) floor[name] = num(st.mean());
      refs.back()["halves"] = halves;
      refs.back()["floor"] = floor;
    }
  }
  j["references"] = refs;
  if (plan_.measure) {
    j["metric_ms_per_frame"] = stats_json(metric_ms_);
    nlohmann::json per = nlohmann::json::object();
    for (const auto& [name, st] : metric_ms_per_metric_) per[name] = stats_json(st);
    j["metric_ms_per_metric"] = per;
  }

  nlohmann::json vs = nlohmann::json::array();
  for (size_t i = 0; i < plan_.variants.size(); ++i) {
    const RunPlan::Variant& pv = plan_.variants[i];
    const VariantSpec& v = *pv.spec;
    const VariantStats& s = variants_[i];
    nlohmann::json e;
    e["name"] = v.name;
    if (!v.frames.empty()) {  // a frame source: what its files are is the files' business
      e["source"] = "frames";
      e["frames"] = v.frames;
    } else {
      e["aa"] = enum_name(kAaNames, v.aa);
      e["glint_model"] = pv.params.glint_model;
      if (const core::GlintModelDecl* gd = pv.params.glint_decl()) {
        nlohmann::json gp = nlohmann::json::object();
        for (const auto& p : gd->parameters) gp[p.name] = pv.params.glint_parameter(p.name);
        e["glint_parameters"] = gp;  // the model's own, defaults included
      }
      e["spp"] = v.samples_per_pixel();
      if (v.aa == AaMethod::Ssaa) e["ssaa_grid"] = v.ssaa_grid;
      if (v.aa == AaMethod::Taa) e["taa"] = v.taa.to_json();
      if (v.render_scale < 1.0) {  // rendered below the output resolution (the GPU ms per pass are of both)
        e["render_scale"] = v.render_scale;
        e["render_resolution"] = {v.render_width(spec.width), v.render_height(spec.height)};
        e["glint_footprint"] = v.glint_footprint;
        if (spec.mesh.max_edge_px > 0.0f) e["mesh_lod"] = v.mesh_lod;  // an adaptive grid: which resolution's
      }
      e["debug"] = v.debug;
      e["material"] = v.material_json;  // preset and every override (glints, energy_consistent, ...)
      if (v.truth_material) e["truth_material"] = v.truth_material_json;
      e["defines"] = pv.program.defines;
    }
    e["reference"] = pv.reference >= 0 ? nlohmann::json(plan_.references[size_t(pv.reference)].name) : nullptr;
    e["gpu_ms"] = stats_json(s.gpu_ms);
    nlohmann::json pp = nlohmann::json::object();
    for (const auto& [pass, st] : s.per_pass) pp[pass] = stats_json(st);
    e["gpu_ms_per_pass"] = pp;
    e["wall_ms"] = stats_json(s.wall_ms);
    nlohmann::json m = nlohmann::json::object();
    for (const Column& c : schema_.columns())
      if (c.summarised && s.columns.count(c.name)) m[c.name] = stats_json(s.columns.at(c.name));
    e["metrics"] = m;
    vs.push_back(e);
  }
  j["variants"] = vs;
  summary_ = j;
  write_text_atomic(path_, dump_json(j, 2) + "\n");
}

// frames.csv, summary.json, the contact sheet and the report, all from the journals.
// report_status: the report's exit code (0 when not asked for).
nlohmann::json write_run_outputs(const fs::path& dir, const RunPlan& plan, const std::vector<const Journal*>& journals,
                                 const RunInfo& info, ImageWriter& images, bool report, int* report_status,
                                 std::ostream& log) {
  *report_status = 0;
  RecordNames names;
  for (const Journal* j : journals) j->replay(names);
  const FrameSchema schema(names.metrics, names.passes, names.floors);
  CsvWriter csv(dir / "frames.csv", schema);
  SummaryWriter summary(dir / "summary.json", plan, schema, info);
  for (const Journal* j : journals) {
    j->replay(csv);
    j->replay(summary);
  }
  csv.finish();
  summary.finish();
  images.finish();
  log << "wrote " << (dir / "frames.csv").string() << ", " << (dir / "summary.json").string()
      << (plan.spec->output.contact_sheet ? " and " + (dir / "contact_sheet.png").string() : std::string()) << "\n";
  if (report) *report_status = write_report(dir.string(), log);
  return summary.summary();
}

// ---------------------------------------------------------------- ImageWriter
ImageWriter::ImageWriter(fs::path dir, const RunPlan& plan, const metrics::ColorManager& cm)
    : dir_(std::move(dir)), plan_(plan), cm_(cm) {
  if (plan.spec->output.exr) chroma_ = cm.chromaticities(plan.spec->working_space);
}

void ImageWriter::save(const std::string& row, int frame, const Image& img, bool exr, bool png, bool sheet) {
  const OutputSpec& out = plan_.spec->output;
  if (frame % out.every != 0) return;
  // The contact sheet is built from the PNGs on disk (so that resumed and
  // merged runs have one too): the first columns of every row get a PNG.
  const bool tile = sheet && out.contact_sheet && frame / out.every < out.contact_sheet_columns;
  png = png || tile;
  const fs::path dir = dir_ / row;
  if (exr || png) fs::create_directories(dir);
  if (exr) metrics::write_exr(frame_path(dir, frame, "exr").string(), img, chroma_);
  if (!png) return;
  // Display-encoded through the OCIO display/view after the exposure, opaque
  // (alpha is coverage in the render, which a preview should not show as
  // transparency).
  Image exposed = img;
  if (out.exposure != 0.0) {
    const float gain = float(std::exp2(out.exposure));
    for (size_t i = 0; i < exposed.data.size(); ++i)
      if (exposed.channels < 4 || i % size_t(exposed.channels) != 3) exposed.data[i] *= gain;
  }
  Image shown = cm_.display(exposed, plan_.spec->working_space, out.display, out.view);
  if (shown.channels == 4)
    for (size_t i = 3; i < shown.data.size(); i += 4) shown.data[i] = 1.0f;
  metrics::write_png(frame_path(dir, frame, "png").string(), shown);
}

void ImageWriter::reference(const ReferenceRecord& r) {
  save(r.name, r.frame, *r.image, plan_.spec->output.exr, plan_.spec->output.png);
  if (plan_.spec->output.halves && r.half_a && r.half_b) {  // EXR only: they are for measuring
    save(r.name + "-half-a", r.frame, *r.half_a, true, false, false);
    save(r.name + "-half-b", r.frame, *r.half_b, true, false, false);
  }
}

void ImageWriter::frame(const FrameRecord& r) {
  save(r.name, r.frame, *r.image, plan_.spec->output.exr, plan_.spec->output.png);
}

void ImageWriter::motion(int frame, const Image& m) {
  const OutputSpec& out = plan_.spec->output;
  if (!out.motion || frame % out.every != 0) return;
  fs::create_directories(dir_ / "motion");
  metrics::write_exr_data(frame_path(dir_ / "motion", frame, "exr").string(), m);
}

void ImageWriter::finish() {
  const OutputSpec& out = plan_.spec->output;
  if (!out.contact_sheet) return;
  std::vector<std::string> rows;
  for (const auto& r : plan_.references) rows.push_back(r.name);
  for (const auto& v : plan_.variants) rows.push_back(v.spec->name);
  std::vector<std::vector<SheetTile>> sheet, zoomed;
  // The zoom region of a tile (clipped to it), each pixel repeated zoom_scale times.
  auto zoom = [&](const Image& im) {
    const int x0 = std::min(out.zoom_x, im.width - 1), y0 = std::min(out.zoom_y, im.height - 1);
    const int w = std::max(1, std::min(out.zoom_w, im.width - x0)), h = std::max(1, std::min(out.zoom_h, im.height - y0));
    const int k = out.zoom_scale;
    Image z(w * k, h * k, im.channels);
    for (int y = 0; y < h * k; ++y)
      for (int x = 0; x < w * k; ++x)
        for (int c = 0; c < im.channels; ++c) z.at(x, y, c) = im.at(x0 + x / k, y0 + y / k, c);
    return z;
  };
  for (const auto& row : rows) {
    std::vector<SheetTile> tiles, zooms;
    for (int c = 0; c < out.contact_sheet_columns; ++c) {
      const int frame = c * out.every;
      const fs::path png = frame_path(dir_ / row, frame, "png");
      if (frame >= plan_.frames || !fs::exists(png)) break;
      const std::string label = row + " f" + std::to_string(frame);
      tiles.push_back({label, metrics::read_image(png.string())});
      if (out.zoom_scale > 0) zooms.push_back({label, zoom(tiles.back().image)});
    }
    if (!tiles.empty()) sheet.push_back(std::move(tiles));
    if (!zooms.empty()) zoomed.push_back(std::move(zooms));
  }
  if (!sheet.empty()) metrics::write_png((dir_ / "contact_sheet.png").string(), make_contact_sheet(sheet));
  if (!zoomed.empty())
    metrics::write_png((dir_ / "contact_sheet_zoom.png").string(),
                       make_contact_sheet(zoomed, out.zoom_w * out.zoom_scale));
}

}  // namespace glintlab

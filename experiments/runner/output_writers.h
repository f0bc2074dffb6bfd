// The consumers of a run's records that write files, each atomically
// (core/util/atomic_file.h):
//   CsvWriter      frames.csv: one row per variant x frame (schema.h columns),
//                  variants in run order, frames ascending
//   SummaryWriter  summary.json: per variant the aggregates of every
//                  summarised column, GPU time per pass and wall time
//                  (metrics/stats.h rules), per reference its cost
//   ImageWriter    <variant>/frame_NNNN.exr (scene-linear, chromaticities) and
//                  .png (through the OCIO display/view), the same for each
//                  reference, contact_sheet.png, and with output.motion
//                  motion/frame_NNNN.exr (float: R, G = v in pixels, B = the surface's
//                  distance now, A = its distance in the previous frame: the `pixels`
//                  convention of `glintlab measure`)
#pragma once

#include "experiments/runner/contact_sheet.h"
#include "experiments/runner/journal.h"
#include "experiments/runner/plan.h"
#include "experiments/runner/records.h"
#include "experiments/runner/schema.h"
#include "metrics/color/color_manager.h"
#include "metrics/stats.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

class CsvWriter final : public RecordSink {
 public:
  CsvWriter(std::filesystem::path path, const FrameSchema& schema);
  void frame(const FrameRecord& r) override;
  void finish() override;

 private:
  std::filesystem::path path_;
  const FrameSchema& schema_;
  std::map<std::pair<int, int>, std::vector<std::string>> rows_;  // (variant, frame) -> cells
};

// Run-level facts the summary records besides the aggregates.
struct RunInfo {
  std::string device;
  std::string ocio_config;
  int warmup_frames = 1;  // frames left out of the timing aggregates
  nlohmann::json extra = nlohmann::json::object();  // further top-level keys (measure: motion, sources)
};

class SummaryWriter final : public RecordSink {
 public:
  SummaryWriter(std::filesystem::path path, const RunPlan& plan, const FrameSchema& schema, RunInfo info);
  void reference(const ReferenceRecord& r) override;
  void frame(const FrameRecord& r) override;
  void finish() override;
  // The document finish() wrote (for the console table).
  const nlohmann::json& summary() const { return summary_; }

 private:
  struct VariantStats {
    metrics::Statistics gpu_ms, wall_ms;
    std::map<std::string, metrics::Statistics> per_pass;
    std::map<std::string, metrics::Statistics> columns;
  };
  struct ReferenceStats {
    metrics::Statistics gpu_ms, wall_ms;
    int rendered = 0, cached = 0, rebuilt = 0;
    std::map<std::string, metrics::Statistics> halves;  // each metric of half B against half A
    std::map<std::string, metrics::Statistics> floor;   // the noise floor of each metric that has one
  };
  std::filesystem::path path_;
  const RunPlan& plan_;
  const FrameSchema& schema_;
  RunInfo info_;
  std::vector<VariantStats> variants_;
  std::vector<ReferenceStats> references_;
  metrics::Statistics metric_ms_;
  std::map<std::string, metrics::Statistics> metric_ms_per_metric_;
  nlohmann::json summary_;
};

class ImageWriter final : public RecordSink {
 public:
  ImageWriter(std::filesystem::path dir, const RunPlan& plan, const metrics::ColorManager& cm);
  void reference(const ReferenceRecord& r) override;
  void frame(const FrameRecord& r) override;
  void motion(int frame, const Image& motion) override;
  void finish() override;

 private:
  void save(const std::string& row, int frame, const Image& img, bool exr, bool png, bool sheet = true);
  std::filesystem::path dir_;
  const RunPlan& plan_;
  const metrics::ColorManager& cm_;
  std::array<float, 8> chroma_{};  // of the working space, when EXRs are written
};

// Counts the defects a run exits 1 for: variant frames with NaN/Inf/negative pixels, and variant
// frames measured against a reference frame that had any (`reference_nonfinite_px`,
// `reference_negative_px`: their metrics are NaN). `run` and `measure` alike.
struct DefectCount final : RecordSink {
  size_t frames = 0, reference_frames = 0;
  void frame(const FrameRecord& r) override;
};

// frames.csv, summary.json, the contact sheet and the report of a run (`run`, `merge`, `measure`),
// all from its journals: every output is a replay of the records. report_status receives the
// report's exit code (0 when not asked for). Returns the summary document.
nlohmann::json write_run_outputs(const std::filesystem::path& dir, const RunPlan& plan,
                                 const std::vector<const Journal*>& journals, const RunInfo& info,
                                 ImageWriter& images, bool report, int* report_status, std::ostream& log);

// {"mean", "p95", "max", "n"}; non-finite values are null (JSON has no
// infinity or NaN).
nlohmann::json stats_json(const metrics::Statistics& s);

}  // namespace glintlab

// What the frame loop emits: one record per reference frame and one per
// variant x frame, handed to every consumer (CSV, summary, images, ...) as
// soon as the frame is measured. Images are valid only during the call.
#pragma once

#include "core/render/frame_graph.h"
#include "core/util/image.h"
#include "metrics/frame_metrics.h"
#include "metrics/pixel_scan.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace glintlab {

struct ReferenceRecord {
  int reference = 0;  // index in RunPlan::references
  std::string name;
  int frame = 0;
  const Image* image = nullptr;  // scene-linear
  bool cached = false;           // loaded from the cache (not rendered)
  bool rebuilt = false;          // the cache entry was corrupt and was rendered again
  double gpu_ms = 0, wall_ms = 0;  // rendered frames only
  // The truth's noise at half its samples: every metric of its half B against its half A (empty where
  // the truth has no halves: read from files, or rendered at factor 1).
  metrics::NamedValues halves_metrics;
  const Image* half_a = nullptr;  // the halves themselves (where it has them), valid during the call
  const Image* half_b = nullptr;
};

struct FrameRecord {
  int variant = 0;  // index in RunPlan::variants
  std::string name;
  int frame = 0;
  double time_s = 0;
  bool sequence_start = false;  // frame 0 or a camera cut: temporal metrics have no predecessor
  int spp = 1;
  double gpu_ms = 0;                      // the variant's whole frame (GPU timestamps)
  std::vector<core::PassTiming> passes;   // per pass
  double wall_ms = 0;                     // record, submit, wait and read back
  metrics::PixelScan scan;                // NaN / Inf / negative pixels of the image
  metrics::NamedValues metrics;           // empty when the run does not measure
  metrics::NamedValues metric_cost_ms;    // wall time of each metric group
  // The noise floor of each metric that has one, from the halves of this frame's truth
  // (metrics::noise_floor); empty where the truth has no halves.
  metrics::NamedValues floor;
  bool reference_cached = false;
  const Image* image = nullptr;           // scene-linear RGBA
};

// A metric named *_px counts pixels (NaN, Inf, negative, disoccluded, valid): a count column, and the
// values a frame keeps where its other metrics are void.
inline bool is_pixel_count(const std::string& metric) {
  return metric.size() > 3 && metric.compare(metric.size() - 3, 3, "_px") == 0;
}

// JSON of a record without its image (the journal's lines). Non-finite
// numbers are written as strings ("nan", "inf", "-inf") so that they survive.
nlohmann::json to_json(const FrameRecord& r);
nlohmann::json to_json(const ReferenceRecord& r);
FrameRecord frame_record_from_json(const nlohmann::json& j);
ReferenceRecord reference_record_from_json(const nlohmann::json& j);

class RecordSink {
 public:
  virtual ~RecordSink() = default;
  virtual void reference(const ReferenceRecord&) {}
  virtual void frame(const FrameRecord& r) = 0;
  // The motion target of a frame (4 channels: v in pixels, distance now, distance in the previous
  // frame), for sinks that save it (`"output": {"motion": true}`).
  virtual void motion(int /*frame*/, const Image& /*motion*/) {}
  // After the last frame: write what is written once.
  virtual void finish() {}
};

}  // namespace glintlab

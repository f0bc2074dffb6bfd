// The frame loop of a run: for every frame of the path it renders the motion
// pass (exact motion vectors), gets each reference frame from the cache or
// renders it, renders every variant's frame graph, measures it, and hands one
// record per reference frame and per variant x frame to the consumers.
// Temporal state (TAA history, flicker trackers) lives per variant and
// restarts at camera cuts.
#pragma once

#include "core/render/scene_gpu.h"
#include "core/vk/vk_context.h"
#include "experiments/runner/plan.h"
#include "experiments/runner/records.h"
#include "experiments/runner/reference_cache.h"
#include "experiments/runner/variant_factory.h"
#include "experiments/runner/work_schedule.h"
#include "metrics/color/color_manager.h"

#include <memory>
#include <ostream>
#include <vector>

namespace glintlab {

class FrameLoop {
 public:
  FrameLoop(const core::VkContext& ctx, const core::SceneGpu& scene, const RunPlan& plan, const SceneData& data,
            const metrics::ColorManager& cm, const ReferenceCache& cache, std::ostream& log);
  ~FrameLoop();

  // Every pass name of any variant, in first-seen order (the gpu_ms_<pass> columns).
  std::vector<std::string> pass_names() const;
  // Names of the per-frame metrics (empty when the run does not measure).
  std::vector<std::string> metric_names() const;

  // Does the work of `schedule`, handing each emitted record to every sink.
  void run(const WorkSchedule& schedule, const std::vector<RecordSink*>& sinks);
  // Whether any variant frame had NaN, Inf or negative pixels.
  bool defects() const { return defects_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool defects_ = false;
};

}  // namespace glintlab

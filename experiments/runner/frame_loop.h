// The frame loop of every run, rendered or read from files: for every frame it
// asks the run's sources (experiments/sources/frame_source.h) for the truths,
// the motion and each variant's frame, measures every variant against its
// truth along the motion (or, without a truth, its own flicker), and hands one
// record per truth frame and per variant x frame to the consumers (journal,
// writers). Temporal state (flicker trackers, the truth halves' tracker)
// lives per variant and restarts at camera cuts and wherever the frame before
// was not measured.
#pragma once

#include "experiments/runner/plan.h"
#include "experiments/runner/records.h"
#include "experiments/runner/work_schedule.h"
#include "experiments/sources/frame_source.h"
#include "metrics/frame_metrics.h"

#include <functional>
#include <memory>
#include <ostream>
#include <vector>

namespace glintlab {

// Where frame k is in time: its time stamp, whether the camera cuts there, and the number messages call
// it by (a file sequence's own frame number).
struct FrameClock {
  double time_s = 0;
  bool cut = false;
  int number = 0;
};

struct LoopSources {
  std::vector<std::unique_ptr<ColourSource>> variants;    // one per RunPlan::variants
  std::vector<std::unique_ptr<ColourSource>> references;  // one per RunPlan::references
  std::unique_ptr<MotionSource> motion;                    // null where nothing needs motion
  std::function<FrameClock(int)> clock;
  // Whether each record also says how well the motion explains the base sequence's own change
  // (motion_explained*, motion_nonfinite_px: metrics/motion_check.h), for motion another renderer gave.
  bool check_motion = false;
};

class FrameLoop {
 public:
  // `frame_metrics`: what each frame is measured with (null where the run does not measure).
  FrameLoop(const RunPlan& plan, LoopSources sources, const metrics::FrameMetrics* frame_metrics, std::ostream& log);
  ~FrameLoop();

  // Does the work of `schedule`, handing each emitted record to every sink.
  void run(const WorkSchedule& schedule, const std::vector<RecordSink*>& sinks);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace glintlab

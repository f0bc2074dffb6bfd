#include "experiments/runner/work_schedule.h"

#include <algorithm>

namespace glintlab {

std::pair<int, int> shard_range(int frames, int k, int n) {
  return {int(int64_t(frames) * k / n), int(int64_t(frames) * (k + 1) / n)};
}

size_t WorkSchedule::emitted_frames() const {
  size_t n = 0;
  for (const auto& v : emit) n += size_t(std::count(v.begin(), v.end(), 1));
  return n;
}

WorkSchedule schedule_work(const RunPlan& plan, const Journal& journal, int frame_begin, int frame_end) {
  WorkSchedule w;
  w.frame_begin = frame_begin;
  w.frame_end = frame_end;
  const size_t F = size_t(plan.frames), V = plan.variants.size();
  w.render.assign(V, std::vector<char>(F, 0));
  w.measure = w.emit = w.render;
  w.motion.assign(F, 0);
  w.reference.assign(plan.references.size(), std::vector<char>(F, 0));
  for (size_t v = 0; v < V; ++v) {
    int last = -1;
    for (int k = frame_begin; k < frame_end; ++k)
      if (!journal.has_frame(int(v), k)) {
        w.emit[v][size_t(k)] = 1;
        last = k;
      }
    // A rendered variant's frame depends on its history (TAA): every frame up to its last one is
    // rendered. A frame read from files does not: only those measured or emitted are read.
    const bool history = !plan.variants[v].files;
    for (int k = 0; k <= last; ++k) w.render[v][size_t(k)] = history || w.emit[v][size_t(k)];
    w.last_frame = std::max(w.last_frame, last);
    if (plan.spec && plan.spec->output.motion)  // written for every frame the run records
      for (int k = frame_begin; k < frame_end; ++k)
        if (w.emit[v][size_t(k)]) w.motion[size_t(k)] = 1;
    if (!plan.measure) continue;
    for (int k = 0; k <= last; ++k) {
      const bool m = w.emit[v][size_t(k)] || (k + 1 < int(F) && w.emit[v][size_t(k) + 1]);
      if (!m) continue;
      w.measure[v][size_t(k)] = w.render[v][size_t(k)] = 1;
      w.motion[size_t(k)] = 1;
      if (plan.variants[v].reference >= 0) w.reference[size_t(plan.variants[v].reference)][size_t(k)] = 1;
    }
  }
  return w;
}

}  // namespace glintlab

#include "experiments/runner/frame_loop.h"

#include "metrics/metric_registry.h"

#include "core/util/strings.h"
#include "experiments/runner/progress.h"
#include "metrics/motion_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

namespace glintlab {

namespace {

using Clock = std::chrono::steady_clock;
const double kNan = std::nan("");

// A frame with NaN, Inf or negative pixels measures nothing: every metric but the pixel counts is NaN.
void void_metrics(metrics::NamedValues& values) {
  for (auto& [name, value] : values)
    if (!is_pixel_count(name)) value = kNan;
}

// The metrics that compare a frame with the one before (the registry's "flicker" group): NaN where the
// frame before had NaN, Inf or negative pixels, which they would otherwise average in.
void void_temporal_metrics(metrics::NamedValues& values) {
  for (auto& [name, value] : values) {
    const metrics::MetricInfo* m = metrics::metric_info(name);
    if (m && std::string(m->group) == "flicker" && !is_pixel_count(name)) value = kNan;
  }
}

std::string defect_text(const metrics::PixelScan& s) {
  return std::to_string(s.nan) + " NaN, " + std::to_string(s.infinite) + " Inf, " + std::to_string(s.negative) +
         " negative pixels";
}

// Frame k's truths as the variants are measured against them.
struct Truth {
  SourceFrame frame;
  std::optional<metrics::FrameMetrics::Reference> prepared;
  metrics::NamedValues floor;
  bool bad_before = false;  // its frame before (in the same shot) had NaN, Inf or negative pixels
};

}  // namespace

struct FrameLoop::Impl {
  const RunPlan& plan;
  LoopSources sources;
  const metrics::FrameMetrics* fm;  // null when the run does not measure
  std::ostream& log;
  std::vector<metrics::FlickerTracker> trackers;       // per variant
  std::vector<metrics::FlickerTracker> half_trackers;  // per truth: its half B along the motion against half A
  std::shared_ptr<const metrics::FlickerReference> check_before;  // the motion check's frame before
  int check_before_k = -2;
  std::vector<int> variant_bad, truth_bad;  // the last frame of each with NaN, Inf or negative pixels (-2: none)

  Impl(const RunPlan& p, LoopSources s, const metrics::FrameMetrics* f, std::ostream& l)
      : plan(p), sources(std::move(s)), fm(f), log(l), trackers(p.variants.size()), half_trackers(p.references.size()),
        variant_bad(p.variants.size(), -2), truth_bad(p.references.size(), -2) {}

  Truth truth(int k, size_t r, SourceFrame f, const WorkSchedule& work, const FrameClock& clock,
              const MotionFrame& motion, bool own_frame, const std::vector<RecordSink*>& sinks);
  metrics::MotionExplained check_motion(int k, const std::shared_ptr<const metrics::FlickerReference>& base,
                                        const Image& motion);
  FrameRecord variant_record(int k, size_t i, const SourceFrame& f, const WorkSchedule& work, const FrameClock& clock,
                             const std::vector<std::optional<Truth>>& truths, const MotionFrame& motion,
                             const metrics::MotionExplained& me,
                             std::shared_ptr<const metrics::FlickerReference> own);
};

FrameLoop::FrameLoop(const RunPlan& plan, LoopSources sources, const metrics::FrameMetrics* frame_metrics,
                     std::ostream& log)
    : impl_(std::make_unique<Impl>(plan, std::move(sources), frame_metrics, log)) {}

FrameLoop::~FrameLoop() = default;

// Truth r at frame k: its record (with its noise floor where it has two halves), the metrics' view of it.
Truth FrameLoop::Impl::truth(int k, size_t r, SourceFrame f, const WorkSchedule& work, const FrameClock& clock,
                             const MotionFrame& motion, bool own_frame, const std::vector<RecordSink*>& sinks) {
  const size_t kk = size_t(k);
  Truth t;
  ReferenceRecord rec;
  rec.reference = int(r);
  rec.name = plan.references[r].name;
  rec.frame = k;
  rec.image = f.image.get();
  rec.cached = f.cached;
  rec.rebuilt = f.rebuilt;
  rec.wall_ms = f.wall_ms;
  rec.gpu_ms = f.gpu_ms;
  t.bad_before = !(k == 0 || clock.cut) && truth_bad[r] == k - 1;
  if (!f.scan.clean()) truth_bad[r] = k;
  if (fm && f.half_a && f.half_b) {  // the noise floor: every metric of half B against half A, along the motion
    if (k == 0 || clock.cut || !work.reference[r][kk - 1]) half_trackers[r].reset();
    if (!f.half_a_prepared) f.half_a_prepared = fm->prepare(f.half_a, false);
    rec.halves_metrics = fm->measure(*f.half_b, *f.half_a_prepared, motion.motion, half_trackers[r]);
    if (!f.scan.clean()) void_metrics(rec.halves_metrics);  // no floor from a bad frame, nor from the next one
    else if (t.bad_before) void_temporal_metrics(rec.halves_metrics);
    t.floor = metrics::noise_floor(rec.halves_metrics);
    rec.half_a = f.half_a.get();
    rec.half_b = f.half_b.get();
  }
  if (own_frame)
    for (RecordSink* s : sinks) s->reference(rec);
  if (own_frame && !f.scan.clean())
    log << "\nwarning: " << rec.name << " frame " << clock.number << f.where << ": " << defect_text(f.scan)
        << ": every metric measured against it is NaN at that frame\n";
  if (fm) t.prepared = f.prepared ? std::move(*f.prepared) : fm->prepare(f.image, plan.references[r].variants.size() > 1);
  t.frame = std::move(f);
  return t;
}

// How well the motion explains the base sequence's change since the frame before (NaN at its first frame).
metrics::MotionExplained FrameLoop::Impl::check_motion(int k,
                                                       const std::shared_ptr<const metrics::FlickerReference>& base,
                                                       const Image& motion) {
  metrics::MotionExplained me;
  me.given = me.negated = me.flip_y = me.flip_x = kNan;
  if (k > 0 && check_before && check_before_k == k - 1)
    me = metrics::motion_explained(check_before->pq, base->pq, plan.spec->width, plan.spec->height, motion);
  check_before = base;
  check_before_k = k;
  return me;
}

// The record of variant i at frame k: its metrics against its truth (or, without one, its own flicker),
// the truth's noise floor, the motion check and the pixel counts.
FrameRecord FrameLoop::Impl::variant_record(int k, size_t i, const SourceFrame& f, const WorkSchedule& work,
                                            const FrameClock& clock, const std::vector<std::optional<Truth>>& truths,
                                            const MotionFrame& motion, const metrics::MotionExplained& me,
                                            std::shared_ptr<const metrics::FlickerReference> own) {
  const size_t kk = size_t(k);
  const RunPlan::Variant& pv = plan.variants[i];
  FrameRecord rec;
  rec.variant = int(i);
  rec.name = pv.spec->name;
  rec.frame = k;
  rec.time_s = clock.time_s;
  rec.sequence_start = k == 0 || clock.cut;
  rec.spp = sources.variants[i]->samples_per_pixel();
  rec.gpu_ms = f.gpu_ms;
  rec.passes = f.passes;
  rec.wall_ms = f.wall_ms;
  rec.image = f.image.get();
  rec.scan = f.scan;
  const bool bad_before = !(k == 0 || clock.cut) && variant_bad[i] == k - 1;
  if (!f.scan.clean()) variant_bad[i] = k;
  if (!work.measure[i][kk]) return rec;
  // The tracker compares with the previous frame: it restarts at a cut and where the previous frame
  // was not measured.
  if (clock.cut || k == 0 || !work.measure[i][kk - 1]) trackers[i].reset();
  const Truth* truth = pv.reference >= 0 ? &*truths[size_t(pv.reference)] : nullptr;
  if (truth) {
    rec.reference_cached = truth->frame.cached;
    rec.metrics = fm->measure(*f.image, *truth->prepared, motion.motion, trackers[i], &rec.metric_cost_ms);
    rec.floor = truth->floor;
  } else {  // no truth: the variant's own flicker
    const auto t0 = Clock::now();
    std::optional<metrics::FlickerFrame> fl = trackers[i].push(*f.image, std::move(own), motion.motion);
    rec.metrics.emplace_back("flicker_contrast", fl ? fl->flicker_contrast : kNan);
    rec.metrics.emplace_back("flicker_valid_px", fl ? double(fl->valid_px) : kNan);
    rec.metrics.emplace_back("flicker_disoccluded_px", fl ? double(fl->disoccluded_px) : kNan);
    rec.metric_cost_ms.emplace_back("flicker", ms_since(t0));
  }
  if (!f.scan.clean() || (truth && !truth->frame.scan.clean())) void_metrics(rec.metrics);
  else if (bad_before || (truth && truth->bad_before)) void_temporal_metrics(rec.metrics);  // they compare with it
  if (sources.check_motion) {
    rec.metrics.emplace_back("motion_explained", me.given);
    rec.metrics.emplace_back("motion_explained_negated", me.negated);
    rec.metrics.emplace_back("motion_explained_flip_y", me.flip_y);
    rec.metrics.emplace_back("motion_explained_flip_x", me.flip_x);
    rec.metrics.emplace_back("motion_nonfinite_px", double(motion.nonfinite));
  }
  if (truth) {
    const metrics::PixelScan& rs = truth->frame.scan;
    rec.metrics.emplace_back("reference_nonfinite_px", double(rs.nan + rs.infinite));
    rec.metrics.emplace_back("reference_negative_px", double(rs.negative));
  }
  return rec;
}

void FrameLoop::run(const WorkSchedule& work, const std::vector<RecordSink*>& sinks) {
  Impl& m = *impl_;
  int total = 0;
  for (const auto& v : work.render) total += int(std::count(v.begin(), v.end(), 1));
  Progress progress(m.log, m.plan.spec->name, total);
  for (int k = 0; k <= work.last_frame; ++k) {
    const size_t kk = size_t(k);
    const FrameClock clock = m.sources.clock(k);
    const bool own_frame = k >= work.frame_begin && k < work.frame_end;

    // ---- the truths' frames, and the motion (estimated from the base sequence where it is not given:
    // the first truth, else the first variant)
    std::vector<std::optional<SourceFrame>> ref_frames(m.plan.references.size());
    for (size_t r = 0; r < ref_frames.size(); ++r)
      if (work.reference[r][kk]) ref_frames[r] = m.sources.references[r]->frame(k);
    std::optional<SourceFrame> first_variant;
    if (!m.plan.variants.empty() && work.render[0][kk] && ref_frames.empty())
      first_variant = m.sources.variants[0]->frame(k);
    MotionFrame motion;
    if (work.motion[kk]) {
      std::shared_ptr<const Image> base;
      if (m.sources.motion->needs_base())
        base = !ref_frames.empty() && ref_frames[0] ? ref_frames[0]->image : first_variant ? first_variant->image : nullptr;
      motion = m.sources.motion->frame(k, base);
      if (own_frame)
        for (RecordSink* s : sinks) s->motion(k, motion.motion);
      if (own_frame && motion.nonfinite > 0)
        m.log << "\nwarning: motion vectors of frame " << clock.number << " have " << motion.nonfinite
              << " non-finite pixels (left out of the flicker means)\n";
    }

    // ---- the truths: records, noise floors, the metrics' view of them
    std::vector<std::optional<Truth>> truths(ref_frames.size());
    for (size_t r = 0; r < ref_frames.size(); ++r)
      if (ref_frames[r]) truths[r] = m.truth(k, r, std::move(*ref_frames[r]), work, clock, motion, own_frame, sinks);

    // ---- the motion check on the base sequence's own change; without a truth, each variant's own view
    std::shared_ptr<const metrics::FlickerReference> own0;
    if (first_variant && m.fm && work.measure[0][kk]) own0 = std::make_shared<const metrics::FlickerReference>(metrics::flicker_reference(*first_variant->image));
    metrics::MotionExplained me;
    if (m.sources.check_motion && work.motion[kk]) {
      const auto base = !truths.empty() && truths[0] ? truths[0]->prepared->flicker : own0;
      if (base) me = m.check_motion(k, base, motion.motion);
    }

    // ---- every variant that has work at frame k
    for (size_t i = 0; i < m.plan.variants.size(); ++i) {
      if (!work.render[i][kk]) continue;
      const RunPlan::Variant& pv = m.plan.variants[i];
      const SourceFrame f = i == 0 && first_variant ? std::move(*first_variant) : m.sources.variants[i]->frame(k);
      std::shared_ptr<const metrics::FlickerReference> own;
      if (pv.reference < 0 && m.fm && work.measure[i][kk])
        own = i == 0 && own0 ? own0 : std::make_shared<const metrics::FlickerReference>(metrics::flicker_reference(*f.image));
      const FrameRecord rec = m.variant_record(k, i, f, work, clock, truths, motion, me, std::move(own));
      if (work.emit[i][kk]) {
        if (!rec.scan.clean())
          m.log << "\nwarning: " << pv.spec->name << " frame " << clock.number << ": " << defect_text(rec.scan) << "\n";
        for (RecordSink* s : sinks) s->frame(rec);
      }
      std::ostringstream detail;
      detail << pv.spec->name << " frame " << clock.number << (work.emit[i][kk] ? "" : " (replay)") << ", "
             << std::fixed << std::setprecision(1) << rec.wall_ms << " ms";
      progress.step(detail.str());
    }
  }
}

}  // namespace glintlab

#include "experiments/runner/frame_loop.h"
#include "core/util/strings.h"

#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "experiments/runner/progress.h"
#include "metrics/frame_metrics.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <chrono>
#include <iomanip>
#include <sstream>

namespace glintlab {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

struct FrameLoop::Impl {
  const core::VkContext& ctx;
  const RunPlan& plan;
  const SceneData& data;
  const ReferenceCache& cache;
  const metrics::ColorManager& cm;
  std::ostream& log;
  std::vector<RenderSetup> variants, references;
  RenderSetup motion;
  std::unique_ptr<metrics::FrameMetrics> frame_metrics;  // null when the run does not measure
  std::vector<metrics::FlickerTracker> trackers;
  std::vector<metrics::FlickerTracker> half_trackers;  // per reference: its half B along the motion against half A

  Impl(const core::VkContext& c, const core::SceneGpu& scene, const RunPlan& p, const SceneData& d,
       const metrics::ColorManager& cm, const ReferenceCache& rc, std::ostream& l)
      : ctx(c), plan(p), data(d), cache(rc), cm(cm), log(l) {
    const ExperimentSpec& spec = *plan.spec;
    for (const auto& v : plan.variants)  // a frame source is read, not rendered: no graph
      variants.push_back(v.files ? RenderSetup{}
                                 : build_variant(ctx, scene, spec.width, spec.height, *v.spec, v.program));
    if (plan.measure || spec.output.motion) motion = build_motion(ctx, scene, spec.width, spec.height);
    if (plan.measure) {
      for (const auto& r : plan.references)
        references.push_back(r.files ? RenderSetup{}
                                     : build_reference(ctx, scene, spec.width, spec.height, r.program,
                                                       spec.reference.grid));
      frame_metrics = std::make_unique<metrics::FrameMetrics>(cm, spec.working_space, spec.metrics, spec.metric_options);
      trackers.resize(plan.variants.size());
      half_trackers.resize(plan.references.size());
    }
  }
};

FrameLoop::FrameLoop(const core::VkContext& ctx, const core::SceneGpu& scene, const RunPlan& plan,
                     const SceneData& data, const metrics::ColorManager& cm, const ReferenceCache& cache,
                     std::ostream& log)
    : impl_(std::make_unique<Impl>(ctx, scene, plan, data, cm, cache, log)) {}

FrameLoop::~FrameLoop() = default;

std::vector<std::string> FrameLoop::pass_names() const {
  std::vector<std::string> out;
  for (const auto& v : impl_->variants)
    for (const auto& n : v.graph ? v.graph->pass_names() : std::vector<std::string>{})
      if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
  return out;
}

std::vector<std::string> FrameLoop::metric_names() const {
  return impl_->frame_metrics ? impl_->frame_metrics->names() : std::vector<std::string>{};
}

void FrameLoop::run(const WorkSchedule& work, const std::vector<RecordSink*>& sinks) {
  Impl& m = *impl_;
  const ExperimentSpec& spec = *m.plan.spec;
  const int w = spec.width, h = spec.height;
  int total = 0;
  for (const auto& v : work.render) total += int(std::count(v.begin(), v.end(), 1));
  Progress progress(m.log, spec.name, total);
  for (int k = 0; k <= work.last_frame; ++k) {
    const size_t kk = size_t(k);
    const core::FrameCamera cam = spec.path.frame(k, w, h);
    core::FrameInputs in;
    in.frame = k;
    in.uniforms = frame_uniforms(spec, m.data, k);
    in.camera_cut = cam.cut;
    const bool own_frame = k >= work.frame_begin && k < work.frame_end;

    // ---- motion vectors and references of frame k (shared by every variant)
    Image motion;
    std::vector<metrics::FrameMetrics::Reference> prepared(m.references.size());
    std::vector<bool> ref_cached(m.references.size(), false);
    std::vector<metrics::PixelScan> ref_scan(m.references.size());  // references are scanned too
    std::vector<metrics::NamedValues> ref_floor(m.references.size());
    if (work.motion[kk]) {
      in.samples = core::samples_for(spec.path, k, w, h, {glm::vec2(0.0f)});
      motion = std::move(m.motion.graph->execute(in).images.at(m.motion.output));
      if (own_frame)
        for (RecordSink* s : sinks) s->motion(k, motion);
    }
    for (size_t r = 0; r < m.references.size(); ++r) {
      if (!work.reference[r][kk]) continue;
      ReferenceRecord rec;
      rec.reference = int(r);
      rec.name = m.plan.references[r].name;
      rec.frame = k;
      std::optional<Image> img;
      if (const auto& files = m.plan.references[r].files) {  // read, not rendered
        ColourFrame cf = read_colour_frame(*files, kk, m.cm, spec.working_space);
        ref_scan[r] = cf.scan;
        rec.wall_ms = cf.read_ms;
        rec.gpu_ms = std::nan("");
        img = std::move(cf.image);
        rec.image = &*img;
        if (own_frame)
          for (RecordSink* s : sinks) s->reference(rec);
        prepared[r] = m.frame_metrics->prepare(*img, m.plan.references[r].variants.size() > 1);
        continue;
      }
      const std::string key = m.plan.reference_key(int(r), in.uniforms);
      const RenderSetup& setup = m.references[r];
      // The truth and, where it has them, its two halves: cached as three entries, rendered again
      // unless all three load.
      const std::string half_keys[2] = {key + "-half-a", key + "-half-b"};
      std::optional<Image> halves[2];
      bool corrupt = false;
      img = m.cache.load(key, &corrupt);
      for (int hh = 0; setup.halves && img && hh < 2; ++hh) {
        halves[hh] = m.cache.load(half_keys[hh], &corrupt);
        if (!halves[hh]) img.reset();
      }
      if (corrupt) {
        m.log << "warning: corrupt reference cache entry " << m.cache.path_of(key) << " removed; re-rendering\n";
        rec.rebuilt = true;
      }
      if (img) {
        rec.cached = true;
      } else {
        in.samples = core::samples_for(spec.path, k, w, h, supersampling(spec.reference.grid, w, h, kReferencePatternSeed).offsets);
        auto t0 = Clock::now();
        core::FrameResult fr = setup.graph->execute(in);
        rec.wall_ms = ms_since(t0);
        rec.gpu_ms = fr.gpu_ms;
        img = std::move(fr.images.at(setup.output));
        m.cache.store(key, *img);
        for (int hh = 0; setup.halves && hh < 2; ++hh) {
          halves[hh] = std::move(fr.images.at(core::SurfacePassOptions().half_targets[hh]));
          m.cache.store(half_keys[hh], *halves[hh]);
        }
      }
      // The noise floor: every metric of half B against half A, along the same motion.
      if (setup.halves) {
        if (k == 0 || cam.cut || !work.reference[r][kk - 1]) m.half_trackers[r].reset();
        rec.halves_metrics = m.frame_metrics->measure(*halves[1], m.frame_metrics->prepare(*halves[0], false), motion,
                                                m.half_trackers[r]);
        ref_floor[r] = metrics::noise_floor(rec.halves_metrics);
        rec.half_a = &*halves[0];
        rec.half_b = &*halves[1];
      }
      rec.image = &*img;
      ref_cached[r] = rec.cached;
      ref_scan[r] = metrics::scan_pixels(*img, 3);
      if (own_frame)
        for (RecordSink* s : sinks) s->reference(rec);
      prepared[r] = m.frame_metrics->prepare(*img, m.plan.references[r].variants.size() > 1);
    }
    for (size_t r = 0; r < m.references.size(); ++r)
      if (work.reference[r][kk] && own_frame && !ref_scan[r].clean())
        m.log << "\nwarning: " << m.plan.references[r].name << " frame " << k << ": " << ref_scan[r].nan << " NaN, "
              << ref_scan[r].infinite << " Inf, " << ref_scan[r].negative
              << " negative pixels: every metric of the variants measured against it is NaN at that frame\n";

    // ---- every variant that has work at frame k
    for (size_t i = 0; i < m.plan.variants.size(); ++i) {
      if (!work.render[i][kk]) continue;
      const RunPlan::Variant& pv = m.plan.variants[i];
      const std::vector<glm::vec2> offsets = variant_offsets(*pv.spec, k);
      in.samples = core::samples_for(spec.path, k, w, h, offsets);
      in.jitter_px = offsets.size() == 1 ? offsets[0] : glm::vec2(0.0f);
      auto t0 = Clock::now();
      core::FrameResult fr;
      std::optional<ColourFrame> read;
      if (pv.files) {  // a frame source: its k-th frame, in the working space
        read = read_colour_frame(*pv.files, kk, m.cm, spec.working_space);
        fr.gpu_ms = std::nan("");
      } else {
        fr = m.variants[i].graph->execute(in);
      }
      FrameRecord rec;
      rec.wall_ms = ms_since(t0);
      rec.variant = int(i);
      rec.name = pv.spec->name;
      rec.frame = k;
      rec.time_s = cam.time;
      rec.sequence_start = k == 0 || cam.cut;
      rec.spp = pv.files ? 0 : pv.spec->samples_per_pixel();
      rec.gpu_ms = fr.gpu_ms;
      rec.passes = fr.timings;
      const Image& img = read ? read->image : fr.images.at(m.variants[i].output);
      rec.image = &img;
      rec.scan = read ? read->scan : metrics::scan_pixels(img, 3);
      if (work.measure[i][kk]) {
        // The tracker compares with the previous frame: it restarts at a cut
        // and where the previous frame was not measured.
        if (cam.cut || k == 0 || !work.measure[i][kk - 1]) m.trackers[i].reset();
        rec.reference_cached = ref_cached[size_t(pv.reference)];
        rec.metrics = m.frame_metrics->measure(img, prepared[size_t(pv.reference)], motion, m.trackers[i],
                                         &rec.metric_cost_ms);
        // A truth with NaN, Inf or negative pixels measures nothing: counted, and every metric NaN.
        const metrics::PixelScan& rs = ref_scan[size_t(pv.reference)];
        if (!rs.clean()) {
          defects_ = true;
          for (auto& [name, value] : rec.metrics)
            if (name.size() < 3 || name.compare(name.size() - 3, 3, "_px") != 0) value = std::nan("");
        }
        rec.metrics.emplace_back("reference_nonfinite_px", double(rs.nan + rs.infinite));
        rec.metrics.emplace_back("reference_negative_px", double(rs.negative));
        rec.floor = ref_floor[size_t(pv.reference)];
      }
      if (work.emit[i][kk]) {
        if (!rec.scan.clean()) {
          defects_ = true;
          m.log << "\nwarning: " << pv.spec->name << " frame " << k << ": " << rec.scan.nan << " NaN, "
                << rec.scan.infinite << " Inf, " << rec.scan.negative << " negative pixels\n";
        }
        for (RecordSink* s : sinks) s->frame(rec);
      }
      std::ostringstream detail;
      detail << pv.spec->name << " frame " << k << (work.emit[i][kk] ? "" : " (replay)") << ", " << std::fixed
             << std::setprecision(1) << rec.wall_ms << " ms";
      progress.step(detail.str());
    }
  }
}

}  // namespace glintlab

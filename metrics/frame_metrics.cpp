#include "metrics/frame_metrics.h"
#include "core/util/strings.h"

#include "metrics/color/measurement_space.h"
#include "metrics/glint_stats.h"
#include "metrics/metric_registry.h"
#include "metrics/pixel_scan.h"
#include "metrics/pooled_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace glintlab::metrics {

NamedValues noise_floor(const NamedValues& halves) {
  NamedValues floor;
  for (const auto& [name, v] : halves)
    if (has_noise_floor(name)) floor.emplace_back(name, 0.5 * v);
  return floor;
}

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

FrameMetrics::FrameMetrics(const ColorManager& cm, std::string working_space, std::vector<std::string> per_pixel,
                           MetricOptions options)
    : cm_(cm), space_(std::move(working_space)), per_pixel_(std::move(per_pixel)), options_(std::move(options)) {}

const Image& FrameMetrics::xyz_of(const Image& img, Image& storage) const {
  if (space_ == kXyzD65Space) return img;
  storage = cm_.to_xyz_d65(img, space_);
  return storage;
}

const Image* FrameMetrics::temporal_display(const Image& linear, const Image& metric, Image& storage) const {
  if (options_.temporal_view.empty()) return nullptr;
  if (options_.temporal_view == options_.display_view) return &metric;  // already displayed through it
  auto [display, view] = parse_display_view(options_.temporal_view);
  storage = cm_.display_referred_xyz(linear, space_, display, view);
  return &storage;
}

FrameMetrics::Reference FrameMetrics::prepare(const Image& ref_linear, bool shared) const {
  return prepare(std::make_shared<const Image>(ref_linear), shared);
}

FrameMetrics::Reference FrameMetrics::prepare(std::shared_ptr<const Image> ref_linear, bool shared) const {
  Reference r;
  r.xyz = space_ == kXyzD65Space ? ref_linear : std::make_shared<const Image>(cm_.to_xyz_d65(*ref_linear, space_));
  r.metric_xyz = options_.display_view.empty()
                     ? r.xyz
                     : std::make_shared<const Image>(metric_xyz(cm_, *ref_linear, space_, options_));
  {
    Image displayed;
    const Image* shown = temporal_display(*ref_linear, *r.metric_xyz, displayed);
    r.flicker = std::make_shared<const FlickerReference>(flicker_reference(*r.xyz, shown));
  }
  // The reference side of the per-pixel metrics that have one, converted once for every variant.
  auto measured = [&](const char* m) { return std::find(per_pixel_.begin(), per_pixel_.end(), m) != per_pixel_.end(); };
  if (options_.flip_hdr && measured("flip")) r.flip.emplace(*r.metric_xyz, options_.flip_ppd);
  if (measured("deltaE2000") && shared) r.lab = lab_image(*r.metric_xyz);
  if (measured("deltaEITP")) r.ictcp = ictcp_image(*r.metric_xyz, options_.itp_luminance_nits);
  return r;
}

std::vector<std::string> FrameMetrics::names() const {
  std::vector<std::string> n;
  for (const auto& m : per_pixel_) {
    n.push_back(m);
    n.push_back(m + "_max");
  }
  for (const FrameStatistic& s : frame_statistics())
    if (std::string(s.group) == "flicker" || (options_.glints && std::string(s.group) == "glints"))
      n.emplace_back(s.name);
  if (options_.pooled) {
    for (int b : default_pool_block_sizes()) {
      n.push_back("pooled_bias_" + std::to_string(b));
      n.push_back("pooled_rms_" + std::to_string(b));
    }
    n.emplace_back("pooled_error");
  }
  return n;
}

NamedValues FrameMetrics::measure(const Image& test_linear, const Reference& ref, const Image& motion,
                                  FlickerTracker& flicker, NamedValues* cost_ms) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  NamedValues v;
  auto timed = [&](const std::string& name, auto&& fn) {
    auto t0 = Clock::now();
    fn();
    if (cost_ms) cost_ms->emplace_back(name, ms_since(t0));
  };
  Image xyz_storage, metric_storage;
  const Image* xyz = nullptr;
  const Image* metric = nullptr;
  timed("convert", [&] {
    xyz = &xyz_of(test_linear, xyz_storage);
    metric = xyz;
    if (!options_.display_view.empty()) metric = &(metric_storage = metric_xyz(cm_, test_linear, space_, options_));
  });
  const Image& test_xyz = *xyz;
  const Image& test_metric = *metric;
  const bool defect = !scan_pixels(test_linear, 3).clean();

  for (const auto& name : per_pixel_)
    timed(name, [&] {
      double mean = nan, max = nan;
      if (name == "flip" && ref.flip) {  // the reference side is shared
        map_mean_max(ref.flip->map(test_metric), &mean, &max);
      } else if (name == "deltaE2000" && ref.lab) {
        map_mean_max(ciede2000_map(test_metric, *ref.lab), &mean, &max);
      } else if (name == "deltaEITP" && ref.ictcp) {
        map_mean_max(delta_e_itp_map(test_metric, *ref.ictcp), &mean, &max);
      } else {
        MetricResult r = evaluate_metric(name, test_metric, *ref.metric_xyz, options_);
        mean = r.mean;
        max = r.max;
      }
      v.emplace_back(name, defect ? nan : mean);
      v.emplace_back(name + "_max", defect ? nan : max);
    });
  Image displayed;
  const Image* shown = nullptr;
  timed("display", [&] { shown = temporal_display(test_linear, test_metric, displayed); });  // temporal_score's
  timed("flicker", [&] {
    std::optional<FlickerFrame> f = flicker.push(test_xyz, ref.flicker, motion, shown);
    auto put = [&](const char* n, double x) { v.emplace_back(n, f && !defect ? x : nan); };
    put("flicker_ratio", f ? f->flicker_ratio : nan);
    put("temporal_error", f ? f->temporal_error : nan);
    put("temporal_error_mc", f ? f->temporal_error_mc : nan);
    put("frame_diff_ratio", f ? f->frame_diff_ratio : nan);
    put("flicker_contrast", f ? f->flicker_contrast : nan);
    put("flicker_excess", f ? f->flicker_excess : nan);
    put("temporal_lag", f ? f->temporal_lag : nan);
    put("flicker_excess_fixed", f ? f->flicker_excess_fixed : nan);
    put("temporal_score", f ? f->temporal_score : nan);
    v.emplace_back("flicker_valid_px", f ? double(f->valid_px) : nan);
    v.emplace_back("flicker_disoccluded_px", f ? double(f->disoccluded_px) : nan);
  });
  if (options_.glints) timed("glints", [&] {
    GlintComparison gc = compare_glints(test_xyz, *ref.xyz);
    v.emplace_back("glint_density_test", defect ? nan : gc.test.density_per_1000px);
    v.emplace_back("glint_density_ref", gc.ref.density_per_1000px);
    v.emplace_back("glint_hist_emd_oct", defect ? nan : gc.emd_octaves);
  });
  if (options_.pooled) timed("pooled", [&] {
    std::vector<PooledErrorScale> pooled = pooled_error(test_xyz, *ref.xyz, 1);
    double pooled8 = nan;
    for (int b : default_pool_block_sizes()) {
      double bias = nan, rms = nan;
      for (const auto& p : pooled)
        if (p.block_size == b && !defect) bias = p.bias, rms = p.rms;
      v.emplace_back("pooled_bias_" + std::to_string(b), bias);
      v.emplace_back("pooled_rms_" + std::to_string(b), rms);
      if (b == kPooledErrorBlock) pooled8 = rms;
    }
    v.emplace_back("pooled_error", pooled8);
  });
  return v;
}

}  // namespace glintlab::metrics

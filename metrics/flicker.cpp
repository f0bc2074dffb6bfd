#include "metrics/flicker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "metrics/delta_e_itp.h"
#include "metrics/error_metrics.h"
#include "metrics/parallel.h"
#include "metrics/simd_clones.h"

namespace glintlab::metrics {

GLINTLAB_AVX2_CLONES void perceptual_luminance_n(const double* Y, double* out, std::size_t n, double reference_nits) {
  NoFillVector<double> nits(n);  // every value written next
  for (std::size_t i = 0; i < n; ++i) nits[i] = std::isnan(Y[i]) ? 0.0 : std::max(Y[i], 0.0) * reference_nits;
  pq_inverse_eotf_n(nits.data(), nits.data(), n);
  for (std::size_t i = 0; i < n; ++i) out[i] = std::isnan(Y[i]) ? Y[i] : nits[i];
}

double perceptual_luminance(double Y, double reference_nits) {
  double pq;
  perceptual_luminance_n(&Y, &pq, 1, reference_nits);
  return pq;
}

namespace {
// Y (channel 1) of an XYZ image and its perceptual_luminance, in rows of work spread over the threads.
void luminance_planes(const Image& xyz, NoFillVector<float>& y, NoFillVector<double>& pq) {
  const std::size_t w = std::size_t(xyz.width), n = xyz.pixel_count();
  y.resize(n);
  pq.resize(n);
  parallel_for(xyz.height, [&](long row) {
    const std::size_t o = std::size_t(row) * w;
    for (std::size_t i = o; i < o + w; ++i) pq[i] = y[i] = xyz.data[i * std::size_t(xyz.channels) + 1];
    perceptual_luminance_n(pq.data() + o, pq.data() + o, w);
  });
}
}  // namespace

double flicker_ratio(double mean_test, double mean_ref) {
  if (std::isnan(mean_test) || std::isnan(mean_ref)) return std::numeric_limits<double>::quiet_NaN();
  if (mean_ref == 0.0) return mean_test == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
  return mean_test / mean_ref;
}

namespace {
// acc[x] += k src[x] for x < n: one tap of a separable filter over a row.
GLINTLAB_AVX2_CLONES void add_scaled(double* __restrict acc, const double* __restrict src, double k, int n) {
  for (int x = 0; x < n; ++x) acc[x] += k * src[x];
}
GLINTLAB_AVX2_CLONES void add_scaled(double* __restrict acc, const float* __restrict src, double k, int n) {
  for (int x = 0; x < n; ++x) acc[x] += k * double(src[x]);
}
}  // namespace

NoFillVector<float> adaptation_luminance(const Image& xyz, double sigma_px) {
  const int w = xyz.width, h = xyz.height;
  const int r = std::max(1, int(std::ceil(3.0 * sigma_px)));
  std::vector<double> k(size_t(2 * r + 1));
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) sum += k[size_t(i + r)] = std::exp(-0.5 * double(i * i) / (sigma_px * sigma_px));
  for (double& x : k) x /= sum;
  // Both passes as sums of whole rows, tap after tap (s += k_i v_{x+i} for i = -r .. r, as a loop over
  // taps per pixel would add them, so the result is the same to the bit): the inner loops run over
  // contiguous x and vectorise. Edges clamped: the horizontal pass reads a copy of the row padded with
  // its end values, the vertical one the clamped rows.
  NoFillVector<float> tmp(size_t(w) * h), out(size_t(w) * h);  // every value written below
  parallel_for(h, [&](long y) {
    NoFillVector<double> row(size_t(w + 2 * r));  // every value written next
    std::vector<double> acc(size_t(w), 0.0);
    for (int x = -r; x < w + r; ++x) row[size_t(x + r)] = xyz.at(std::clamp(x, 0, w - 1), int(y), 1);
    for (int i = -r; i <= r; ++i) add_scaled(acc.data(), row.data() + (r + i), k[size_t(i + r)], w);
    for (int x = 0; x < w; ++x) tmp[size_t(y) * w + x] = float(acc[size_t(x)]);
  });
  parallel_for(h, [&](long y) {
    std::vector<double> acc(size_t(w), 0.0);
    for (int i = -r; i <= r; ++i)
      add_scaled(acc.data(), tmp.data() + size_t(std::clamp(int(y) + i, 0, h - 1)) * w, k[size_t(i + r)], w);
    for (int x = 0; x < w; ++x) out[size_t(y) * w + x] = float(acc[size_t(x)]);
  });
  return out;
}

namespace {
// reproject's work for row y, into out[0 .. width).
GLINTLAB_AVX2_CLONES void reproject_row(const Image& motion, const float* prev_distance,
                                        double tolerance, int y, Reprojected* out) {
  const int w = motion.width, h = motion.height;
  for (int x = 0; x < w; ++x) {
    Reprojected& r = out[x];
    r = Reprojected{};
    const float* m = motion.px(x, y);
    if (!(m[2] > 0.0f)) {
      r.state = Reprojected::kBackground;
      continue;
    }
    // The centre of pixel p sat at (x + 0.5, y + 0.5) - v in frame t-1; in texel-index
    // coordinates (texel centres at integers) that is (x, y) - v.
    const double qx = x - double(m[0]), qy = y - double(m[1]);
    const double d_prev = m[3];
    bool ok = d_prev > 0.0 && std::isfinite(qx) && std::isfinite(qy) && qx >= 0.0 && qy >= 0.0 &&
              qx <= double(w - 1) && qy <= double(h - 1);
    if (ok) {
      const int x0 = std::min(int(qx), w - 1), y0 = std::min(int(qy), h - 1);
      const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
      const double fx = qx - x0, fy = qy - y0;
      const int tx[4] = {x0, x1, x0, x1}, ty[4] = {y0, y0, y1, y1};
      const double tw[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
      double d_interp = 0.0;
      for (int k = 0; k < 4; ++k) {
        r.idx[k] = unsigned(ty[k]) * unsigned(w) + unsigned(tx[k]);
        r.weight[k] = float(tw[k]);
        // A tap that saw no surface, or a surface far off the point's distance
        // (another object across a silhouette), contaminates the sample.
        if (tw[k] > 0.0 && !(std::abs(prev_distance[r.idx[k]] - d_prev) <= kSilhouetteTolerance * d_prev)) ok = false;
        d_interp += tw[k] * prev_distance[r.idx[k]];
      }
      // On a smooth surface the interpolated distance is the point's; across a
      // silhouette it mixes the two surfaces and misses it.
      ok = ok && std::abs(d_interp - d_prev) <= tolerance * d_prev;
    }
    r.state = ok ? Reprojected::kValid : Reprojected::kDisoccluded;
  }
}
}  // namespace

std::vector<Reprojected> reproject(const Image& motion, const std::vector<float>& prev_distance, double tolerance) {
  if (prev_distance.size() != motion.pixel_count())
    throw std::invalid_argument("reproject: the previous distances and the motion image differ in size");
  std::vector<Reprojected> out(motion.pixel_count());
  parallel_for(motion.height, [&](long y) {
    reproject_row(motion, prev_distance.data(), tolerance, int(y), out.data() + std::size_t(y) * motion.width);
  });
  return out;
}

FlickerReference flicker_reference(const Image& ref_xyz) {
  FlickerReference r;
  r.width = ref_xyz.width;
  r.height = ref_xyz.height;
  luminance_planes(ref_xyz, r.y, r.pq);
  r.adaptation = adaptation_luminance(ref_xyz);
  return r;
}

std::optional<FlickerFrame> FlickerTracker::push(const Image& test_xyz, std::shared_ptr<const FlickerReference> shared,
                                                 const Image& motion) {
  if (!shared) throw std::invalid_argument("FlickerTracker::push: no reference");
  const FlickerReference& ref = *shared;
  if (test_xyz.width != ref.width || test_xyz.height != ref.height)
    throw std::invalid_argument("FlickerTracker::push: test is " + std::to_string(test_xyz.width) + "x" +
                                std::to_string(test_xyz.height) + " but the reference " + std::to_string(ref.width) +
                                "x" + std::to_string(ref.height));
  require_same_size(test_xyz, motion, "FlickerTracker::push (motion)");
  if (motion.channels < 4)
    throw std::invalid_argument("FlickerTracker::push: the motion image needs 4 channels (v.xy, distance now, "
                                "distance in the previous frame), got " + std::to_string(motion.channels));
  if (pushed_ > 0 && (test_xyz.width != width_ || test_xyz.height != height_))
    throw std::invalid_argument("FlickerTracker::push: frame " + std::to_string(pushed_) + " is " +
                                std::to_string(test_xyz.width) + "x" + std::to_string(test_xyz.height) +
                                " but the sequence is " + std::to_string(width_) + "x" + std::to_string(height_));
  const int w = test_xyz.width, h = test_xyz.height;
  const std::size_t n = test_xyz.pixel_count();
  NoFillVector<float> yt, dist(n);
  NoFillVector<double> pqt;
  luminance_planes(test_xyz, yt, pqt);
  for (std::size_t i = 0; i < n; ++i) dist[i] = motion.data[i * motion.channels + 2];
  std::optional<FlickerFrame> result;
  NoFillVector<float> own_adaptation = adaptation_luminance(test_xyz);
  if (pushed_ > 0) {
    const FlickerReference& prev_ref = *prev_ref_;
    // Sums per row in parallel, then over rows in order: the same result for any thread count.
    struct Row {
      double ct = 0, cr = 0, cs = 0, emc = 0, e = 0, dt = 0, dr = 0, excess = 0, lag = 0, excess_fixed = 0;
      std::size_t valid = 0, disoccluded = 0, background = 0;
    };
    std::vector<Row> rows(static_cast<size_t>(h));
    parallel_for(h, [&](long y) {
      Row& row = rows[size_t(y)];
      // Where the row's pixels were in frame t-1 (reproject's, a row at a time, into the thread's own
      // row buffer: reproject_row writes every entry).
      static thread_local std::vector<Reprojected> warp;
      warp.resize(static_cast<std::size_t>(w));
      reproject_row(motion, prev_dist_.data(), kDisocclusionTolerance, int(y), warp.data());
      // The previous frames resampled along the motion at the row's valid pixels, and their PQ in one call.
      NoFillVector<double> prev(2 * std::size_t(w)), prev_pq(2 * std::size_t(w));  // the first 2 valid written
      std::size_t valid = 0;
      for (int x = 0; x < w; ++x) {
        const Reprojected& rp = warp[std::size_t(x)];
        if (rp.state != Reprojected::kValid) continue;
        prev[2 * valid] = rp.sample(prev_yt_);
        prev[2 * valid + 1] = rp.sample(prev_ref.y);
        ++valid;
      }
      perceptual_luminance_n(prev.data(), prev_pq.data(), 2 * valid);
      // The row's sums in locals (kept in registers: a Row in memory may alias the planes), each in
      // x order; the five terms over the reference's adaptation luminance share one reciprocal.
      double e = 0, dt = 0, dr = 0, excess_fixed = 0, ct = 0, cr = 0, cs = 0, excess = 0, lag = 0, emc = 0;
      std::size_t n_valid = 0, n_disoccluded = 0, n_background = 0;
      std::size_t k = 0;  // the next valid pixel's entry
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        // Fixed-pixel terms over every pixel.
        const double dT = pqt[i] - prev_pqt_[i], dR = ref.pq[i] - prev_ref.pq[i];
        e += std::abs(dT - dR);
        dt += std::abs(dT);
        dr += std::abs(dR);
        const double inv_denom = 1.0 / (double(ref.adaptation[i]) + kContrastEpsilon);
        {  // fixed gaze, at the eye's resolution
          const double fT = std::abs(double(own_adaptation[i]) - prev_ya_test_[i]);
          const double fR = std::abs(double(ref.adaptation[i]) - prev_ref.adaptation[i]);
          excess_fixed += std::max(0.0, fT - fR) * inv_denom;
        }
        // Along the motion.
        const Reprojected& rp = warp[std::size_t(x)];
        if (rp.state == Reprojected::kBackground) {
          ++n_background;
          continue;
        }
        if (rp.state == Reprojected::kDisoccluded) {
          ++n_disoccluded;
          continue;
        }
        const double t_prev = prev[2 * k], r_prev = prev[2 * k + 1];
        const double pq_t_prev = prev_pq[2 * k], pq_r_prev = prev_pq[2 * k + 1];
        ++k;
        ++n_valid;
        ct += std::abs(double(yt[i]) - t_prev) * inv_denom;
        cr += std::abs(double(ref.y[i]) - r_prev) * inv_denom;
        cs += std::abs(double(yt[i]) - t_prev) / (double(own_adaptation[i]) + kContrastEpsilon);
        // One-sided, both frames low-passed at the eye's resolution before the difference.
        const double lT = std::abs(double(own_adaptation[i]) - rp.sample(prev_ya_test_));
        const double lR = std::abs(double(ref.adaptation[i]) - rp.sample(prev_ref.adaptation));
        excess += std::max(0.0, lT - lR) * inv_denom;
        lag += std::max(0.0, lR - lT) * inv_denom;
        emc += std::abs((pqt[i] - ref.pq[i]) - (pq_t_prev - pq_r_prev));
      }
      row.e = e, row.dt = dt, row.dr = dr, row.excess_fixed = excess_fixed;
      row.ct = ct, row.cr = cr, row.cs = cs, row.excess = excess, row.lag = lag, row.emc = emc;
      row.valid = n_valid, row.disoccluded = n_disoccluded, row.background = n_background;
    });
    FlickerFrame f;
    double s_ct = 0, s_cr = 0, s_cs = 0, s_emc = 0, s_e = 0, s_dt = 0, s_dr = 0, s_x = 0, s_l = 0, s_xf = 0;
    for (const Row& r : rows) {
      s_x += r.excess, s_l += r.lag, s_xf += r.excess_fixed;
      s_ct += r.ct, s_cr += r.cr, s_cs += r.cs, s_emc += r.emc, s_e += r.e, s_dt += r.dt, s_dr += r.dr;
      f.valid_px += r.valid, f.disoccluded_px += r.disoccluded, f.background_px += r.background;
    }
    const double inv_n = n ? 1.0 / double(n) : 0.0;
    const double inv_v = f.valid_px ? 1.0 / double(f.valid_px) : std::numeric_limits<double>::quiet_NaN();
    f.temporal_error = s_e * inv_n;
    f.frame_diff_ratio = flicker_ratio(s_dt * inv_n, s_dr * inv_n);
    f.mean_contrast_test = s_ct * inv_v;
    f.mean_contrast_ref = s_cr * inv_v;
    f.flicker_contrast = s_cs * inv_v;
    f.flicker_excess = s_x * inv_v;
    f.temporal_lag = s_l * inv_v;
    f.flicker_excess_fixed = s_xf * inv_n;
    f.temporal_error_mc = s_emc * inv_v;
    f.flicker_ratio = flicker_ratio(f.mean_contrast_test, f.mean_contrast_ref);
    frames_.push_back(f);
    result = f;
  }
  width_ = w;
  height_ = h;
  prev_yt_ = std::move(yt);
  prev_pqt_ = std::move(pqt);
  prev_dist_ = std::move(dist);
  prev_ya_test_ = std::move(own_adaptation);
  prev_ref_ = std::move(shared);
  ++pushed_;
  return result;
}

void FlickerTracker::reset() {
  pushed_ = 0;
  width_ = height_ = 0;
  prev_yt_.clear();
  prev_pqt_.clear();
  prev_ref_.reset();
  prev_dist_.clear();
  prev_ya_test_.clear();
}

}  // namespace glintlab::metrics

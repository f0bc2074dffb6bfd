#include "metrics/flicker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "metrics/ciede2000.h"
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
// CIE 1976 lightness L* = 116 f(Y) − 16 (CIE 15:2004 eq. 8.1, lab_f of ciede2000.h: linear below
// (6/29)^3, so no cube root of a negative) of a display-referred XYZ image, white Y = 1.
NoFillVector<float> lightness_plane(const Image& xyz) {
  NoFillVector<float> l(xyz.pixel_count());
  for (std::size_t i = 0; i < l.size(); ++i)
    l[i] = float(116.0 * lab_f(double(xyz.data[i * std::size_t(xyz.channels) + 1])) - 16.0);
  return l;
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
// One row of the reprojection as structure of arrays, so that the loops over it run on the vector
// units: each pixel's state and its four bilinear taps into frame t-1 (indices and weights).
struct RowWarp {
  NoFillVector<int> state;
  NoFillVector<int> idx[4];
  NoFillVector<float> weight[4];
  void resize(std::size_t w) {
    state.resize(w);
    for (int k = 0; k < 4; ++k) idx[k].resize(w), weight[k].resize(w);
  }
};

// The reprojection of row y into `out` (every entry written). Branch-free, so that it vectorises:
// every pixel computes its taps, a masked one at a clamped in-range position (no conversion of an
// out-of-range value to int), and the tests are combined into its state.
// (The loop over plain restricted pointers: GCC 12 vectorises it so, not through the Image and RowWarp.)
GLINTLAB_AVX2_CLONES void reproject_pixels(const float* __restrict m, int w, int h, int y,
                                           const float* __restrict prev_distance, double tolerance,
                                           int* __restrict state, int* __restrict i0, int* __restrict i1,
                                           int* __restrict i2, int* __restrict i3, float* __restrict w0,
                                           float* __restrict w1, float* __restrict w2, float* __restrict w3) {
  // (Conditions as 0/1 ints and the state as arithmetic on them: GCC 12 vectorises that, not bools.)
  static_assert(Reprojected::kValid == 0 && Reprojected::kBackground == 1 && Reprojected::kDisoccluded == 2, "");
  for (int x = 0; x < w; ++x) {
    const float* px = m + 4 * x;
    // The centre of pixel p sat at (x + 0.5, y + 0.5) - v in frame t-1; in texel-index
    // coordinates (texel centres at integers) that is (x, y) - v. (NaN fails every comparison.)
    const double qx = x - double(px[0]), qy = y - double(px[1]);
    const double d_prev = px[3];
    const int inside = (d_prev > 0.0) & (qx >= 0.0) & (qy >= 0.0) & (qx <= double(w - 1)) & (qy <= double(h - 1));
    const double cx = inside ? qx : 0.0, cy = inside ? qy : 0.0;
    const int x0 = std::min(int(cx), w - 1), y0 = std::min(int(cy), h - 1);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = cx - x0, fy = cy - y0;
    const double t0 = (1 - fx) * (1 - fy), t1 = fx * (1 - fy), t2 = (1 - fx) * fy, t3 = fx * fy;
    const int j0 = y0 * w + x0, j1 = y0 * w + x1, j2 = y1 * w + x0, j3 = y1 * w + x1;
    const double p0 = prev_distance[j0], p1 = prev_distance[j1], p2 = prev_distance[j2], p3 = prev_distance[j3];
    // A tap that saw no surface contaminates the sample.
    const int taps = !((t0 > 0.0) & !(p0 > 0.0)) & !((t1 > 0.0) & !(p1 > 0.0)) & !((t2 > 0.0) & !(p2 > 0.0)) &
                     !((t3 > 0.0) & !(p3 > 0.0));
    // The inverse distance of a plane is (nearly) affine on the screen, so its bilinear interpolation
    // is the point's at any angle of view, however fast the distance itself grows toward a horizon;
    // across a silhouette it mixes the two surfaces and misses the point's by the other surface's
    // weight times the jump. (A tap of no surface has been flagged above; 1/0 is kept out of the sum.)
    double inv_interp = 0.0;
    inv_interp += t0 / (p0 > 0.0 ? p0 : 1.0);
    inv_interp += t1 / (p1 > 0.0 ? p1 : 1.0);
    inv_interp += t2 / (p2 > 0.0 ? p2 : 1.0);
    inv_interp += t3 / (p3 > 0.0 ? p3 : 1.0);
    const int ok = inside & taps & (std::abs(inv_interp * d_prev - 1.0) <= tolerance);
    const int background = !(px[2] > 0.0f);
    state[x] = background + (1 - background) * (2 - 2 * ok);  // kBackground, else kValid or kDisoccluded
    i0[x] = j0, i1[x] = j1, i2[x] = j2, i3[x] = j3;
    w0[x] = float(t0), w1[x] = float(t1), w2[x] = float(t2), w3[x] = float(t3);
  }
}
// Row y of a 4-channel motion image (callers check the channels).
void reproject_row(const Image& motion, const float* prev_distance, double tolerance, int y, RowWarp& out) {
  reproject_pixels(motion.px(0, y), motion.width, motion.height, y, prev_distance, tolerance, out.state.data(),
                   out.idx[0].data(), out.idx[1].data(), out.idx[2].data(), out.idx[3].data(), out.weight[0].data(),
                   out.weight[1].data(), out.weight[2].data(), out.weight[3].data());
}

// out[x] = the bilinear value of `plane` (a quantity of frame t-1) at row pixel x's taps, x < w.
GLINTLAB_AVX2_CLONES void sample_row(const RowWarp& warp, const float* __restrict plane, int w, double* __restrict out) {
  const int *__restrict i0 = warp.idx[0].data(), *__restrict i1 = warp.idx[1].data();
  const int *__restrict i2 = warp.idx[2].data(), *__restrict i3 = warp.idx[3].data();
  const float *__restrict w0 = warp.weight[0].data(), *__restrict w1 = warp.weight[1].data();
  const float *__restrict w2 = warp.weight[2].data(), *__restrict w3 = warp.weight[3].data();
  for (int x = 0; x < w; ++x) {
    double v = 0.0;
    v += double(w0[x]) * plane[i0[x]];
    v += double(w1[x]) * plane[i1[x]];
    v += double(w2[x]) * plane[i2[x]];
    v += double(w3[x]) * plane[i3[x]];
    out[x] = v;
  }
}

// The per-pixel terms of FlickerTracker::push for one row of w pixels, kRowTerms a pixel into `terms`
// (pixel x's at terms[kRowTerms x ..]): |ΔT − ΔR|, |ΔT|, |ΔR| (PQ, fixed pixel), the fixed-gaze excess,
// then along the motion c(T), c(R), T's own contrast, the excess, the lag and |e_t − e_{t−1}| (0 where
// the pixel is masked). The planes are the row's (frame t and frame t−1 at the same pixels); `prev`
// holds frame t−1 resampled along the motion: T, R, T's and R's Y_a, PQ of T and of R, w each.
constexpr std::size_t kRowTerms = 10;
GLINTLAB_AVX2_CLONES void flicker_terms(int w, const int* __restrict state, const float* __restrict yt,
                                        const double* __restrict pqt, const double* __restrict prev_pqt,
                                        const float* __restrict own_a, const float* __restrict prev_own_a,
                                        const float* __restrict ref_y, const double* __restrict ref_pq,
                                        const double* __restrict prev_ref_pq, const float* __restrict ref_a,
                                        const float* __restrict prev_ref_a, const double* __restrict prev,
                                        double* __restrict terms) {
  const double *t_prev = prev, *r_prev = prev + w, *ta_prev = prev + 2 * w, *ra_prev = prev + 3 * w;
  const double *pq_t_prev = prev + 4 * w, *pq_r_prev = prev + 5 * w;
  for (int x = 0; x < w; ++x) {
    double* tm = terms + kRowTerms * std::size_t(x);
    // Fixed-pixel terms over every pixel.
    const double dT = pqt[x] - prev_pqt[x], dR = ref_pq[x] - prev_ref_pq[x];
    tm[0] = std::abs(dT - dR);
    tm[1] = std::abs(dT);
    tm[2] = std::abs(dR);
    // The five terms over the reference's adaptation luminance share one reciprocal.
    const double inv_denom = 1.0 / (double(ref_a[x]) + kContrastEpsilon);
    {  // fixed gaze, at the eye's resolution
      const double fT = std::abs(double(own_a[x]) - prev_own_a[x]);
      const double fR = std::abs(double(ref_a[x]) - prev_ref_a[x]);
      tm[3] = std::max(0.0, fT - fR) * inv_denom;
    }
    // Along the motion.
    const double ct = std::abs(double(yt[x]) - t_prev[x]) * inv_denom;
    const double cr = std::abs(double(ref_y[x]) - r_prev[x]) * inv_denom;
    const double cs = std::abs(double(yt[x]) - t_prev[x]) / (double(own_a[x]) + kContrastEpsilon);
    // One-sided, both frames low-passed at the eye's resolution before the difference.
    const double lT = std::abs(double(own_a[x]) - ta_prev[x]);
    const double lR = std::abs(double(ref_a[x]) - ra_prev[x]);
    const double excess = std::max(0.0, lT - lR) * inv_denom;
    const double lag = std::max(0.0, lR - lT) * inv_denom;
    const double emc = std::abs((pqt[x] - ref_pq[x]) - (pq_t_prev[x] - pq_r_prev[x]));
    const bool valid = state[x] == Reprojected::kValid;
    tm[4] = valid ? ct : 0.0;
    tm[5] = valid ? cr : 0.0;
    tm[6] = valid ? cs : 0.0;
    tm[7] = valid ? excess : 0.0;
    tm[8] = valid ? lag : 0.0;
    tm[9] = valid ? emc : 0.0;
  }
}
}  // namespace

std::vector<Reprojected> reproject(const Image& motion, const std::vector<float>& prev_distance, double tolerance) {
  if (prev_distance.size() != motion.pixel_count())
    throw std::invalid_argument("reproject: the previous distances and the motion image differ in size");
  if (motion.channels != 4)
    throw std::invalid_argument("reproject: the motion image needs 4 channels, got " + std::to_string(motion.channels));
  std::vector<Reprojected> out(motion.pixel_count());
  parallel_for(motion.height, [&](long y) {
    RowWarp warp;
    warp.resize(std::size_t(motion.width));
    reproject_row(motion, prev_distance.data(), tolerance, int(y), warp);
    for (int x = 0; x < motion.width; ++x) {
      Reprojected& r = out[std::size_t(y) * std::size_t(motion.width) + std::size_t(x)];
      r.state = Reprojected::State(warp.state[std::size_t(x)]);
      if (r.state != Reprojected::kValid) continue;  // a masked pixel has no taps
      for (int k = 0; k < 4; ++k)
        r.idx[k] = unsigned(warp.idx[k][std::size_t(x)]), r.weight[k] = warp.weight[k][std::size_t(x)];
    }
  });
  return out;
}

FlickerReference flicker_reference(const Image& ref_xyz, const Image* display_xyz) {
  FlickerReference r;
  r.width = ref_xyz.width;
  r.height = ref_xyz.height;
  luminance_planes(ref_xyz, r.y, r.pq);
  r.adaptation = adaptation_luminance(ref_xyz);
  if (display_xyz) {
    require_same_size(ref_xyz, *display_xyz, "flicker_reference (displayed)");
    r.display_lightness = lightness_plane(*display_xyz);
  }
  return r;
}

namespace {
// temporal_score of one frame (metrics/flicker.h) from the displayed lightness of frames t and t-1;
// sums of c^4 per row in parallel, then over rows in order (the same for any thread count).
double temporal_score_frame(int w, int h, const float* lt, const float* prev_lt, const float* lr,
                            const float* prev_lr) {
  std::vector<double> rows(static_cast<size_t>(h));
  parallel_for(h, [&](long y) {
    const std::size_t o = std::size_t(y) * std::size_t(w);
    double sum = 0.0;
    for (int x = 0; x < w; ++x) {
      const std::size_t i = o + std::size_t(x);
      const double c = std::abs((double(lt[i]) - prev_lt[i]) - (double(lr[i]) - prev_lr[i]));
      const double c2 = c * c;
      sum += c2 * c2;
    }
    rows[size_t(y)] = sum;
  });
  double sum = 0.0;
  for (double r : rows) sum += r;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  return n ? std::pow(sum / double(n), 1.0 / kTemporalScorePower) : 0.0;
}
}  // namespace

std::optional<FlickerFrame> FlickerTracker::push(const Image& test_xyz, std::shared_ptr<const FlickerReference> shared,
                                                 const Image& motion, const Image* test_display_xyz) {
  if (!shared) throw std::invalid_argument("FlickerTracker::push: no reference");
  const FlickerReference& ref = *shared;
  if (test_xyz.width != ref.width || test_xyz.height != ref.height)
    throw std::invalid_argument("FlickerTracker::push: test is " + std::to_string(test_xyz.width) + "x" +
                                std::to_string(test_xyz.height) + " but the reference " + std::to_string(ref.width) +
                                "x" + std::to_string(ref.height));
  require_same_size(test_xyz, motion, "FlickerTracker::push (motion)");
  if (motion.channels != 4)
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
  NoFillVector<float> display_lt;
  if (test_display_xyz) {
    require_same_size(test_xyz, *test_display_xyz, "FlickerTracker::push (displayed)");
    display_lt = lightness_plane(*test_display_xyz);
  }
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
      // Where the row's pixels were in frame t-1, and the four quantities of frame t-1 the terms
      // need resampled there (for every pixel: a masked one's values are not used), into the thread's
      // own row buffers (every entry written); then the PQ of the two luminances.
      static thread_local RowWarp warp;
      static thread_local NoFillVector<double> prev;  // 6 planes of w: T, R, T's and R's Y_a, PQ of T and R
      warp.resize(std::size_t(w));
      prev.resize(6 * std::size_t(w));
      double* const t_prev = prev.data();
      double* const r_prev = t_prev + w;
      double* const ta_prev = r_prev + w;
      double* const ra_prev = ta_prev + w;
      double* const pq_t_prev = ra_prev + w;
      double* const pq_r_prev = pq_t_prev + w;
      reproject_row(motion, prev_dist_.data(), kDisocclusionTolerance, int(y), warp);
      sample_row(warp, prev_yt_.data(), w, t_prev);
      sample_row(warp, prev_ref.y.data(), w, r_prev);
      sample_row(warp, prev_ya_test_.data(), w, ta_prev);
      sample_row(warp, prev_ref.adaptation.data(), w, ra_prev);
      perceptual_luminance_n(t_prev, pq_t_prev, std::size_t(w));
      perceptual_luminance_n(r_prev, pq_r_prev, std::size_t(w));
      // The row's terms (vectorised), then their sums in x order (as one loop over the pixels would add them).
      static thread_local NoFillVector<double> terms;
      terms.resize(kRowTerms * std::size_t(w));
      const std::size_t o = std::size_t(y) * std::size_t(w);
      flicker_terms(w, warp.state.data(), yt.data() + o, pqt.data() + o, prev_pqt_.data() + o, own_adaptation.data() + o,
                    prev_ya_test_.data() + o, ref.y.data() + o, ref.pq.data() + o, prev_ref.pq.data() + o,
                    ref.adaptation.data() + o, prev_ref.adaptation.data() + o, prev.data(), terms.data());
      double e = 0, dt = 0, dr = 0, excess_fixed = 0, ct = 0, cr = 0, cs = 0, excess = 0, lag = 0, emc = 0;
      std::size_t n_valid = 0, n_disoccluded = 0, n_background = 0;
      const double* tm = terms.data();
      for (int x = 0; x < w; ++x, tm += kRowTerms) {
        e += tm[0], dt += tm[1], dr += tm[2], excess_fixed += tm[3];
        ct += tm[4], cr += tm[5], cs += tm[6], excess += tm[7], lag += tm[8], emc += tm[9];
        const int state = warp.state[std::size_t(x)];
        n_valid += state == Reprojected::kValid;
        n_background += state == Reprojected::kBackground;
        n_disoccluded += state == Reprojected::kDisoccluded;
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
    const bool displayed = !display_lt.empty() && prev_display_lt_.size() == n &&
                           ref.display_lightness.size() == n && prev_ref.display_lightness.size() == n;
    f.temporal_score = displayed ? temporal_score_frame(w, h, display_lt.data(), prev_display_lt_.data(),
                                                        ref.display_lightness.data(), prev_ref.display_lightness.data())
                                 : std::numeric_limits<double>::quiet_NaN();
    frames_.push_back(f);
    result = f;
  }
  width_ = w;
  height_ = h;
  prev_yt_ = std::move(yt);
  prev_pqt_ = std::move(pqt);
  prev_dist_ = std::move(dist);
  prev_ya_test_ = std::move(own_adaptation);
  prev_display_lt_ = std::move(display_lt);
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
  prev_display_lt_.clear();
}

}  // namespace glintlab::metrics

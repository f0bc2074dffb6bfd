#include "metrics/motion_check.h"

#include "metrics/flicker.h"
#include "metrics/parallel.h"
#include "metrics/simd_clones.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace glintlab::metrics {

namespace {

// The bilinear value of plane p (w x h) at texel-index position (qx, qy) (centres at integers),
// clamped to the plane. Plain values, no struct: GCC 12 vectorises the loop that calls it so.
inline double bilinear(const double* p, int w, int h, double qx, double qy) {
  qx = std::min(std::max(qx, 0.0), double(w - 1));  // std::clamp's value for every q but NaN, as selects
  qy = std::min(std::max(qy, 0.0), double(h - 1));
  const int x0 = std::min(int(qx), w - 1), y0 = std::min(int(qy), h - 1);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const double fx = qx - x0, fy = qy - y0;
  return (1 - fx) * (1 - fy) * p[y0 * w + x0] + fx * (1 - fy) * p[y0 * w + x1] + (1 - fx) * fy * p[y1 * w + x0] +
         fx * fy * p[y1 * w + x1];
}

// One candidate's term of row y's checked pixels (x = kMotionCheckStride j, j < count), into out[j]:
// |now − before| along the vectors with signs (sx, sy) (given: (-1, -1), negated: (+1, +1), y flipped:
// (-1, +1), x flipped: (+1, -1)); 0 where the pixel does not count (ok[j] = 0). The row's motion
// comes compacted (vx, vy, each `count` long), and the loop is branch-free, so that it vectorises
// (one candidate a loop: GCC 12 does not take all four at once); a pixel that does not count looks
// up with vectors of 0.
GLINTLAB_AVX2_CLONES void explained_term(const double* __restrict mx, const double* __restrict my,
                                         const int* __restrict ok, const double* __restrict p0,
                                         const double* __restrict p1, int w, int h, int y, int count, double sx,
                                         double sy, double* __restrict out) {
  for (int j = 0; j < count; ++j) {
    const int x = kMotionCheckStride * j;
    const double vx = ok[j] ? mx[j] : 0.0, vy = ok[j] ? my[j] : 0.0;
    const double now = p1[y * w + x];
    const double d = std::abs(now - bilinear(p0, w, h, x + sx * vx, y + sy * vy));
    out[j] = ok[j] ? d : 0.0;
  }
}

}  // namespace

MotionExplained motion_explained(const NoFillVector<double>& p0, const NoFillVector<double>& p1, int w, int h,
                                 const Image& motion) {
  const size_t n = size_t(w) * size_t(h);
  if (p0.size() != n || p1.size() != n || motion.width != w || motion.height != h || motion.channels != 4)
    throw std::invalid_argument("motion_explained: the luminance planes and the 4-channel motion image differ in size");
  struct Row {
    double fixed = 0, cand[4] = {0, 0, 0, 0};
    size_t n = 0;
  };
  // Every second pixel of every second row (kMotionCheckStride): a check of a convention, not a
  // metric, over a quarter of a million pixels at 1080p, for a quarter of the cost.
  const int rows_checked = (h + kMotionCheckStride - 1) / kMotionCheckStride;
  std::vector<Row> rows(static_cast<size_t>(rows_checked));
  parallel_for(rows_checked, [&](long yl) {
    const int y = int(yl) * kMotionCheckStride, count = (w + kMotionCheckStride - 1) / kMotionCheckStride;
    const size_t n = size_t(count);
    static thread_local NoFillVector<double> mv, terms;
    static thread_local NoFillVector<int> ok;
    mv.resize(2 * n);
    terms.resize(5 * n);
    ok.resize(n);
    for (int j = 0; j < count; ++j) {  // the checked pixels' vectors, compacted, whether each counts, the fixed term
      const int x = kMotionCheckStride * j;
      const float* m = motion.px(x, y);
      const double vx = m[0], vy = m[1];
      const double qx = x - vx, qy = y - vy;  // (NaN fails every comparison)
      ok[size_t(j)] = m[2] > 0.0f && !(m[3] < 0.0f) && qx >= 0 && qy >= 0 && qx <= w - 1 && qy <= h - 1;
      mv[size_t(j)] = vx, mv[n + size_t(j)] = vy;
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      terms[size_t(j)] = ok[size_t(j)] ? std::abs(p1[i] - p0[i]) : 0.0;
    }
    // The candidates take x - vx or x + vx and y - vy or y + vy: given (-, -), negated (+, +),
    // y flipped (-, +), x flipped (+, -).
    const double signs[4][2] = {{-1, -1}, {1, 1}, {-1, 1}, {1, -1}};
    for (int c = 0; c < 4; ++c)
      explained_term(mv.data(), mv.data() + n, ok.data(), p0.data(), p1.data(), w, h, y, count, signs[c][0],
                     signs[c][1], terms.data() + size_t(c + 1) * n);
    Row& r = rows[size_t(yl)];  // the sums in x order (a pixel that does not count adds 0)
    for (size_t j = 0; j < n; ++j) {
      r.fixed += terms[j];
      for (int c = 0; c < 4; ++c) r.cand[c] += terms[size_t(c + 1) * n + j];
      r.n += size_t(ok[j]);
    }
  });
  double fixed = 0, cand[4] = {0, 0, 0, 0};
  MotionExplained out;
  for (const Row& r : rows) {
    fixed += r.fixed;
    for (int c = 0; c < 4; ++c) cand[c] += r.cand[c];
    out.pixels += r.n;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto ratio = [&](double a) { return out.pixels > 0 && fixed > 0 ? a / fixed : nan; };
  out.given = ratio(cand[0]);
  out.negated = ratio(cand[1]);
  out.flip_y = ratio(cand[2]);
  out.flip_x = ratio(cand[3]);
  return out;
}

std::string motion_warning(const MotionExplained& m) {
  if (!std::isfinite(m.given)) return "";
  struct Mirror {
    double value;
    const char* what;
  };
  const Mirror mirrors[3] = {
      {m.negated, "their sign: negated (-x, -y) they explain the change better (vectors p_{t-1} - p_t, or "
                  "pointing to the next frame instead of the previous one?)"},
      {m.flip_y, "their y axis: with y flipped they explain the change better (+y up in the file; glintlab's "
                 "grows downwards)"},
      {m.flip_x, "their x axis: with x flipped they explain the change better"}};
  const Mirror* best = nullptr;
  for (const Mirror& x : mirrors)
    if (std::isfinite(x.value) && x.value < m.given * (1.0 - kMotionMirrorMargin) && (!best || x.value < best->value))
      best = &x;
  char figures[160];
  std::snprintf(figures, sizeof figures, " (motion_explained %.3f as given; negated %.3f, y flipped %.3f, x flipped %.3f)",
                m.given, m.negated, m.flip_y, m.flip_x);
  if (best) return std::string("the motion vectors look wrong in ") + best->what + figures;
  if (m.given >= 1.0)
    return std::string("the motion vectors explain less of the reference's change than no motion at all: wrong units "
                       "(NDC or UV read as pixels?), vectors of another frame, or not motion vectors") + figures;
  return "";
}

}  // namespace glintlab::metrics

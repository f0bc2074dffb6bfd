#include "metrics/motion_check.h"

#include "metrics/flicker.h"
#include "metrics/parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace glintlab::metrics {

namespace {

// One axis of a bilinear lookup at texel-index coordinate q (centres at integers), clamped to [0, n - 1].
struct Tap {
  int i0, i1;
  double f;
  Tap(double q, int n) {
    q = std::clamp(q, 0.0, double(n - 1));
    i0 = std::min(int(q), n - 1);
    i1 = std::min(i0 + 1, n - 1);
    f = q - i0;
  }
};

double bilinear(const NoFillVector<double>& p, int w, const Tap& tx, const Tap& ty) {
  auto at = [&](int x, int y) { return p[size_t(y) * size_t(w) + size_t(x)]; };
  const double fx = tx.f, fy = ty.f;
  return (1 - fx) * (1 - fy) * at(tx.i0, ty.i0) + fx * (1 - fy) * at(tx.i1, ty.i0) + (1 - fx) * fy * at(tx.i0, ty.i1) +
         fx * fy * at(tx.i1, ty.i1);
}

}  // namespace

MotionExplained motion_explained(const NoFillVector<double>& p0, const NoFillVector<double>& p1, int w, int h,
                                 const Image& motion) {
  const size_t n = size_t(w) * size_t(h);
  if (p0.size() != n || p1.size() != n || motion.width != w || motion.height != h || motion.channels < 4)
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
    const int y = int(yl) * kMotionCheckStride;
    Row& r = rows[size_t(yl)];
    for (int x = 0; x < w; x += kMotionCheckStride) {
      const float* m = motion.px(x, y);
      if (!(m[2] > 0.0f) || m[3] < 0.0f) continue;
      const double vx = m[0], vy = m[1];
      const double qx = x - vx, qy = y - vy;
      if (!(std::isfinite(qx) && std::isfinite(qy) && qx >= 0 && qy >= 0 && qx <= w - 1 && qy <= h - 1)) continue;
      const double now = p1[size_t(y) * size_t(w) + size_t(x)];
      r.fixed += std::abs(now - p0[size_t(y) * size_t(w) + size_t(x)]);
      // The four candidates take x - vx or x + vx and y - vy or y + vy: given (-, -), negated (+, +),
      // y flipped (-, +), x flipped (+, -).
      const Tap xm(x - vx, w), xp(x + vx, w), ym(y - vy, h), yp(y + vy, h);
      r.cand[0] += std::abs(now - bilinear(p0, w, xm, ym));
      r.cand[1] += std::abs(now - bilinear(p0, w, xp, yp));
      r.cand[2] += std::abs(now - bilinear(p0, w, xm, yp));
      r.cand[3] += std::abs(now - bilinear(p0, w, xp, ym));
      ++r.n;
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

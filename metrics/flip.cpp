#include "metrics/flip.h"
#include "metrics/ciede2000.h"
#include "metrics/parallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "metrics/delta_e_itp.h"
#include "metrics/error_metrics.h"
#include "metrics/vector_math.h"

namespace glintlab::metrics {

namespace {

constexpr double kPi = 3.14159265358979323846;

// FLIP 2020 constants (colour pipeline, feature pipeline, final combination).
constexpr double kQc = 0.7;          // q_c: exponent on the HyAB distance
constexpr double kPc = 0.4;          // p_c: breakpoint of the error redistribution, fraction of c_max
constexpr double kPt = 0.95;         // p_t: error value at the breakpoint
constexpr double kQf = 0.5;          // q_f: exponent on the feature difference
constexpr double kFeatureW = 0.082;  // w: peak-to-trough width (degrees) of the edge detector; sigma = w / 2
constexpr double kToneTarget = 0.85; // HDR-FLIP: tone-mapped value of the brightest / median pixel

// FLIP 2020 spatial CSF filters: S(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2),
// x in degrees, per YCxCz channel (achromatic, red-green, blue-yellow).
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfA{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kCsfRG{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kCsfBY{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfMaxB = 0.04;  // largest b over all channels: sets the common kernel radius

// HDR-FLIP tone mappers as rationals (k0 x^2 + k1 x + k2) / (k3 x^2 + k4 x + k5) (FLIP v1.6's
// coefficients): ACES with the 0.6 pre-exposure folded in, Hable, and Reinhard's x / (1 + x) (which
// FLIP uses only to place the exposure range; Reinhard itself maps on luminance).
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};
constexpr double kHable[6] = {0.231683, 0.013791, 0.0, 0.18, 0.3, 0.018};
constexpr double kReinhard[6] = {0.0, 1.0, 0.0, 0.0, 1.0, 1.0};

const double* tone_coefficients(FlipToneMapper tm) {
  switch (tm) {
    case FlipToneMapper::Aces: return kAces;
    case FlipToneMapper::Hable: return kHable;
    case FlipToneMapper::Reinhard: return kReinhard;
  }
  return kAces;
}

// BT.709 luma coefficients on linear RGB: FLIP's luminance for the exposure range and for Reinhard.
constexpr double kLum[3] = {0.2126, 0.7152, 0.0722};

// Rational tone curve of one channel: negative -> 0, large values (+inf included) held at 1e18 where
// every curve is above 1, clamped to [0, 1]; NaN stays NaN. Branch-free (the comparisons select), in
// double for the public functions and in float for FLIP's per-pixel pipeline (1e18 squared is finite).
template <typename T>
T rational_tonemap(const T* k, T x) {
  x = x < T(0) ? T(0) : (x > T(1e18) ? T(1e18) : x);
  const T y = (k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5]);
  return y < T(0) ? T(0) : (y > T(1) ? T(1) : y);
}

using Plane = std::vector<float>;

// Linear Rec.709 <-> XYZ and FLIP's reference white (the XYZ of RGB (1, 1, 1)).
struct Rec709 {
  Mat3 rgb2xyz, xyz2rgb;
  double white[3];
};

const Rec709& rec709() {
  static const Rec709 c = [] {
    Rec709 r;
    r.rgb2xyz = rgb_to_xyz_npm(0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290);
    r.xyz2rgb = mat3_inverse(r.rgb2xyz);
    for (int i = 0; i < 3; ++i) r.white[i] = r.rgb2xyz[3 * i] + r.rgb2xyz[3 * i + 1] + r.rgb2xyz[3 * i + 2];
    return r;
  }();
  return c;
}

// Linear RGB in [0,1] -> Hunt-adjusted L*a*b* (FLIP 2020, perceptually uniform colour space:
// a* and b* scaled by 0.01 L*). `m` is the RGB -> XYZ matrix with each row divided by the white's
// component (XYZ relative to the white), in T.
template <typename T>
void hunt_lab(T r, T g, T b, const T* m, T out[3]) {
  const T fx = lab_f(m[0] * r + m[1] * g + m[2] * b);
  const T fy = lab_f(m[3] * r + m[4] * g + m[5] * b);
  const T fz = lab_f(m[6] * r + m[7] * g + m[8] * b);
  const T L = T(116) * fy - T(16);
  out[0] = L;
  out[1] = T(0.01) * L * T(500) * (fx - fy);
  out[2] = T(0.01) * L * T(200) * (fy - fz);
}

// The matrices of the per-pixel pipeline in T: RGB -> white-relative XYZ, and back.
template <typename T>
struct ColourMatrices {
  T to_rel_xyz[9], from_rel_xyz[9];
  ColourMatrices() {
    const Rec709& c = rec709();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        to_rel_xyz[3 * i + j] = T(c.rgb2xyz[3 * i + j] / c.white[i]);
        from_rel_xyz[3 * i + j] = T(c.xyz2rgb[3 * i + j] * c.white[j]);
      }
  }
};

double hyab(const double p[3], const double q[3]) {  // FLIP 2020: HyAB = |ΔL| + ||Δ(a, b)||
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// c_max: HyAB^q_c between Hunt-adjusted green and blue, the most distant pair in the RGB cube.
double flip_cmax() {
  static const double cmax = [] {
    const ColourMatrices<double> m;
    double g[3], b[3];
    hunt_lab(0.0, 1.0, 0.0, m.to_rel_xyz, g);
    hunt_lab(0.0, 0.0, 1.0, m.to_rel_xyz, b);
    return std::pow(hyab(g, b), kQc);
  }();
  return cmax;
}

// ---------------------------------------------------------------- separable filters
struct Kernel {
  std::vector<float> w;  // 2r + 1 taps, correlation order (tap j multiplies offset j - r)
  int radius() const { return int(w.size() - 1) / 2; }
};

float flush(double v) { return std::abs(v) < 1e-30 ? 0.0f : float(v); }  // no denormal taps

struct FlipKernels {
  // Colour: per channel one or two normalised 1D Gaussians with weights (the 2D kernel
  // w1 g1(x) g1(y) + w2 g2(x) g2(y), normalised to sum 1 over the square support as the paper).
  Kernel a, rg, by1, by2;
  float by_w1 = 1.0f, by_w2 = 0.0f;
  // Features: normalised Gaussian g, first derivative dg and second derivative ddg (positive taps
  // sum to 1, negative taps to -1 in the 2D kernel, which factorises as dg(x) g(y)).
  Kernel g, dg, ddg;
};

// exp(-pi^2 (x / ppd)^2 / b) on [-r, r], normalised; returns the unnormalised sum in *sum.
Kernel csf_gaussian(double b, int r, double ppd, double* sum) {
  std::vector<double> v(2 * r + 1);
  double s = 0.0;
  for (int x = -r; x <= r; ++x) {
    const double d = x / ppd;
    v[x + r] = std::exp(-kPi * kPi * d * d / b);
    s += v[x + r];
  }
  *sum = s;
  // Drop outer tap pairs below 1e-9 of the sum (far below float resolution of the result); the
  // narrow achromatic and red-green kernels share the blue-yellow radius otherwise.
  int t = 0;
  while (t < r && v[t] / s < 1e-9) ++t;
  Kernel k;
  for (int i = t; i <= 2 * r - t; ++i) k.w.push_back(flush(v[i] / s));
  return k;
}

FlipKernels make_kernels(double ppd) {
  FlipKernels K;
  // FLIP 2020: radius = ceil(3 sqrt(b_max / (2 pi^2)) ppd).
  const int r = int(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * kPi * kPi)) * ppd));
  double s1 = 0.0, s2 = 0.0;
  K.a = csf_gaussian(kCsfA.b1, r, ppd, &s1);   // a2 = 0 for the achromatic channel
  K.rg = csf_gaussian(kCsfRG.b1, r, ppd, &s1);  // a2 = 0 for red-green
  K.by1 = csf_gaussian(kCsfBY.b1, r, ppd, &s1);
  K.by2 = csf_gaussian(kCsfBY.b2, r, ppd, &s2);
  const double m1 = kCsfBY.a1 * std::sqrt(kPi / kCsfBY.b1) * s1 * s1;
  const double m2 = kCsfBY.a2 * std::sqrt(kPi / kCsfBY.b2) * s2 * s2;
  K.by_w1 = float(m1 / (m1 + m2));
  K.by_w2 = float(m2 / (m1 + m2));

  // FLIP 2020 feature detection: sigma = w/2 degrees, radius ceil(3 sigma) pixels.
  const double sd = 0.5 * kFeatureW * ppd;
  const int rf = int(std::ceil(3.0 * sd));
  std::vector<double> g(2 * rf + 1), dg(2 * rf + 1), ddg(2 * rf + 1);
  double sg = 0.0, dpos = 0.0, ddpos = 0.0, ddneg = 0.0;
  for (int x = -rf; x <= rf; ++x) {
    const double e = std::exp(-double(x) * x / (2.0 * sd * sd));
    g[x + rf] = e;
    dg[x + rf] = -x * e;
    ddg[x + rf] = (double(x) * x / (sd * sd) - 1.0) * e;
    sg += e;
    if (dg[x + rf] > 0) dpos += dg[x + rf];
    if (ddg[x + rf] > 0) ddpos += ddg[x + rf];
    if (ddg[x + rf] < 0) ddneg -= ddg[x + rf];
  }
  for (int i = 0; i <= 2 * rf; ++i) {
    K.g.w.push_back(flush(g[i] / sg));
    K.dg.w.push_back(dpos > 0 ? flush(dg[i] / dpos) : 0.0f);  // negative taps sum to -dpos by symmetry
    const double n = ddg[i] > 0 ? ddpos : ddneg;
    K.ddg.w.push_back(n > 0 ? flush(ddg[i] / n) : 0.0f);
  }
  return K;
}

// d[x] = sum over taps j in order of k[j] src[j][x], for x < n: 4 V-sized vectors of pixels at a time,
// their sums in registers (GCC/Clang vector extensions), so that each tap costs one load per pixel and
// no store. The same operations in the same order as a scalar loop.
template <int kBytes>
inline void weighted_sum_vec(float* __restrict d, const float* const* src, const float* k, int taps, int n) {
  typedef float V __attribute__((vector_size(kBytes)));
  constexpr int L = kBytes / 4;
  int x = 0;
  for (; x + 4 * L <= n; x += 4 * L) {
    V a0 = {}, a1 = {}, a2 = {}, a3 = {};
    for (int j = 0; j < taps; ++j) {
      V s0, s1, s2, s3;  // unaligned loads
      std::memcpy(&s0, src[j] + x, sizeof s0);
      std::memcpy(&s1, src[j] + x + L, sizeof s1);
      std::memcpy(&s2, src[j] + x + 2 * L, sizeof s2);
      std::memcpy(&s3, src[j] + x + 3 * L, sizeof s3);
      const V kj = V{} + k[j];
      a0 += kj * s0;
      a1 += kj * s1;
      a2 += kj * s2;
      a3 += kj * s3;
    }
    std::memcpy(d + x, &a0, sizeof a0);
    std::memcpy(d + x + L, &a1, sizeof a1);
    std::memcpy(d + x + 2 * L, &a2, sizeof a2);
    std::memcpy(d + x + 3 * L, &a3, sizeof a3);
  }
  for (; x < n; ++x) {
    float acc = 0.0f;
    for (int j = 0; j < taps; ++j) acc += k[j] * src[j][x];
    d[x] = acc;
  }
}

// Two versions, chosen once by the loader (GCC function multiversioning): 8 floats per vector where
// the CPU has AVX2, 4 (SSE, every x86-64) elsewhere. No FMA in either (ISO C++: GCC contracts
// nothing), so both give bit-identical sums; with AVX2 a 640x360 frame's HDR-FLIP took 39 ms
// instead of 48 ms on one thread.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target("avx2"))) void weighted_sum(float* __restrict d, const float* const* src, const float* k,
                                                  int taps, int n) {
  weighted_sum_vec<32>(d, src, k, taps, n);
}
__attribute__((target("default"))) void weighted_sum(float* __restrict d, const float* const* src, const float* k,
                                                     int taps, int n) {
  weighted_sum_vec<16>(d, src, k, taps, n);
}
#else
void weighted_sum(float* __restrict d, const float* const* src, const float* k, int taps, int n) {
  weighted_sum_vec<16>(d, src, k, taps, n);
}
#endif

// One row correlated with k, borders replicated (pad, src: scratch).
void filter_row(const float* s, float* d, int w, const Kernel& k, std::vector<float>& pad,
                std::vector<const float*>& src) {
  const int r = k.radius();
  pad.resize(std::size_t(w) + 2 * r);
  for (int i = 0; i < r; ++i) {
    pad[i] = s[0];
    pad[std::size_t(w) + r + i] = s[w - 1];
  }
  std::copy(s, s + w, pad.begin() + r);
  src.resize(std::size_t(2 * r + 1));
  for (int j = 0; j <= 2 * r; ++j) src[j] = pad.data() + j;
  weighted_sum(d, src.data(), k.w.data(), 2 * r + 1, w);
}

// Row y of the vertical correlation with k (borders replicated) of rows held in a ring: row yy of the
// input is at ring + (yy mod ring_rows) w (src: scratch).
void filter_column(const float* ring, int ring_rows, int y, int h, int w, const Kernel& k, float* d,
                   std::vector<const float*>& src) {
  const int r = k.radius();
  src.resize(std::size_t(2 * r + 1));
  for (int j = -r; j <= r; ++j) src[j + r] = ring + std::size_t(std::clamp(y + j, 0, h - 1) % ring_rows) * w;
  weighted_sum(d, src.data(), k.w.data(), 2 * r + 1, w);
}

// Per-image state of LDR-FLIP: filtered Hunt-adjusted Lab and feature magnitudes.
struct Prepared {
  Plane L, A, B, edge, point;
};

// The horizontally filtered signals of the two pipelines, kept for a ring of rows.
enum RowSignal { kRowA, kRowRG, kRowBY1, kRowBY2, kRowDG, kRowDDG, kRowG, kRowSignals };

// Scratch of prepare(): one input row, the ring, one output row per vertical filter. About 0.4 MB
// at 640 px wide, so it stays in a core's L2 cache (the planes of the whole image did not).
struct Work {
  std::vector<float> r, g, b, yc, cx, cz, ylum, pad;
  std::vector<const float*> taps;
  std::vector<float> ring;                              // kRowSignals x ring_rows x w
  std::vector<float> c_yc, c_cx, c_cz1, c_cz2, ex, ey, px, py;  // vertical filter outputs of one row
};

// x clamped to [0, 1]; NaN passes (branch-free: the comparisons select).
inline float clamp01(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }

// FLIP 2020: linear RGB -> white-relative XYZ (matrix m) -> YCxCz, and the luminance Y / Y_n that the
// feature pipeline filters. (Separate functions with restrict pointers so that the loops vectorise.)
void rgb_to_ycxcz(const float* __restrict R, const float* __restrict G, const float* __restrict B, const float* m,
                  std::size_t n, float* __restrict yc, float* __restrict cx, float* __restrict cz,
                  float* __restrict ylum) {
  const float m0 = m[0], m1 = m[1], m2 = m[2], m3 = m[3], m4 = m[4], m5 = m[5], m6 = m[6], m7 = m[7], m8 = m[8];
  for (std::size_t i = 0; i < n; ++i) {
    const float x = m0 * R[i] + m1 * G[i] + m2 * B[i];
    const float y = m3 * R[i] + m4 * G[i] + m5 * B[i];
    const float z = m6 * R[i] + m7 * G[i] + m8 * B[i];
    yc[i] = 116.0f * y - 16.0f;
    cx[i] = 500.0f * (x - y);
    cz[i] = 200.0f * (y - z);
    ylum[i] = y;  // feature input: (Y' + 16) / 116 = Y / Y_n in [0, 1]
  }
}

// The CSF-filtered YCxCz (Cz as w1 cz1 + w2 cz2, the two blue-yellow Gaussians) -> white-relative XYZ
// -> linear RGB clamped to the RGB cube (matrix mi) -> Hunt-adjusted L*a*b* (matrix m).
void filtered_ycxcz_to_hunt_lab(const float* __restrict yc, const float* __restrict cx, const float* __restrict cz1,
                                const float* __restrict cz2, float w1, float w2, const float* m, const float* mi,
                                std::size_t n, float* __restrict L, float* __restrict A, float* __restrict B) {
  float mm[9], mmi[9];
  std::copy(m, m + 9, mm);
  std::copy(mi, mi + 9, mmi);
  for (std::size_t i = 0; i < n; ++i) {
    const float cz = w1 * cz1[i] + w2 * cz2[i];
    const float y = (yc[i] + 16.0f) / 116.0f;
    const float X = y + cx[i] / 500.0f, Y = y, Z = y - cz / 200.0f;
    const float r = clamp01(mmi[0] * X + mmi[1] * Y + mmi[2] * Z);
    const float g = clamp01(mmi[3] * X + mmi[4] * Y + mmi[5] * Z);
    const float b = clamp01(mmi[6] * X + mmi[7] * Y + mmi[8] * Z);
    float lab[3];
    hunt_lab(r, g, b, mm, lab);
    L[i] = lab[0];
    A[i] = lab[1];
    B[i] = lab[2];
  }
}

// sqrt(a^2 + b^2) element-wise: the magnitude of the edge and point detectors.
void magnitude(const float* __restrict a, const float* __restrict b, float* __restrict out, int n) {
  for (int i = 0; i < n; ++i) out[i] = std::sqrt(a[i] * a[i] + b[i] * b[i]);
}

// n pixels of linear sRGB (stride ch) -> R, G, B in [0, 1]: LDR (exposure_scale <= 0) clamped; HDR
// scaled by exposure_scale = 2^c and tone mapped with `tm` (HDR-FLIP). NaN stays NaN.
void tonemap_row(const float* p, int ch, int n, double exposure_scale, FlipToneMapper tm, float* __restrict R,
                 float* __restrict G, float* __restrict B) {
  if (exposure_scale > 0.0 && tm != FlipToneMapper::Reinhard) {  // per-channel rational curve
    const double* kd = tone_coefficients(tm);
    const float k[6] = {float(kd[0]), float(kd[1]), float(kd[2]), float(kd[3]), float(kd[4]), float(kd[5])};
    const float e = float(exposure_scale);
    for (int i = 0; i < n; ++i) {
      R[i] = rational_tonemap(k, e * p[i * ch]);
      G[i] = rational_tonemap(k, e * p[i * ch + 1]);
      B[i] = rational_tonemap(k, e * p[i * ch + 2]);
    }
  } else if (exposure_scale > 0.0) {  // Reinhard, on luminance
    for (int i = 0; i < n; ++i) {
      double c[3] = {exposure_scale * p[i * ch], exposure_scale * p[i * ch + 1], exposure_scale * p[i * ch + 2]};
      flip_tonemap(tm, c);
      R[i] = float(c[0]);
      G[i] = float(c[1]);
      B[i] = float(c[2]);
    }
  } else {
    for (int i = 0; i < n; ++i) {
      R[i] = clamp01(p[i * ch]);
      G[i] = clamp01(p[i * ch + 1]);
      B[i] = clamp01(p[i * ch + 2]);
    }
  }
}

// src: linear sRGB (first three channels), tone mapped per exposure as tonemap_row says. The
// per-pixel stages run in single precision, as FLIP's own code, and without branches so that they
// vectorise; NaN stays NaN through every stage (the clamps pass it).
// The image streams through one row at a time: input row j is tone mapped, converted to YCxCz and
// filtered horizontally by every kernel into a ring of 2R + 1 rows (R the largest vertical radius);
// output row y is then the vertical filters over the ring, converted to Hunt-adjusted L*a*b* and
// edge/point magnitudes. The same sums in the same order as filtering whole planes, in a working set
// that fits in L2.
void prepare(const Image& src, double exposure_scale, FlipToneMapper tm, const FlipKernels& K, Work& W,
             Prepared& P) {
  const int w = src.width, h = src.height;
  const std::size_t n = std::size_t(w) * h;
  static const ColourMatrices<float> cm;
  const Kernel* rows[kRowSignals] = {&K.a, &K.rg, &K.by1, &K.by2, &K.dg, &K.ddg, &K.g};
  int R = 0;  // the largest vertical radius: every kernel filters rows and columns
  for (const Kernel* k : rows) R = std::max(R, k->radius());
  const int ring_rows = 2 * R + 1;
  for (std::vector<float>* v : {&W.r, &W.g, &W.b, &W.yc, &W.cx, &W.cz, &W.ylum, &W.c_yc, &W.c_cx, &W.c_cz1, &W.c_cz2,
                                &W.ex, &W.ey, &W.px, &W.py})
    v->resize(std::size_t(w));
  W.ring.resize(std::size_t(kRowSignals) * ring_rows * w);
  auto plane = [&](int s) { return W.ring.data() + std::size_t(s) * ring_rows * w; };
  for (Plane* v : {&P.L, &P.A, &P.B, &P.edge, &P.point}) v->resize(n);

  int next = 0;  // the next input row to bring into the ring
  auto input_row = [&](int j) {
    tonemap_row(src.data.data() + std::size_t(j) * w * src.channels, src.channels, w, exposure_scale, tm,
                W.r.data(), W.g.data(), W.b.data());
    // FLIP 2020: linear RGB -> XYZ -> YCxCz (opponent space, relative to the reference white).
    rgb_to_ycxcz(W.r.data(), W.g.data(), W.b.data(), cm.to_rel_xyz, std::size_t(w), W.yc.data(), W.cx.data(),
                 W.cz.data(), W.ylum.data());
    const float* in[kRowSignals] = {W.yc.data(), W.cx.data(), W.cz.data(), W.cz.data(),
                                    W.ylum.data(), W.ylum.data(), W.ylum.data()};
    for (int s = 0; s < kRowSignals; ++s)
      filter_row(in[s], plane(s) + std::size_t(j % ring_rows) * w, w, *rows[s], W.pad, W.taps);
  };
  for (int y = 0; y < h; ++y) {
    while (next <= std::min(h - 1, y + R)) input_row(next++);
    const std::size_t o = std::size_t(y) * w;
    // Colour pipeline: the CSFs' vertical halves, then back to RGB and on to Hunt-adjusted L*a*b*.
    filter_column(plane(kRowA), ring_rows, y, h, w, K.a, W.c_yc.data(), W.taps);
    filter_column(plane(kRowRG), ring_rows, y, h, w, K.rg, W.c_cx.data(), W.taps);
    filter_column(plane(kRowBY1), ring_rows, y, h, w, K.by1, W.c_cz1.data(), W.taps);
    filter_column(plane(kRowBY2), ring_rows, y, h, w, K.by2, W.c_cz2.data(), W.taps);
    filtered_ycxcz_to_hunt_lab(W.c_yc.data(), W.c_cx.data(), W.c_cz1.data(), W.c_cz2.data(), K.by_w1, K.by_w2,
                               cm.to_rel_xyz, cm.from_rel_xyz, std::size_t(w), P.L.data() + o, P.A.data() + o,
                               P.B.data() + o);
    // Feature pipeline: edge (first derivative) and point (second derivative) detectors on Y / Y_n.
    filter_column(plane(kRowDG), ring_rows, y, h, w, K.g, W.ex.data(), W.taps);    // edge x: dg(x) g(y)
    filter_column(plane(kRowG), ring_rows, y, h, w, K.dg, W.ey.data(), W.taps);    // edge y: g(x) dg(y)
    filter_column(plane(kRowDDG), ring_rows, y, h, w, K.g, W.px.data(), W.taps);   // point x: ddg(x) g(y)
    filter_column(plane(kRowG), ring_rows, y, h, w, K.ddg, W.py.data(), W.taps);   // point y: g(x) ddg(y)
    magnitude(W.ex.data(), W.ey.data(), P.edge.data() + o, w);
    magnitude(W.px.data(), W.py.data(), P.point.data() + o, w);
  }
}

// FLIP 2020 final error: ΔE_c^(1 - ΔE_f). Writes into out (or keeps the maximum when take_max).
// In single precision, as FLIP's own code; the two powers of a block of pixels go through
// metrics/vector_math.h (they were the largest cost of this function).
void combine(const Prepared& t, const Prepared& r, float* out, bool take_max) {
  const float cmax = float(flip_cmax());
  const float pccmax = float(kPc) * cmax;
  const float below = float(kPt) / pccmax, above = float(1.0 - kPt) / (cmax - pccmax);
  const float inv_sqrt2 = float(1.0 / std::sqrt(2.0));
  const std::size_t n = t.L.size();
  constexpr std::size_t kBlock = 1024;
  std::vector<float> e(kBlock), q(kBlock, float(kQc)), v(kBlock);
  for (std::size_t b0 = 0; b0 < n; b0 += kBlock) {
    const std::size_t m = std::min(kBlock, n - b0);
    // Colour: HyAB, then HyAB^q_c.
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = b0 + k;
      const float dL = t.L[i] - r.L[i], da = t.A[i] - r.A[i], db = t.B[i] - r.B[i];
      e[k] = std::abs(dL) + std::sqrt(da * da + db * db);
    }
    pow_n(e.data(), q.data(), e.data(), m);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = b0 + k;
      // Redistribute HyAB^q_c to [0, 1] (p_t at p_c c_max); c_max is the largest HyAB in the RGB cube,
      // the min only absorbs rounding.
      const float dEc = std::min(e[k] < pccmax ? below * e[k] : float(kPt) + (e[k] - pccmax) * above, 1.0f);
      // Features: (max(|Δedge|, |Δpoint|) / sqrt 2)^q_f in [0, 1].
      const float df = std::max(std::abs(t.edge[i] - r.edge[i]), std::abs(t.point[i] - r.point[i]));
      static_assert(kQf == 0.5, "the sqrt implements q_f = 0.5");
      const float dEf = std::sqrt(std::min(df * inv_sqrt2, 1.0f));  // q_f = 0.5
      e[k] = dEc;
      v[k] = 1.0f - dEf;
    }
    pow_n(e.data(), v.data(), v.data(), m);  // ΔE_c^(1 - ΔE_f); 0^(1 - 0) = 0, as where nothing differs
    float* o = out + b0;
    for (std::size_t k = 0; k < m; ++k) {
      if (!take_max) o[k] = v[k];
      else if (v[k] > o[k] || std::isnan(v[k])) o[k] = v[k];
    }
  }
}

void check_ppd(double ppd, const char* who) {
  if (!(ppd > 0.0) || !(ppd <= kFlipMaxPpd))
    throw std::invalid_argument(std::string(who) + ": pixels per degree must be in (0, " + std::to_string(int(kFlipMaxPpd)) +
                                "], got " + std::to_string(ppd));
}

}  // namespace

double flip_aces_tonemap(double x) { return rational_tonemap(kAces, x); }

void flip_tonemap(FlipToneMapper tm, double rgb[3]) {
  if (tm != FlipToneMapper::Reinhard) {
    const double* k = tone_coefficients(tm);
    for (int c = 0; c < 3; ++c) rgb[c] = rational_tonemap(k, rgb[c]);
    return;
  }
  double v[3];
  for (int c = 0; c < 3; ++c) v[c] = std::isnan(rgb[c]) ? rgb[c] : std::clamp(rgb[c], 0.0, 1e30);
  const double f = 1.0 / (1.0 + kLum[0] * v[0] + kLum[1] * v[1] + kLum[2] * v[2]);
  for (int c = 0; c < 3; ++c) rgb[c] = std::isnan(v[c]) ? v[c] : std::clamp(v[c] * f, 0.0, 1.0);
}

Image xyz_to_linear_srgb(const Image& xyz) {
  if (xyz.channels < 3) throw std::invalid_argument("xyz_to_linear_srgb: image needs >= 3 channels (X, Y, Z)");
  const Mat3& M = rec709().xyz2rgb;
  Image rgb(xyz.width, xyz.height, 3);
  for (std::size_t i = 0; i < xyz.pixel_count(); ++i) {
    const float* p = xyz.data.data() + i * xyz.channels;
    for (int c = 0; c < 3; ++c)
      rgb.data[3 * i + c] = float(M[3 * c] * p[0] + M[3 * c + 1] * p[1] + M[3 * c + 2] * p[2]);
  }
  return rgb;
}

namespace {
// FLIP's count, max(2, ceil(stop - start)), for a span of at most kFlipMaxExposures stops (checked
// before the conversion to int).
int exposure_count(double start, double stop) {
  const double span = std::ceil(stop - start - 1e-5);
  if (!(span <= kFlipMaxExposures))
    throw std::invalid_argument("HDR-FLIP: the exposures span " + std::to_string(stop - start) + " stops; at most " +
                                std::to_string(kFlipMaxExposures) + " exposures are allowed (set --start-exposure, "
                                "--stop-exposure or --num-exposures)");
  return std::max(2, int(span));
}

}  // namespace

HdrFlipExposures hdr_flip_exposures(const Image& ref_xyz, FlipToneMapper tm) {
  // x_max: larger root of (k0 - t k3) x^2 + (k1 - t k4) x + (k2 - t k5) = 0, t = 0.85 (linear when the
  // quadratic term vanishes, as for Reinhard).
  const double* k = tone_coefficients(tm);
  const double t = kToneTarget;
  const double qa = k[0] - t * k[3], qb = k[1] - t * k[4], qc = k[2] - t * k[5];
  double x_max;
  if (qa == 0.0) {
    x_max = -qc / qb;
  } else {
    const double d1 = -0.5 * qb / qa;
    x_max = d1 + std::sqrt(d1 * d1 - qc / qa);
  }

  const Image rgb = xyz_to_linear_srgb(ref_xyz);
  std::vector<double> Y;
  Y.reserve(rgb.pixel_count());
  for (std::size_t i = 0; i < rgb.pixel_count(); ++i) {
    const float* p = rgb.data.data() + 3 * i;
    const double y = kLum[0] * p[0] + kLum[1] * p[1] + kLum[2] * p[2];
    if (std::isfinite(y)) Y.push_back(y);
  }
  HdrFlipExposures e;
  if (Y.empty()) return e;
  const double y_hi = *std::max_element(Y.begin(), Y.end());
  if (!(y_hi > 0.0)) return e;
  auto upper_median = [](std::vector<double>& v) {  // FLIP: element n/2 of the sorted values
    const std::size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + m, v.end());
    return v[m];
  };
  double y_lo = upper_median(Y);
  if (!(y_lo > 0.0)) {
    std::vector<double> pos;
    for (double y : Y)
      if (y > 0.0) pos.push_back(y);
    y_lo = upper_median(pos);
  }
  e.start = std::log2(x_max / y_hi);
  e.stop = std::log2(x_max / y_lo);
  e.count = exposure_count(e.start, e.stop);
  return e;
}

HdrFlipExposures resolve_hdr_flip_exposures(const Image& ref_xyz, const HdrFlipOptions& o) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("HDR-FLIP: " + what); };
  if (std::isinf(o.start_exposure)) bad("start exposure must be finite");
  if (std::isinf(o.stop_exposure)) bad("stop exposure must be finite");
  if (o.num_exposures < 0) bad("number of exposures must be >= 1 (or 0 for automatic), got " + std::to_string(o.num_exposures));
  const bool auto_start = std::isnan(o.start_exposure), auto_stop = std::isnan(o.stop_exposure);
  HdrFlipExposures e;
  if (auto_start || auto_stop) e = hdr_flip_exposures(ref_xyz, o.tone_mapper);
  if (!auto_start) e.start = o.start_exposure;
  if (!auto_stop) e.stop = o.stop_exposure;
  if (e.start > e.stop) {
    auto num = [](double v) {
      std::ostringstream s;
      s << v;
      return s.str();
    };
    bad("start exposure " + num(e.start) + (auto_start ? " (computed from the reference)" : "") +
        " is above stop exposure " + num(e.stop) + (auto_stop ? " (computed from the reference)" : ""));
  }
  if (o.num_exposures > kFlipMaxExposures)
    bad("number of exposures must be at most " + std::to_string(kFlipMaxExposures) + ", got " +
        std::to_string(o.num_exposures));
  if (o.num_exposures > 0) e.count = o.num_exposures;
  else if (!auto_start || !auto_stop) e.count = exposure_count(e.start, e.stop);
  return e;
}

Image ldr_flip_map_linear_srgb(const Image& test_rgb, const Image& ref_rgb, double ppd) {
  require_same_size(test_rgb, ref_rgb, "ldr_flip_map");
  check_ppd(ppd, "ldr_flip_map");
  const int w = test_rgb.width, h = test_rgb.height;
  Image out(w, h, 1);
  if (out.pixel_count() == 0) return out;
  const FlipKernels K = make_kernels(ppd);
  Work W;
  Prepared pt, pr;
  prepare(test_rgb, 0.0, FlipToneMapper::Aces, K, W, pt);
  prepare(ref_rgb, 0.0, FlipToneMapper::Aces, K, W, pr);
  combine(pt, pr, out.data.data(), false);
  return out;
}

Image ldr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd) {
  require_same_size(test_xyz, ref_xyz, "ldr_flip_map");
  return ldr_flip_map_linear_srgb(xyz_to_linear_srgb(test_xyz), xyz_to_linear_srgb(ref_xyz), ppd);
}

Image hdr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd) {
  return hdr_flip_map(test_xyz, ref_xyz, ppd, HdrFlipOptions{});
}

struct HdrFlipReference::State {
  FlipKernels K;
  FlipToneMapper tm = FlipToneMapper::Aces;
  std::vector<double> scales;
  std::vector<Prepared> ref;  // the reference, prepared once per exposure
};

HdrFlipReference::HdrFlipReference(const Image& ref_xyz, double ppd, const HdrFlipOptions& options)
    : width_(ref_xyz.width), height_(ref_xyz.height) {
  check_ppd(ppd, "HdrFlipReference");
  exposures_ = resolve_hdr_flip_exposures(ref_xyz, options);
  auto state = std::make_shared<State>();
  state_ = state;
  State& st = *state;
  st.K = make_kernels(ppd);
  st.tm = options.tone_mapper;
  const double step = (exposures_.stop - exposures_.start) / std::max(exposures_.count - 1, 1);
  for (int i = 0; i < exposures_.count; ++i) st.scales.push_back(std::exp2(exposures_.start + i * step));
  st.ref.resize(st.scales.size());
  if (ref_xyz.pixel_count() == 0) return;
  const Image r_rgb = xyz_to_linear_srgb(ref_xyz);
  parallel_for(long(st.scales.size()), [&](long i) {
    Work W;
    prepare(r_rgb, st.scales[size_t(i)], st.tm, st.K, W, st.ref[size_t(i)]);
  });
}

Image HdrFlipReference::map(const Image& test_xyz) const {
  require_reference_size(test_xyz, width_, height_, "HdrFlipReference::map");
  Image out(width_, height_, 1, 0.0f);
  if (out.pixel_count() == 0) return out;
  const State& st = *state_;
  const Image t_rgb = xyz_to_linear_srgb(test_xyz);
  // Exposures are independent: each worker keeps the maximum of the exposures it did.
  const int workers = std::max(1, std::min<int>(int(st.scales.size()), int(metric_threads())));
  std::vector<std::vector<float>> partial(workers);
  std::atomic<int> next{0};
  auto work = [&](int id) {
    Work W;
    Prepared pt;
    std::vector<float>& mx = partial[id];
    mx.assign(out.pixel_count(), 0.0f);
    for (int i = next++; i < int(st.scales.size()); i = next++) {
      prepare(t_rgb, st.scales[size_t(i)], st.tm, st.K, W, pt);
      combine(pt, st.ref[size_t(i)], mx.data(), true);
    }
  };
  std::vector<std::thread> pool;
  for (int id = 1; id < workers; ++id) pool.emplace_back(work, id);
  work(0);
  for (std::thread& th : pool) th.join();
  for (const std::vector<float>& mx : partial)
    for (std::size_t j = 0; j < mx.size(); ++j)
      if (mx[j] > out.data[j] || std::isnan(mx[j])) out.data[j] = mx[j];
  return out;
}

Image hdr_flip_map(const Image& test_xyz, const Image& ref_xyz, double ppd, const HdrFlipOptions& options,
                   HdrFlipExposures* used) {
  require_same_size(test_xyz, ref_xyz, "hdr_flip_map");
  HdrFlipReference ref(ref_xyz, ppd, options);
  if (used) *used = ref.exposures();
  return ref.map(test_xyz);
}

}  // namespace glintlab::metrics

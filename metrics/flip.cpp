#include "metrics/flip.h"
#include "metrics/ciede2000.h"
#include "metrics/parallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "metrics/delta_e_itp.h"
#include "metrics/error_metrics.h"

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

// Rational tone curve of one channel: negative -> 0, +inf stays finite (-> k0/k3), clamped to [0, 1].
double rational_tonemap(const double* k, double x) {
  if (std::isnan(x)) return x;
  x = std::clamp(x, 0.0, 1e30);
  const double y = (k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5]);
  return std::clamp(y, 0.0, 1.0);
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
// a* and b* scaled by 0.01 L*).
void hunt_lab(double r, double g, double b, double out[3]) {
  const Rec709& c = rec709();
  const Mat3& M = c.rgb2xyz;
  const double fx = lab_f((M[0] * r + M[1] * g + M[2] * b) / c.white[0]);
  const double fy = lab_f((M[3] * r + M[4] * g + M[5] * b) / c.white[1]);
  const double fz = lab_f((M[6] * r + M[7] * g + M[8] * b) / c.white[2]);
  const double L = 116.0 * fy - 16.0;
  out[0] = L;
  out[1] = 0.01 * L * 500.0 * (fx - fy);
  out[2] = 0.01 * L * 200.0 * (fy - fz);
}

double hyab(const double p[3], const double q[3]) {  // FLIP 2020: HyAB = |ΔL| + ||Δ(a, b)||
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// c_max: HyAB^q_c between Hunt-adjusted green and blue, the most distant pair in the RGB cube.
double flip_cmax() {
  static const double cmax = [] {
    double g[3], b[3];
    hunt_lab(0, 1, 0, g);
    hunt_lab(0, 0, 1, b);
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

// d[x] (+)= k s[x]. Written in blocks of 8 with restrict pointers so that it vectorises at -O2
// (GCC's very-cheap cost model needs a fixed trip count and no aliasing checks).
inline void axpy(float* __restrict d, const float* __restrict s, float k, int n, bool first) {
  int x = 0;
  if (first) {
    for (; x + 8 <= n; x += 8)
      for (int i = 0; i < 8; ++i) d[x + i] = k * s[x + i];
    for (; x < n; ++x) d[x] = k * s[x];
  } else {
    for (; x + 8 <= n; x += 8)
      for (int i = 0; i < 8; ++i) d[x + i] += k * s[x + i];
    for (; x < n; ++x) d[x] += k * s[x];
  }
}

// Horizontal correlation with replicated borders.
void conv_rows(const Plane& src, Plane& dst, int w, int h, const Kernel& k, std::vector<float>& pad) {
  const int r = k.radius();
  pad.resize(std::size_t(w) + 2 * r);
  dst.resize(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    const float* s = src.data() + std::size_t(y) * w;
    for (int i = 0; i < r; ++i) {
      pad[i] = s[0];
      pad[std::size_t(w) + r + i] = s[w - 1];
    }
    std::copy(s, s + w, pad.begin() + r);
    float* d = dst.data() + std::size_t(y) * w;
    for (int j = 0; j <= 2 * r; ++j) axpy(d, pad.data() + j, k.w[j], w, j == 0);
  }
}

// Vertical correlation with replicated borders.
void conv_cols(const Plane& src, Plane& dst, int w, int h, const Kernel& k) {
  const int r = k.radius();
  dst.resize(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    float* d = dst.data() + std::size_t(y) * w;
    for (int j = -r; j <= r; ++j) {
      const int yy = std::clamp(y + j, 0, h - 1);
      axpy(d, src.data() + std::size_t(yy) * w, k.w[j + r], w, j == -r);
    }
  }
}

// Per-image state of LDR-FLIP: filtered Hunt-adjusted Lab and feature magnitudes.
struct Prepared {
  Plane L, A, B, edge, point;
};

struct Work {
  Plane yc, cx, cz, ylum, t0, t1, t2, t3, t4;
  std::vector<float> pad;
};

// src: linear sRGB (first three channels). LDR (exposure_scale <= 0): clamped to [0, 1]; HDR: scaled by
// exposure_scale = 2^c and tone mapped with `tm` (HDR-FLIP), which also lands in [0, 1].
void prepare(const Image& src, double exposure_scale, FlipToneMapper tm, const FlipKernels& K, Work& W,
             Prepared& P) {
  const int w = src.width, h = src.height;
  const Rec709& c = rec709();
  const Mat3& M = c.rgb2xyz;
  const std::size_t n = std::size_t(w) * h;
  W.yc.resize(n);
  W.cx.resize(n);
  W.cz.resize(n);
  W.ylum.resize(n);
  // FLIP 2020: linear RGB -> XYZ -> YCxCz (opponent space, relative to the reference white).
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = src.data.data() + i * src.channels;
    double r, g, b;
    if (exposure_scale > 0.0) {
      double c[3] = {exposure_scale * p[0], exposure_scale * p[1], exposure_scale * p[2]};
      flip_tonemap(tm, c);
      r = c[0];
      g = c[1];
      b = c[2];
    } else {
      r = std::isnan(p[0]) ? p[0] : std::clamp(double(p[0]), 0.0, 1.0);
      g = std::isnan(p[1]) ? p[1] : std::clamp(double(p[1]), 0.0, 1.0);
      b = std::isnan(p[2]) ? p[2] : std::clamp(double(p[2]), 0.0, 1.0);
    }
    const double x = (M[0] * r + M[1] * g + M[2] * b) / c.white[0];
    const double y = (M[3] * r + M[4] * g + M[5] * b) / c.white[1];
    const double z = (M[6] * r + M[7] * g + M[8] * b) / c.white[2];
    W.yc[i] = float(116.0 * y - 16.0);
    W.cx[i] = float(500.0 * (x - y));
    W.cz[i] = float(200.0 * (y - z));
    W.ylum[i] = float(y);  // feature input: (Y' + 16) / 116 = Y / Y_n in [0, 1]
  }
  // Colour pipeline, spatial filtering with the CSFs (separable Gaussians).
  conv_rows(W.yc, W.t0, w, h, K.a, W.pad);
  conv_cols(W.t0, W.yc, w, h, K.a);
  conv_rows(W.cx, W.t0, w, h, K.rg, W.pad);
  conv_cols(W.t0, W.cx, w, h, K.rg);
  conv_rows(W.cz, W.t0, w, h, K.by1, W.pad);
  conv_cols(W.t0, W.t1, w, h, K.by1);
  conv_rows(W.cz, W.t0, w, h, K.by2, W.pad);
  conv_cols(W.t0, W.t2, w, h, K.by2);
  P.L.resize(n);
  P.A.resize(n);
  P.B.resize(n);
  const Mat3& Mi = c.xyz2rgb;
  for (std::size_t i = 0; i < n; ++i) {
    const double cz = double(K.by_w1) * W.t1[i] + double(K.by_w2) * W.t2[i];
    // YCxCz -> XYZ -> linear RGB, clamped to the RGB cube.
    const double y = (W.yc[i] + 16.0) / 116.0;
    const double X = (y + W.cx[i] / 500.0) * c.white[0], Y = y * c.white[1], Z = (y - cz / 200.0) * c.white[2];
    const double r = std::clamp(Mi[0] * X + Mi[1] * Y + Mi[2] * Z, 0.0, 1.0);
    const double g = std::clamp(Mi[3] * X + Mi[4] * Y + Mi[5] * Z, 0.0, 1.0);
    const double b = std::clamp(Mi[6] * X + Mi[7] * Y + Mi[8] * Z, 0.0, 1.0);
    double lab[3];
    hunt_lab(r, g, b, lab);
    P.L[i] = float(lab[0]);
    P.A[i] = float(lab[1]);
    P.B[i] = float(lab[2]);
  }
  // Feature pipeline: edge (first derivative) and point (second derivative) detectors on Y / Y_n.
  conv_rows(W.ylum, W.t0, w, h, K.dg, W.pad);
  conv_rows(W.ylum, W.t1, w, h, K.ddg, W.pad);
  conv_rows(W.ylum, W.t2, w, h, K.g, W.pad);
  conv_cols(W.t0, W.t3, w, h, K.g);   // edge x
  conv_cols(W.t2, W.t4, w, h, K.dg);  // edge y
  P.edge.resize(n);
  for (std::size_t i = 0; i < n; ++i) P.edge[i] = std::sqrt(W.t3[i] * W.t3[i] + W.t4[i] * W.t4[i]);
  conv_cols(W.t1, W.t3, w, h, K.g);    // point x
  conv_cols(W.t2, W.t4, w, h, K.ddg);  // point y
  P.point.resize(n);
  for (std::size_t i = 0; i < n; ++i) P.point[i] = std::sqrt(W.t3[i] * W.t3[i] + W.t4[i] * W.t4[i]);
}

// FLIP 2020 final error: ΔE_c^(1 - ΔE_f). Writes into out (or keeps the maximum when take_max).
void combine(const Prepared& t, const Prepared& r, float* out, bool take_max) {
  const double cmax = flip_cmax();
  const double pccmax = kPc * cmax;
  const std::size_t n = t.L.size();
  for (std::size_t i = 0; i < n; ++i) {
    // Colour: redistribute HyAB^q_c to [0, 1] (p_t at p_c c_max).
    const double dL = double(t.L[i]) - r.L[i], da = double(t.A[i]) - r.A[i], db = double(t.B[i]) - r.B[i];
    const double hy = std::abs(dL) + std::sqrt(da * da + db * db);  // HyAB
    if (hy == 0.0 && t.edge[i] == r.edge[i] && t.point[i] == r.point[i]) {  // 0^(1 - 0) = 0
      if (!take_max) out[i] = 0.0f;
      continue;
    }
    const double e = std::pow(hy, kQc);
    double dEc = e < pccmax ? (kPt / pccmax) * e : kPt + (e - pccmax) / (cmax - pccmax) * (1.0 - kPt);
    dEc = std::min(dEc, 1.0);  // c_max is the largest HyAB in the RGB cube; this only absorbs rounding
    // Features: (max(|Δedge|, |Δpoint|) / sqrt 2)^q_f in [0, 1].
    const double df = std::max(std::abs(double(t.edge[i]) - r.edge[i]), std::abs(double(t.point[i]) - r.point[i]));
    static_assert(kQf == 0.5, "the sqrt implements q_f = 0.5");
    const double dEf = std::sqrt(std::min(df / std::sqrt(2.0), 1.0));  // q_f = 0.5
    const float v = float(std::pow(dEc, 1.0 - dEf));
    if (!take_max) out[i] = v;
    else if (v > out[i] || std::isnan(v)) out[i] = v;
  }
}

void check_ppd(double ppd, const char* who) {
  if (!(ppd > 0.0) || !std::isfinite(ppd))
    throw std::invalid_argument(std::string(who) + ": pixels per degree must be finite and > 0, got " + std::to_string(ppd));
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
  e.count = std::max(2, int(std::ceil(e.stop - e.start - 1e-5)));
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
  if (o.num_exposures > 0) e.count = o.num_exposures;
  else if (!auto_start || !auto_stop) e.count = std::max(2, int(std::ceil(e.stop - e.start - 1e-5)));
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
  if (test_xyz.width != width_ || test_xyz.height != height_)
    throw std::invalid_argument("HdrFlipReference::map: the test image is " + std::to_string(test_xyz.width) + "x" +
                                std::to_string(test_xyz.height) + " but the reference " + std::to_string(width_) +
                                "x" + std::to_string(height_));
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

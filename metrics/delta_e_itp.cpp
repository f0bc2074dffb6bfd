#include "metrics/delta_e_itp.h"

#include <algorithm>
#include <cmath>

#include "metrics/parallel.h"
#include <stdexcept>
#include <string>

#include "metrics/error_metrics.h"

namespace glintlab::metrics {

namespace {

// SMPTE ST 2084 constants (exact rationals of the standard).
constexpr double kPqM1 = 2610.0 / 16384.0;
constexpr double kPqM2 = 2523.0 / 4096.0 * 128.0;
constexpr double kPqC1 = 3424.0 / 4096.0;
constexpr double kPqC2 = 2413.0 / 4096.0 * 32.0;
constexpr double kPqC3 = 2392.0 / 4096.0 * 32.0;

}  // namespace

Mat3 mat3_mul(const Mat3& a, const Mat3& b) {
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return r;
}

Mat3 mat3_inverse(const Mat3& m) {
  const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                     m[2] * (m[3] * m[7] - m[4] * m[6]);
  if (det == 0.0) throw std::logic_error("mat3_inverse: singular colour matrix");
  const double s = 1.0 / det;
  return {(m[4] * m[8] - m[5] * m[7]) * s, (m[2] * m[7] - m[1] * m[8]) * s, (m[1] * m[5] - m[2] * m[4]) * s,
          (m[5] * m[6] - m[3] * m[8]) * s, (m[0] * m[8] - m[2] * m[6]) * s, (m[2] * m[3] - m[0] * m[5]) * s,
          (m[3] * m[7] - m[4] * m[6]) * s, (m[1] * m[6] - m[0] * m[7]) * s, (m[0] * m[4] - m[1] * m[3]) * s};
}

// SMPTE RP 177: columns are the primaries' XYZ (Y = 1) scaled so that R = G = B = 1 gives the white.
Mat3 rgb_to_xyz_npm(double xr, double yr, double xg, double yg, double xb, double yb, double xw, double yw) {
  const Mat3 P = {xr / yr, xg / yg, xb / yb, 1.0, 1.0, 1.0, (1 - xr - yr) / yr, (1 - xg - yg) / yg,
                  (1 - xb - yb) / yb};
  const Mat3 Pi = mat3_inverse(P);
  const double W[3] = {xw / yw, 1.0, (1 - xw - yw) / yw};
  double S[3];
  for (int i = 0; i < 3; ++i) S[i] = Pi[3 * i] * W[0] + Pi[3 * i + 1] * W[1] + Pi[3 * i + 2] * W[2];
  Mat3 M{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M[3 * i + j] = P[3 * i + j] * S[j];
  return M;
}

double pq_inverse_eotf(double luminance_nits) {
  if (!(luminance_nits > 0.0)) luminance_nits = 0.0;  // also NaN
  luminance_nits = std::min(luminance_nits, 1e30);     // +inf: keep pow finite
  const double Ym1 = std::pow(luminance_nits / 10000.0, kPqM1);
  return std::pow((kPqC1 + kPqC2 * Ym1) / (1.0 + kPqC3 * Ym1), kPqM2);  // SMPTE ST 2084 inverse EOTF
}

double pq_eotf(double code_value) {
  const double E = std::clamp(code_value, 0.0, 1.0);
  const double Em = std::pow(E, 1.0 / kPqM2);
  return 10000.0 * std::pow(std::max(Em - kPqC1, 0.0) / (kPqC2 - kPqC3 * Em), 1.0 / kPqM1);  // SMPTE ST 2084 EOTF
}

const Mat3& bt2020_rgb_to_xyz() {
  // ITU-R BT.2020 primaries, D65 white (x, y) = (0.3127, 0.3290).
  static const Mat3 m = rgb_to_xyz_npm(0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290);
  return m;
}

const Mat3& xyz_to_bt2100_lms() {
  // ITU-R BT.2100 (ICtCp): LMS from BT.2020 RGB.
  static const Mat3 lms_from_rgb = {1688.0 / 4096, 2146.0 / 4096, 262.0 / 4096,  //
                                    683.0 / 4096,  2951.0 / 4096, 462.0 / 4096,  //
                                    99.0 / 4096,   309.0 / 4096,  3688.0 / 4096};
  static const Mat3 m = mat3_mul(lms_from_rgb, mat3_inverse(bt2020_rgb_to_xyz()));
  return m;
}

ICtCp xyz_to_ictcp(double X, double Y, double Z, double luminance_nits) {
  const Mat3& M = xyz_to_bt2100_lms();
  const double Xa = X * luminance_nits, Ya = Y * luminance_nits, Za = Z * luminance_nits;
  double lms_p[3];
  for (int i = 0; i < 3; ++i) {
    const double v = M[3 * i] * Xa + M[3 * i + 1] * Ya + M[3 * i + 2] * Za;
    lms_p[i] = std::isnan(v) ? v : pq_inverse_eotf(v);  // NaN input stays NaN
  }
  // ITU-R BT.2100: I, Ct, Cp from L'M'S'.
  return {0.5 * lms_p[0] + 0.5 * lms_p[1],
          (6610.0 * lms_p[0] - 13613.0 * lms_p[1] + 7003.0 * lms_p[2]) / 4096.0,
          (17933.0 * lms_p[0] - 17390.0 * lms_p[1] - 543.0 * lms_p[2]) / 4096.0};
}

double delta_e_itp(const ICtCp& c1, const ICtCp& c2) {
  // ITU-R BT.2124: T = 0.5 Ct, P = Cp.
  const double dI = c1.I - c2.I, dT = 0.5 * (c1.Ct - c2.Ct), dP = c1.Cp - c2.Cp;
  return 720.0 * std::sqrt(dI * dI + dT * dT + dP * dP);
}

Image delta_e_itp_map(const Image& test_xyz, const Image& ref_xyz, double luminance_nits) {
  require_same_size(test_xyz, ref_xyz, "delta_e_itp_map");
  if (!(luminance_nits > 0.0) || !std::isfinite(luminance_nits))
    throw std::invalid_argument("delta_e_itp_map: luminance_nits (cd/m^2 for Y = 1) must be finite and > 0, got " +
                                std::to_string(luminance_nits));
  Image m(test_xyz.width, test_xyz.height, 1);
  parallel_for(long(m.pixel_count()), [&](long i) {
    const float* t = test_xyz.data.data() + i * test_xyz.channels;
    const float* r = ref_xyz.data.data() + i * ref_xyz.channels;
    m.data[i] = float(delta_e_itp(xyz_to_ictcp(t[0], t[1], t[2], luminance_nits),
                                  xyz_to_ictcp(r[0], r[1], r[2], luminance_nits)));
  });
  return m;
}

}  // namespace glintlab::metrics

#include "metrics/delta_e_itp.h"

#include <algorithm>
#include <cmath>

#include "metrics/parallel.h"
#include "metrics/simd_clones.h"
#include <stdexcept>
#include <string>
#include <vector>

#include "metrics/error_metrics.h"
#include "metrics/vector_math.h"

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

GLINTLAB_AVX2_CLONES void pq_inverse_eotf_n(const double* luminance_nits, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    double v = luminance_nits[i];
    if (!(v > 0.0)) v = 0.0;        // also NaN
    out[i] = std::min(v, 1e30) / 10000.0;  // +inf: keep the powers finite
  }
  // SMPTE ST 2084 inverse EOTF: ((c1 + c2 Y^m1) / (1 + c3 Y^m1))^m2, Y = L / 10000.
  pow_n(out, kPqM1, out, n);
  for (std::size_t i = 0; i < n; ++i) out[i] = (kPqC1 + kPqC2 * out[i]) / (1.0 + kPqC3 * out[i]);
  pow_n(out, kPqM2, out, n);
}

double pq_inverse_eotf(double luminance_nits) {
  double code;
  pq_inverse_eotf_n(&luminance_nits, &code, 1);
  return code;
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

namespace {
// ICtCp of `count` colours given as relative XYZ (xyz[3 i ...]) with Y = 1 at `luminance_nits`: LMS,
// PQ of all 3 count values in one call, then ITU-R BT.2100's I, Ct, Cp. A NaN LMS value stays NaN.
void xyz_to_ictcp_n(const double* xyz, std::size_t count, double luminance_nits, ICtCp* out) {
  const Mat3& M = xyz_to_bt2100_lms();
  std::vector<double> lms(3 * count), lms_p(3 * count);
  for (std::size_t j = 0; j < count; ++j) {
    const double Xa = xyz[3 * j] * luminance_nits, Ya = xyz[3 * j + 1] * luminance_nits,
                 Za = xyz[3 * j + 2] * luminance_nits;
    for (int i = 0; i < 3; ++i) lms[3 * j + i] = M[3 * i] * Xa + M[3 * i + 1] * Ya + M[3 * i + 2] * Za;
  }
  pq_inverse_eotf_n(lms.data(), lms_p.data(), lms.size());
  for (std::size_t j = 0; j < count; ++j) {
    double p[3];
    for (int i = 0; i < 3; ++i) p[i] = std::isnan(lms[3 * j + i]) ? lms[3 * j + i] : lms_p[3 * j + i];
    out[j] = {0.5 * p[0] + 0.5 * p[1], (6610.0 * p[0] - 13613.0 * p[1] + 7003.0 * p[2]) / 4096.0,
              (17933.0 * p[0] - 17390.0 * p[1] - 543.0 * p[2]) / 4096.0};
  }
}

// The ICtCp of row y of an XYZ image.
void row_ictcp(const Image& xyz, long y, double luminance_nits, ICtCp* out) {
  const std::size_t w = std::size_t(xyz.width);
  std::vector<double> row(3 * w);
  const float* p = xyz.data.data() + std::size_t(y) * w * xyz.channels;
  for (std::size_t x = 0; x < w; ++x)
    for (int c = 0; c < 3; ++c) row[3 * x + c] = p[x * xyz.channels + c];
  xyz_to_ictcp_n(row.data(), w, luminance_nits, out);
}
}  // namespace

ICtCp xyz_to_ictcp(double X, double Y, double Z, double luminance_nits) {
  const double xyz[3] = {X, Y, Z};
  ICtCp c;
  xyz_to_ictcp_n(xyz, 1, luminance_nits, &c);
  return c;
}

double delta_e_itp(const ICtCp& c1, const ICtCp& c2) {
  // ITU-R BT.2124: T = 0.5 Ct, P = Cp.
  const double dI = c1.I - c2.I, dT = 0.5 * (c1.Ct - c2.Ct), dP = c1.Cp - c2.Cp;
  return 720.0 * std::sqrt(dI * dI + dT * dT + dP * dP);
}

namespace {
void check_nits(double luminance_nits, const char* who) {
  if (!(luminance_nits > 0.0) || !std::isfinite(luminance_nits))
    throw std::invalid_argument(std::string(who) + ": luminance_nits (cd/m^2 for Y = 1) must be finite and > 0, got " +
                                std::to_string(luminance_nits));
}
}  // namespace

Image delta_e_itp_map(const Image& test_xyz, const Image& ref_xyz, double luminance_nits) {
  require_same_size(test_xyz, ref_xyz, "delta_e_itp_map");
  check_nits(luminance_nits, "delta_e_itp_map");
  return delta_e_itp_map(test_xyz, ictcp_image(ref_xyz, luminance_nits));
}

ICtCpImage ictcp_image(const Image& xyz, double luminance_nits) {
  if (xyz.channels < 3) throw std::invalid_argument("ictcp_image: the image needs >= 3 channels (X, Y, Z)");
  check_nits(luminance_nits, "ictcp_image");
  ICtCpImage out{xyz.width, xyz.height, luminance_nits, std::vector<ICtCp>(xyz.pixel_count())};
  parallel_for(xyz.height, [&](long y) { row_ictcp(xyz, y, luminance_nits, &out.ictcp[size_t(y) * xyz.width]); });
  return out;
}

Image delta_e_itp_map(const Image& test_xyz, const ICtCpImage& ref) {
  require_reference_size(test_xyz, ref.width, ref.height, "delta_e_itp_map");
  Image m(test_xyz.width, test_xyz.height, 1);
  const std::size_t w = std::size_t(test_xyz.width);
  parallel_for(test_xyz.height, [&](long y) {
    std::vector<ICtCp> t(w);
    row_ictcp(test_xyz, y, ref.luminance_nits, t.data());
    for (std::size_t x = 0, i = std::size_t(y) * w; x < w; ++x, ++i) m.data[i] = float(delta_e_itp(t[x], ref.ictcp[i]));
  });
  return m;
}

}  // namespace glintlab::metrics

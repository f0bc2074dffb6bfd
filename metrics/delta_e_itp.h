// ΔE_ITP, Recommendation ITU-R BT.2124 (2019): colour difference in the ICtCp space of ITU-R BT.2100 with
// T = 0.5 Ct, P = Cp and ΔE_ITP = 720 sqrt(ΔI^2 + ΔT^2 + ΔP^2) (1 ≈ one just-noticeable difference).
//
// Chain (all in double): relative CIE XYZ (Y = 1 is the diffuse white) -> absolute XYZ in cd/m^2
// (times luminance_nits, default 100 cd/m^2 for Y = 1) -> linear BT.2020 RGB (inverse of the BT.2020
// normalised primary matrix, derived per SMPTE RP 177 from the BT.2020 primaries and the D65 white
// x = 0.3127, y = 0.3290) -> BT.2100 LMS (integer /4096 matrix) -> SMPTE ST 2084 (PQ) inverse EOTF
// -> BT.2100 ICtCp matrix.
// Negative LMS (colours outside the BT.2020 gamut) are clamped to 0 before PQ; values above
// 10000 cd/m^2 are not clamped (PQ code values > 1).
#pragma once

#include <cstddef>
#include <vector>

#include <array>

#include "core/util/image.h"

namespace glintlab::metrics {

constexpr double kItpDefaultLuminanceNits = 100.0;  // cd/m^2 for Y = 1

using Mat3 = std::array<double, 9>;  // row-major 3x3

// 3x3 helpers shared with flip.cpp (RGB <-> XYZ matrices are derived, not typed in).
Mat3 mat3_mul(const Mat3& a, const Mat3& b);
Mat3 mat3_inverse(const Mat3& m);  // throws std::logic_error when singular
// SMPTE RP 177 normalised primary matrix (linear RGB -> XYZ, white has Y = 1) from xy chromaticities.
Mat3 rgb_to_xyz_npm(double xr, double yr, double xg, double yg, double xb, double yb, double xw, double yw);

// SMPTE ST 2084 inverse EOTF: absolute luminance in cd/m^2 -> PQ code value (1 at 10000 cd/m^2).
// Inputs <= 0 or NaN give the code value of 0 cd/m^2 (c1^m2 ≈ 7.3e-7); +inf is treated as 1e30 cd/m^2.
double pq_inverse_eotf(double luminance_nits);
// The same for n values (the scalar function is this with n = 1: identical results). In-place allowed.
// Through metrics/vector_math.h (its powers cost about a third of std::pow's).
void pq_inverse_eotf_n(const double* luminance_nits, double* out, std::size_t n);
// SMPTE ST 2084 EOTF: PQ code value in [0, 1] -> cd/m^2.
double pq_eotf(double code_value);

// BT.2020 linear RGB -> CIE XYZ (normalised primary matrix, Y of white = 1), derived from chromaticities.
const Mat3& bt2020_rgb_to_xyz();
// CIE XYZ -> BT.2100 LMS (BT.2100 LMS matrix times the inverse of bt2020_rgb_to_xyz()).
const Mat3& xyz_to_bt2100_lms();

struct ICtCp {
  double I = 0.0;
  double Ct = 0.0;
  double Cp = 0.0;
};

// ICtCp (BT.2100 PQ) of a relative XYZ colour whose Y = 1 is `luminance_nits` cd/m^2.
ICtCp xyz_to_ictcp(double X, double Y, double Z, double luminance_nits = kItpDefaultLuminanceNits);

// BT.2124: 720 sqrt(ΔI^2 + (0.5 ΔCt)^2 + ΔCp^2).
double delta_e_itp(const ICtCp& c1, const ICtCp& c2);

// Per-pixel ΔE_ITP between two relative CIE XYZ images, 1 channel.
Image delta_e_itp_map(const Image& test_xyz, const Image& ref_xyz,
                      double luminance_nits = kItpDefaultLuminanceNits);

// The reference side of delta_e_itp_map converted once, for many test images: the ICtCp of every pixel
// at `luminance_nits` (validated as in delta_e_itp_map).
struct ICtCpImage {
  int width = 0, height = 0;
  double luminance_nits = kItpDefaultLuminanceNits;
  std::vector<ICtCp> ictcp;
};
ICtCpImage ictcp_image(const Image& xyz, double luminance_nits = kItpDefaultLuminanceNits);
// Equals delta_e_itp_map(test_xyz, ref_xyz, n) exactly for ref = ictcp_image(ref_xyz, n).
Image delta_e_itp_map(const Image& test_xyz, const ICtCpImage& ref);

}  // namespace glintlab::metrics

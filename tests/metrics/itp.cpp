// ΔE_ITP (ITU-R BT.2124) and its pieces: SMPTE ST 2084 code values, the BT.2020 matrix, ICtCp invariants.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "metrics/delta_e_itp.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {
// D65 from its chromaticity (0.3127, 0.3290): the white of the BT.2020 / BT.709 matrices.
constexpr double kWx = 0.3127 / 0.3290, kWz = (1.0 - 0.3127 - 0.3290) / 0.3290;
}  // namespace

TEST(Pq, PublishedCodeValues) {
  // SMPTE ST 2084 code values as tabulated in the HDR literature.
  EXPECT_NEAR(pq_inverse_eotf(10000.0), 1.0, 1e-12);
  EXPECT_NEAR(pq_inverse_eotf(1000.0), 0.7518, 5e-5);
  EXPECT_NEAR(pq_inverse_eotf(100.0), 0.5081, 5e-5);
  EXPECT_NEAR(pq_inverse_eotf(203.0), 0.58, 1e-3);  // BT.2408 HDR reference white: 58 % PQ
  // 0 cd/m^2 -> c1^m2 ≈ 7.3e-7 (not exactly 0 in ST 2084).
  EXPECT_GT(pq_inverse_eotf(0.0), 7.2e-7);
  EXPECT_LT(pq_inverse_eotf(0.0), 7.4e-7);
  EXPECT_EQ(pq_inverse_eotf(-5.0), pq_inverse_eotf(0.0));
  EXPECT_TRUE(std::isfinite(pq_inverse_eotf(INFINITY)));
}

TEST(Pq, EotfInvertsAndIsMonotonic) {
  double prev = -1.0;
  for (double L = 0.001; L <= 10000.0; L *= 1.7) {
    const double E = pq_inverse_eotf(L);
    EXPECT_NEAR(pq_eotf(E), L, 1e-9 * L + 1e-12);
    EXPECT_GT(E, prev);
    prev = E;
  }
}

TEST(Itp, Bt2020MatrixMatchesPublished) {
  // BT.2020 RGB -> XYZ normalised primary matrix as published (e.g. SMPTE RP 177 applied to BT.2020);
  // its Y row is the BT.2020 luma coefficients 0.2627 / 0.6780 / 0.0593.
  const double published[9] = {0.6369580, 0.1446169, 0.1688810, 0.2627002, 0.6779981,
                               0.0593017, 0.0000000, 0.0280727, 1.0609851};
  const Mat3& m = bt2020_rgb_to_xyz();
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(m[i], published[i], 2e-7) << i;
  // LMS rows each sum to 4096/4096: RGB white -> L = M = S.
  const Mat3& lms = xyz_to_bt2100_lms();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(lms[3 * i] * kWx + lms[3 * i + 1] + lms[3 * i + 2] * kWz, 1.0, 1e-12);
}

TEST(Itp, WhiteAndGreysAreAchromatic) {
  for (double Y : {0.0, 0.01, 0.18, 1.0, 10.0, 100.0}) {
    const ICtCp c = xyz_to_ictcp(kWx * Y, Y, kWz * Y, 100.0);
    EXPECT_NEAR(c.Ct, 0.0, 1e-6) << Y;
    EXPECT_NEAR(c.Cp, 0.0, 1e-6) << Y;
    EXPECT_NEAR(c.I, pq_inverse_eotf(100.0 * Y), 1e-12) << Y;
  }
  // Y = 1 at the default 100 cd/m^2: I = PQ(100) = 0.5081.
  EXPECT_NEAR(xyz_to_ictcp(kWx, 1.0, kWz).I, 0.5081, 5e-5);
  // A saturated colour is not achromatic.
  const ICtCp red = xyz_to_ictcp(0.4124, 0.2126, 0.0193);
  EXPECT_GT(std::abs(red.Cp), 0.05);
}

TEST(Itp, IdenticalZeroSymmetricAndLuminanceStep) {
  const ICtCp a = xyz_to_ictcp(0.3, 0.25, 0.6), b = xyz_to_ictcp(0.31, 0.27, 0.55);
  EXPECT_EQ(delta_e_itp(a, a), 0.0);
  EXPECT_DOUBLE_EQ(delta_e_itp(a, b), delta_e_itp(b, a));
  // Achromatic step: only ΔI is non-zero, ΔE_ITP = 720 |ΔI|.
  const double L1 = 100.0, L2 = 101.0;
  const double dE = delta_e_itp(xyz_to_ictcp(kWx, 1.0, kWz, L1), xyz_to_ictcp(kWx, 1.0, kWz, L2));
  EXPECT_NEAR(dE, 720.0 * (pq_inverse_eotf(L2) - pq_inverse_eotf(L1)), 1e-9);
  // BT.2124: ΔE_ITP = 1 is about one just-noticeable difference; a 1 % luminance step at 100 cd/m^2 is
  // of that order (Weber fraction ~1 %), a 10 % step is several JNDs.
  EXPECT_GT(dE, 0.4);
  EXPECT_LT(dE, 1.5);
  const double dE10 = delta_e_itp(xyz_to_ictcp(kWx, 1.0, kWz), xyz_to_ictcp(1.1 * kWx, 1.1, 1.1 * kWz));
  EXPECT_GT(dE10, 5.0);
  EXPECT_LT(dE10, 10.0);
  // T = 0.5 Ct: a pure Ct difference counts half.
  const ICtCp p{0.5, 0.0, 0.0}, q{0.5, 0.01, 0.0}, s{0.5, 0.0, 0.01};
  EXPECT_NEAR(delta_e_itp(p, q), 720.0 * 0.005, 1e-12);
  EXPECT_NEAR(delta_e_itp(p, s), 720.0 * 0.01, 1e-12);
}

TEST(Itp, ScaleConventionInvariance) {
  // Only absolute luminance matters: (s X, s Y, s Z) at L/s cd/m^2 equals (X, Y, Z) at L cd/m^2.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  for (int i = 0; i < 200; ++i) {
    const double X1 = u(rng), Y1 = u(rng), Z1 = u(rng), X2 = u(rng), Y2 = u(rng), Z2 = u(rng);
    const double s = 0.25 + u(rng);
    const double d = delta_e_itp(xyz_to_ictcp(X1, Y1, Z1, 100.0), xyz_to_ictcp(X2, Y2, Z2, 100.0));
    const double ds = delta_e_itp(xyz_to_ictcp(s * X1, s * Y1, s * Z1, 100.0 / s),
                                  xyz_to_ictcp(s * X2, s * Y2, s * Z2, 100.0 / s));
    EXPECT_NEAR(d, ds, 1e-9 * (1.0 + d));
  }
  // Y = 1 at 200 cd/m^2 is the same as doubling both colours at 100 cd/m^2.
  EXPECT_NEAR(delta_e_itp(xyz_to_ictcp(0.2, 0.3, 0.4, 200.0), xyz_to_ictcp(0.25, 0.3, 0.4, 200.0)),
              delta_e_itp(xyz_to_ictcp(0.4, 0.6, 0.8, 100.0), xyz_to_ictcp(0.5, 0.6, 0.8, 100.0)), 1e-9);
}

TEST(Itp, MapMatchesScalarAndValidates) {
  Image t(4, 3, 3), r(4, 3, 3);
  for (std::size_t i = 0; i < t.data.size(); ++i) {
    t.data[i] = 0.05f + 0.01f * float(i);
    r.data[i] = 0.05f + 0.011f * float(i);
  }
  const Image m = delta_e_itp_map(t, r, 250.0);
  ASSERT_EQ(m.channels, 1);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      const float* p = t.px(x, y);
      const float* q = r.px(x, y);
      EXPECT_NEAR(m.at(x, y, 0),
                  delta_e_itp(xyz_to_ictcp(p[0], p[1], p[2], 250.0), xyz_to_ictcp(q[0], q[1], q[2], 250.0)), 1e-4);
    }
  const Image z = delta_e_itp_map(t, t);
  for (float v : z.data) EXPECT_EQ(v, 0.0f);
  EXPECT_THROW(delta_e_itp_map(t, r, 0.0), std::invalid_argument);
  EXPECT_THROW(delta_e_itp_map(t, Image(3, 4, 3)), std::invalid_argument);
}

// CIEDE2000 against the published test data of Sharma, Wu & Dalal 2005 (Table 1) and CIELAB basics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "metrics/ciede2000.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {
struct SharmaPair {
  double L1, a1, b1, L2, a2, b2, dE;
};
// Sharma, Wu & Dalal, Color Res. Appl. 30(1), 2005, Table 1 (all 34 pairs).
const SharmaPair kSharma[34] = {
    {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
    {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
    {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
    {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
    {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
    {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
    {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
    {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
    {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
    {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
    {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
    {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
    {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
    {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
    {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
    {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
    {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
    {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
    {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
};
}  // namespace

TEST(Ciede2000, SharmaTable1AllPairsBothOrders) {
  for (int i = 0; i < 34; ++i) {
    const SharmaPair& p = kSharma[i];
    const Lab c1{p.L1, p.a1, p.b1}, c2{p.L2, p.a2, p.b2};
    // The table is rounded to 4 decimals: the exact value is within 5e-5 of it.
    EXPECT_NEAR(ciede2000(c1, c2), p.dE, 1e-4) << "pair " << i + 1;
    EXPECT_NEAR(ciede2000(c2, c1), p.dE, 1e-4) << "pair " << i + 1 << " swapped";
  }
}

TEST(Ciede2000, SymmetricAndZeroOnIdentity) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> L(0.0, 100.0), ab(-120.0, 120.0);
  for (int i = 0; i < 2000; ++i) {
    const Lab c1{L(rng), ab(rng), ab(rng)}, c2{L(rng), ab(rng), ab(rng)};
    const double d12 = ciede2000(c1, c2), d21 = ciede2000(c2, c1);
    EXPECT_NEAR(d12, d21, 1e-9 * (1.0 + d12));
    EXPECT_GT(d12, 0.0);
    EXPECT_EQ(ciede2000(c1, c1), 0.0);
  }
}

TEST(Ciede2000, ParametricFactorsScaleLightnessTerm) {
  // Pure lightness difference: ΔE00 = |ΔL'| / (kL S_L), so kL = 2 halves it.
  const Lab c1{50, 0, 0}, c2{60, 0, 0};
  EXPECT_NEAR(ciede2000(c1, c2, 2.0), 0.5 * ciede2000(c1, c2), 1e-12);
  // At L_bar = 55: S_L = 1 + 0.015 * 25 / sqrt(45).
  EXPECT_NEAR(ciede2000(c1, c2), 10.0 / (1.0 + 0.015 * 25.0 / std::sqrt(45.0)), 1e-12);
}

TEST(Ciede2000, XyzToLabKnownValues) {
  Lab w = xyz_to_lab(0.95047, 1.0, 1.08883);
  EXPECT_NEAR(w.L, 100.0, 1e-9);
  EXPECT_NEAR(w.a, 0.0, 1e-9);
  EXPECT_NEAR(w.b, 0.0, 1e-9);
  Lab k = xyz_to_lab(0, 0, 0);
  EXPECT_NEAR(k.L, 0.0, 1e-12);
  // Middle grey Y = 0.18 (CIE 15 cube-root branch).
  EXPECT_NEAR(xyz_to_lab(0.18 * 0.95047, 0.18, 0.18 * 1.08883).L, 116.0 * std::cbrt(0.18) - 16.0, 1e-9);
  // Linear branch below (6/29)^3: L* = 903.3 Y (CIE: (29/3)^3 Y).
  EXPECT_NEAR(xyz_to_lab(0.001 * 0.95047, 0.001, 0.001 * 1.08883).L, std::pow(29.0 / 3.0, 3) * 0.001, 1e-9);
  // sRGB red primary (XYZ = first column of the sRGB matrix): the widely published L*a*b* (53.24, 80.09, 67.20).
  Lab red = xyz_to_lab(0.4124564, 0.2126729, 0.0193339);
  EXPECT_NEAR(red.L, 53.24, 0.01);
  EXPECT_NEAR(red.a, 80.09, 0.01);
  EXPECT_NEAR(red.b, 67.20, 0.01);
}

TEST(Ciede2000, FastCubeRootAndTheCompandingEdges) {
  // The single-precision cube root of FLIP's colour pipeline: within 3 ulp of std::cbrt(float) on every
  // octave from 2^-8 to 2^60 at 4099 mantissas each.
  double worst_ulp_f = 0.0;
  for (int e = -8; e <= 60; ++e)
    for (int k = 0; k <= 4098; ++k) {
      const float t = std::ldexp(1.0f + k / 4099.0f, e);
      const float want = std::cbrt(t), got = cbrt_positive(t);
      worst_ulp_f = std::max(worst_ulp_f, double(std::abs(got - want) / (std::nextafter(want, 2.0f * want) - want)));
    }
  EXPECT_LE(worst_ulp_f, 3.0);
  EXPECT_NEAR(lab_f(8.0f), 2.0f, 4e-7f);
  EXPECT_TRUE(std::isnan(lab_f(std::nanf(""))));
  // The companding in double, through xyz_to_lab (its cube roots from libmvec): NaN stays NaN, +inf
  // gives +inf, a negative value takes the linear branch (no cube root of a negative), and both
  // branches meet at (6/29)^3.
  EXPECT_TRUE(std::isnan(xyz_to_lab(0.5, std::nan(""), 0.5).L));
  EXPECT_EQ(xyz_to_lab(1.0, std::numeric_limits<double>::infinity(), 1.0).L, std::numeric_limits<double>::infinity());
  EXPECT_NEAR(xyz_to_lab(0.0, -1.0, 0.0).L, 116.0 * (-1.0 / (3.0 * (6.0 / 29.0) * (6.0 / 29.0)) + 4.0 / 29.0) - 16.0,
              1e-12);
  const double knee = std::pow(6.0 / 29.0, 3), knee_L = 116.0 * 6.0 / 29.0 - 16.0;
  EXPECT_NEAR(xyz_to_lab(0.0, std::nextafter(knee, 1.0), 0.0).L, knee_L, 1e-12);
  EXPECT_NEAR(xyz_to_lab(0.0, knee, 0.0).L, knee_L, 1e-12);
  // The array form is the scalar one, also across its blocks of 256 (a 600-pixel row, stride 4).
  std::vector<float> xyz(600 * 4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.01f, 4.0f);
  for (float& v : xyz) v = u(rng);
  std::vector<double> L(600), a(600), b(600);
  xyz_to_lab_n(xyz.data(), 4, 600, L.data(), a.data(), b.data());
  for (std::size_t i = 0; i < 600; ++i) {
    const Lab want = xyz_to_lab(xyz[4 * i], xyz[4 * i + 1], xyz[4 * i + 2]);
    EXPECT_EQ(L[i], want.L) << i;
    EXPECT_EQ(a[i], want.a) << i;
    EXPECT_EQ(b[i], want.b) << i;
  }
}

TEST(Ciede2000, MapMatchesScalarAndChecksSize) {
  Image t(3, 2, 4, 0.0f), r(3, 2, 4, 0.0f);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const float v = 0.1f + 0.2f * x + 0.3f * y;
      float* p = t.px(x, y);
      p[0] = 0.95047f * v; p[1] = v; p[2] = 1.08883f * v * 0.5f; p[3] = 1.0f;
      float* q = r.px(x, y);
      q[0] = 0.95047f * v * 0.9f; q[1] = v; q[2] = 1.08883f * v; q[3] = 0.0f;  // alpha must be ignored
    }
  const Image m = ciede2000_map(t, r);
  ASSERT_EQ(m.channels, 1);
  ASSERT_EQ(m.width, 3);
  ASSERT_EQ(m.height, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const float* p = t.px(x, y);
      const float* q = r.px(x, y);
      EXPECT_NEAR(m.at(x, y, 0), ciede2000(xyz_to_lab(p[0], p[1], p[2]), xyz_to_lab(q[0], q[1], q[2])), 1e-4);
      EXPECT_GT(m.at(x, y, 0), 1.0f);
    }
  EXPECT_THROW(ciede2000_map(t, Image(2, 2, 4)), std::invalid_argument);
  EXPECT_THROW(ciede2000_map(Image(3, 2, 2), Image(3, 2, 2)), std::invalid_argument);
}

namespace {
// The paper's steps as written (four cosines in T, libm's functions, branches), the oracle for the
// array form ciede2000_n, which computes the same with selects, trigonometric identities and libmvec.
double ciede2000_as_written(const Lab& x, const Lab& y) {
  constexpr double deg = 3.14159265358979323846 / 180.0;
  const double Cbar = 0.5 * (std::hypot(x.a, x.b) + std::hypot(y.a, y.b));
  const double G = 0.5 * (1.0 - std::sqrt(std::pow(Cbar, 7) / (std::pow(Cbar, 7) + std::pow(25.0, 7))));
  const double a1 = (1 + G) * x.a, a2 = (1 + G) * y.a;
  const double C1 = std::hypot(a1, x.b), C2 = std::hypot(a2, y.b);
  auto hue = [&](double b, double a) {
    if (b == 0 && a == 0) return 0.0;
    const double h = std::atan2(b, a) / deg;
    return h < 0 ? h + 360 : h;
  };
  const double h1 = hue(x.b, a1), h2 = hue(y.b, a2);
  double dh = 0;
  if (C1 * C2 != 0) {
    dh = h2 - h1;
    if (dh > 180) dh -= 360;
    if (dh < -180) dh += 360;
  }
  const double L = (x.L + y.L) / 2, C = (C1 + C2) / 2;
  double H = h1 + h2;
  if (C1 * C2 != 0) {
    if (std::abs(h1 - h2) <= 180) H = (h1 + h2) / 2;
    else if (h1 + h2 < 360) H = (h1 + h2 + 360) / 2;
    else H = (h1 + h2 - 360) / 2;
    if (a1 * y.b == x.b * a2 && a1 * a2 + x.b * y.b < 0) {  // opposite hues: the tie |h1 - h2| = 180 exactly
      dh = h1 < 180 ? 180 : -180;
      H = h1 < 180 ? h1 + 90 : h1 - 90;
    }
  }
  const double dH = 2 * std::sqrt(C1 * C2) * std::sin(dh * deg / 2);
  const double T = 1 - 0.17 * std::cos((H - 30) * deg) + 0.24 * std::cos(2 * H * deg) +
                   0.32 * std::cos((3 * H + 6) * deg) - 0.20 * std::cos((4 * H - 63) * deg);
  const double dtheta = 30 * std::exp(-std::pow((H - 275) / 25, 2));
  const double RC = 2 * std::sqrt(std::pow(C, 7) / (std::pow(C, 7) + std::pow(25.0, 7)));
  const double SL = 1 + 0.015 * std::pow(L - 50, 2) / std::sqrt(20 + std::pow(L - 50, 2));
  const double SC = 1 + 0.045 * C, SH = 1 + 0.015 * C * T, RT = -std::sin(2 * dtheta * deg) * RC;
  const double tL = (y.L - x.L) / SL, tC = (C2 - C1) / SC, tH = dH / SH;
  const double q = tL * tL + tC * tC + tH * tH + RT * tC * tH;
  return std::sqrt(q < 0 ? 0.0 : q);  // NaN stays NaN
}
}  // namespace

TEST(Ciede2000, ArrayFormIsThePaperToRoundingAcrossBlocksAndEdges) {
  // Random pairs over the whole L*a*b* range, the Sharma pairs (hue wrap-around, achromatic sides),
  // exact hue quadrant edges (a or b = 0 of either sign), identical pairs and NaN; 1000 pairs so the
  // array form runs several blocks and a partial one.
  std::vector<Lab> x, y;
  for (const SharmaPair& p : kSharma) {
    x.push_back({p.L1, p.a1, p.b1});
    y.push_back({p.L2, p.a2, p.b2});
  }
  for (double a : {0.0, -0.0, 3.0, -3.0})
    for (double b : {0.0, -0.0, 2.0, -2.0}) {
      x.push_back({40.0, a, b});
      y.push_back({45.0, -b, a});
    }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> L(0.0, 120.0), ab(-128.0, 128.0), near(-1e-3, 1e-3);
  for (int k = 0; k < 16; ++k) {  // mirror images: hues exactly 180° apart, the paper's "<= 180" tie
    x.push_back({L(rng), ab(rng), ab(rng)});
    y.push_back({L(rng), -x.back().a, -x.back().b});
  }
  while (x.size() < 1000) {
    const Lab p{L(rng), ab(rng), ab(rng)};
    x.push_back(p);
    // a neighbour (the small differences the metric mostly sees) or an unrelated colour
    y.push_back(x.size() % 2 ? Lab{p.L + near(rng), p.a + near(rng), p.b + near(rng)} : Lab{L(rng), ab(rng), ab(rng)});
  }
  x[500] = y[500];
  x[700].a = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> planes[6];
  for (std::size_t i = 0; i < x.size(); ++i) {
    planes[0].push_back(x[i].L), planes[1].push_back(x[i].a), planes[2].push_back(x[i].b);
    planes[3].push_back(y[i].L), planes[4].push_back(y[i].a), planes[5].push_back(y[i].b);
  }
  std::vector<double> out(x.size());
  ciede2000_n({planes[0].data(), planes[1].data(), planes[2].data()},
              {planes[3].data(), planes[4].data(), planes[5].data()}, out.data(), out.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double want = ciede2000_as_written(x[i], y[i]);
    if (std::isnan(want)) {
      EXPECT_TRUE(std::isnan(out[i])) << i;
      continue;
    }
    worst = std::max(worst, std::abs(out[i] - want) / std::max(want, 1e-2));
    EXPECT_EQ(out[i], ciede2000(x[i], y[i])) << i;  // the scalar form is the array form
  }
  EXPECT_TRUE(std::isnan(out[700]));
  EXPECT_EQ(out[500], 0.0);
  EXPECT_LT(worst, 1e-9) << "largest difference relative to max(ΔE00, 0.01)";
}

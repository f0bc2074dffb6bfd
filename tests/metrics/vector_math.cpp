// The array math of metrics/vector_math.h (libmvec on x86-64) against <cmath>, the array PQ against the
// scalar definition, and the shared-reference colour-difference maps against the two-image maps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "metrics/ciede2000.h"
#include "metrics/delta_e_itp.h"
#include "metrics/flicker.h"
#include "metrics/vector_math.h"

using namespace glintlab;
using namespace glintlab::metrics;

namespace {
template <typename T>
double ulps(T got, T want) {
  if (got == want) return 0.0;
  const T step = std::nextafter(want, std::numeric_limits<T>::infinity()) - want;
  return double(std::abs(got - want) / step);
}
}  // namespace

TEST(VectorMath, Log2AndExp2WithinFourUlpOfLibm) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> e(-60.0, 60.0);
  for (std::size_t n : {std::size_t(1), std::size_t(2), std::size_t(3), std::size_t(1001)}) {  // odd tails too
    std::vector<double> x(n), l(n), p(n);
    std::vector<float> xf(n), lf(n), pf(n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = std::exp2(e(rng));
      xf[i] = float(std::exp2(e(rng) / 2.0));
    }
    log2_n(x.data(), l.data(), n);
    log2_n(xf.data(), lf.data(), n);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_LE(ulps(l[i], std::log2(x[i])), 4.0) << x[i];
      EXPECT_LE(ulps(lf[i], std::log2(xf[i])), 4.0) << xf[i];
      p[i] = l[i] / 3.0;  // exponents in about [-20, 20]
      pf[i] = lf[i] / 3.0f;
    }
    std::vector<double> ex(n);
    std::vector<float> exf(n);
    exp2_n(p.data(), ex.data(), n);
    exp2_n(pf.data(), exf.data(), n);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_LE(ulps(ex[i], std::exp2(p[i])), 4.0) << p[i];
      EXPECT_LE(ulps(exf[i], std::exp2(pf[i])), 4.0) << pf[i];
    }
  }
}

TEST(VectorMath, EveryFunctionWithinFourUlpOfLibmInEveryVariant) {
  // Each variant this CPU can run (SSE always, AVX2 where the CPU has it), lengths with partial vectors.
  const std::string chosen = vector_math_isa();
  std::vector<std::string> isas;
  for (const char* isa : {"sse", "avx2", "libm"})
    if (use_vector_math_isa(isa)) isas.push_back(isa);
  ASSERT_FALSE(isas.empty());
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> angle(-20.0, 20.0), e(-30.0, 30.0), s(-1.0, 1.0);
  for (const std::string& isa : isas) {
    ASSERT_TRUE(use_vector_math_isa(isa));
    EXPECT_EQ(std::string(vector_math_isa()), isa);
    for (std::size_t n : {std::size_t(1), std::size_t(3), std::size_t(5), std::size_t(7), std::size_t(999)}) {
      std::vector<double> x(n), y(n), c(n), out(n);
      for (std::size_t i = 0; i < n; ++i) {
        x[i] = angle(rng);
        y[i] = s(rng) * std::exp2(e(rng) / 3.0);
        c[i] = (i % 2 ? -1.0 : 1.0) * std::exp2(e(rng));
      }
      sin_n(x.data(), out.data(), n);
      for (std::size_t i = 0; i < n; ++i) EXPECT_LE(ulps(out[i], std::sin(x[i])), 4.0) << isa << " sin " << x[i];
      cos_n(x.data(), out.data(), n);
      for (std::size_t i = 0; i < n; ++i) EXPECT_LE(ulps(out[i], std::cos(x[i])), 4.0) << isa << " cos " << x[i];
      exp_n(x.data(), out.data(), n);
      for (std::size_t i = 0; i < n; ++i) EXPECT_LE(ulps(out[i], std::exp(x[i])), 4.0) << isa << " exp " << x[i];
      cbrt_n(c.data(), out.data(), n);  // negative values too
      for (std::size_t i = 0; i < n; ++i) EXPECT_LE(ulps(out[i], std::cbrt(c[i])), 4.0) << isa << " cbrt " << c[i];
      atan2_n(y.data(), x.data(), out.data(), n);
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_LE(ulps(out[i], std::atan2(y[i], x[i])), 4.0) << isa << " atan2 " << y[i] << ", " << x[i];
      std::vector<float> xf(n), lf(n);
      for (std::size_t i = 0; i < n; ++i) xf[i] = float(std::exp2(e(rng)));
      log2_n(xf.data(), lf.data(), n);
      for (std::size_t i = 0; i < n; ++i) EXPECT_LE(ulps(lf[i], std::log2(xf[i])), 4.0) << isa << " log2f " << xf[i];
    }
    // atan2's signed zeros and quadrants, exactly.
    const double z[] = {0.0, -0.0, 0.0, -0.0}, w[] = {1.0, 1.0, -1.0, -1.0};
    double r[4];
    atan2_n(z, w, r, 4);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(r[k], std::atan2(z[k], w[k])) << isa << " atan2 edge " << k;
    EXPECT_TRUE(std::signbit(r[1]));
  }
  ASSERT_TRUE(use_vector_math_isa(chosen));
}

TEST(VectorMath, PowersAndTheirEdges) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  std::vector<double> x = {0.0, 1.0, 8.0, 0.001, 1e6, inf, nan, -2.0}, out(x.size());
  pow_n(x.data(), 1.0 / 3.0, out.data(), x.size());
  EXPECT_EQ(out[0], 0.0);
  EXPECT_EQ(out[1], 1.0);
  EXPECT_NEAR(out[2], 2.0, 1e-15);
  EXPECT_NEAR(out[3], 0.1, 1e-16);
  EXPECT_NEAR(out[4], 100.0, 1e-13);
  EXPECT_EQ(out[5], inf);
  EXPECT_TRUE(std::isnan(out[6]));
  EXPECT_TRUE(std::isnan(out[7]));  // as std::pow of a negative base with a fractional exponent
  // Single precision with per-element exponents, as FLIP's combination takes them.
  std::vector<float> b = {0.0f, 0.0f, 0.5f, 0.3f, 1.0f, std::nanf("")}, p = {0.7f, 0.0f, 0.7f, 0.25f, 0.0f, 0.5f};
  std::vector<float> r(b.size());
  pow_n(b.data(), p.data(), r.data(), b.size());
  EXPECT_EQ(r[0], 0.0f);  // 0^0.7
  EXPECT_EQ(r[1], 1.0f);  // 0^0 = 1, as std::pow
  EXPECT_LE(ulps(r[2], std::pow(0.5f, 0.7f)), 8.0);
  EXPECT_LE(ulps(r[3], std::pow(0.3f, 0.25f)), 8.0);
  EXPECT_EQ(r[4], 1.0f);
  EXPECT_TRUE(std::isnan(r[5]));
}

TEST(VectorMath, ArrayPqIsTheScalarDefinition) {
  // The array PQ against std::pow of the ST 2084 formula, over 12 decades and the edge cases.
  const double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0, c1 = 3424.0 / 4096.0,
               c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
  std::vector<double> L;
  for (double v = 1e-6; v < 1e6; v *= 1.37) L.push_back(v);
  std::vector<double> E(L.size());
  pq_inverse_eotf_n(L.data(), E.data(), L.size());
  for (std::size_t i = 0; i < L.size(); ++i) {
    const double y = std::pow(L[i] / 10000.0, m1);
    const double want = std::pow((c1 + c2 * y) / (1.0 + c3 * y), m2);
    EXPECT_NEAR(E[i], want, 1e-13 * want) << L[i];
    EXPECT_EQ(E[i], pq_inverse_eotf(L[i]));  // the scalar function is the array one
  }
  std::vector<double> edge = {0.0, -3.0, std::nan(""), std::numeric_limits<double>::infinity()}, out(4);
  pq_inverse_eotf_n(edge.data(), out.data(), 4);
  EXPECT_NEAR(out[0], std::pow(c1, m2), 1e-18);
  EXPECT_EQ(out[1], out[0]);
  EXPECT_EQ(out[2], out[0]);  // NaN luminance: the code value of 0 cd/m^2, as the scalar function says
  EXPECT_TRUE(std::isfinite(out[3]));
  // The flicker metric's perceptual luminance keeps NaN.
  std::vector<double> Y = {0.18, std::nan(""), -1.0}, pq(3);
  perceptual_luminance_n(Y.data(), pq.data(), 3);
  EXPECT_EQ(pq[0], pq_inverse_eotf(18.0));
  EXPECT_TRUE(std::isnan(pq[1]));
  EXPECT_EQ(pq[2], pq_inverse_eotf(0.0));
}

TEST(VectorMath, SharedReferenceMapsEqualTwoImageMaps) {
  // ΔE00 and ΔE_ITP against a reference converted once equal the maps of the two images, bit for bit,
  // on an image wider than one vector block with an odd width (tails) and values across the range.
  Image t(37, 5, 4), r(37, 5, 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 3.0f);
  for (float& v : t.data) v = u(rng);
  for (float& v : r.data) v = u(rng);
  t.data[5] = std::nanf("");
  const Image d1 = ciede2000_map(t, r), d2 = ciede2000_map(t, lab_image(r));
  const Image i1 = delta_e_itp_map(t, r, 203.0), i2 = delta_e_itp_map(t, ictcp_image(r, 203.0));
  auto same_or_both_nan = [](float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  for (std::size_t i = 0; i < d1.data.size(); ++i) {
    EXPECT_TRUE(same_or_both_nan(d1.data[i], d2.data[i])) << i;
    EXPECT_TRUE(same_or_both_nan(i1.data[i], i2.data[i])) << i;
  }
  // The pixel with a NaN input is NaN in both maps, never a clean-looking number.
  EXPECT_TRUE(std::isnan(d2.data[1]));
  EXPECT_TRUE(std::isnan(i2.data[1]));
  // An image against its own conversion: ΔE_ITP is exactly 0.
  const Image same = delta_e_itp_map(r, ictcp_image(r, 203.0));
  for (float v : same.data) EXPECT_EQ(v, 0.0f);
  EXPECT_THROW(ciede2000_map(Image(4, 4, 3), lab_image(Image(4, 5, 3))), std::invalid_argument);
  EXPECT_THROW(delta_e_itp_map(Image(4, 4, 3), ictcp_image(Image(5, 4, 3))), std::invalid_argument);
  EXPECT_THROW(ictcp_image(Image(4, 4, 3), 0.0), std::invalid_argument);
}

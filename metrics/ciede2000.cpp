#include "metrics/ciede2000.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "metrics/parallel.h"
#include "metrics/simd_clones.h"

#include "metrics/error_metrics.h"
#include "metrics/vector_math.h"

namespace glintlab::metrics {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double k25To7 = 6103515625.0;  // 25^7
// Pairs per pass of ciede2000_n: its planes (about 20 of them) stay in the first-level cache.
constexpr std::size_t kBlock = 256;
}  // namespace

namespace {
// L*a*b* from the white-relative values t = X / X_w, Y / Y_w, Z / Z_w of n <= kBlock pixels.
GLINTLAB_AVX2_CLONES void lab_of_ratios(const double* tx, const double* ty, const double* tz, std::size_t n,
                                        double* L, double* a, double* b) {
  double rx[kBlock], ry[kBlock], rz[kBlock];
  cbrt_n(tx, rx, n);
  cbrt_n(ty, ry, n);
  cbrt_n(tz, rz, n);
  for (std::size_t i = 0; i < n; ++i) {
    const double fx = lab_companding(tx[i], rx[i]), fy = lab_companding(ty[i], ry[i]);
    const double fz = lab_companding(tz[i], rz[i]);
    L[i] = 116.0 * fy - 16.0;
    a[i] = 500.0 * (fx - fy);
    b[i] = 200.0 * (fy - fz);
  }
}
}  // namespace

GLINTLAB_AVX2_CLONES void xyz_to_lab_n(const float* xyz, std::size_t stride, std::size_t count, double* L, double* a,
                                       double* b) {
  double tx[kBlock], ty[kBlock], tz[kBlock];
  for (std::size_t o = 0; o < count; o += kBlock) {
    const std::size_t n = std::min(kBlock, count - o);
    for (std::size_t i = 0; i < n; ++i) {
      const float* p = xyz + (o + i) * stride;
      tx[i] = p[0] / kLabWhiteX;
      ty[i] = p[1] / kLabWhiteY;
      tz[i] = p[2] / kLabWhiteZ;
    }
    lab_of_ratios(tx, ty, tz, n, L + o, a + o, b + o);
  }
}

Lab xyz_to_lab(double X, double Y, double Z) {
  const double tx = X / kLabWhiteX, ty = Y / kLabWhiteY, tz = Z / kLabWhiteZ;
  Lab out;
  lab_of_ratios(&tx, &ty, &tz, 1, &out.L, &out.a, &out.b);
  return out;
}

// Sharma et al. 2005, steps 1-3, written as element-wise passes over planes of up to kBlock pairs:
// the arithmetic passes vectorise (the branches of the paper are selects), and the transcendental
// functions go through the array math of vector_math.h (libmvec).
GLINTLAB_AVX2_CLONES void ciede2000_n(const LabPlanes& lab1, const LabPlanes& lab2, double* out, std::size_t count,
                                      double kL, double kC, double kH) {
  double C1p[kBlock], C2p[kBlock], a1p[kBlock], a2p[kBlock], h1p[kBlock], h2p[kBlock], dhp[kBlock], s[kBlock];
  double hbar[kBlock], c1[kBlock], s1[kBlock], e[kBlock], r[kBlock];
  for (std::size_t o = 0; o < count; o += kBlock) {
    const std::size_t n = std::min(kBlock, count - o);
    const double *L1 = lab1.L + o, *A1 = lab1.a + o, *B1 = lab1.b + o;
    const double *L2 = lab2.L + o, *A2 = lab2.a + o, *B2 = lab2.b + o;
    // step 1: C'_i, h'_i with a'_i = (1 + G) a_i (chromas as sqrt(a^2 + b^2): L*a*b* values are far
    // from overflow, and hypot is slower).
    for (std::size_t i = 0; i < n; ++i) {
      const double Cab_bar = 0.5 * (std::sqrt(A1[i] * A1[i] + B1[i] * B1[i]) + std::sqrt(A2[i] * A2[i] + B2[i] * B2[i]));
      const double Cab2 = Cab_bar * Cab_bar, Cab7 = Cab2 * Cab2 * Cab2 * Cab_bar;
      const double G = 0.5 * (1.0 - std::sqrt(Cab7 / (Cab7 + k25To7)));
      a1p[i] = (1.0 + G) * A1[i];
      a2p[i] = (1.0 + G) * A2[i];
      C1p[i] = std::sqrt(a1p[i] * a1p[i] + B1[i] * B1[i]);
      C2p[i] = std::sqrt(a2p[i] * a2p[i] + B2[i] * B2[i]);
    }
    atan2_n(B1, a1p, h1p, n);
    atan2_n(B2, a2p, h2p, n);
    // Hue angles in degrees in [0, 360); 0 where a' = b = 0 (step 1). Then step 2's Δh' (0 when a chroma
    // is 0) and step 3's mean hue h'_bar per the paper's four cases (the sum when a chroma is 0).
    for (std::size_t i = 0; i < n; ++i) {
      double g1 = h1p[i] / kDeg, g2 = h2p[i] / kDeg;
      g1 = g1 < 0.0 ? g1 + 360.0 : g1;
      g2 = g2 < 0.0 ? g2 + 360.0 : g2;
      g1 = B1[i] == 0.0 && a1p[i] == 0.0 ? 0.0 : g1;
      g2 = B2[i] == 0.0 && a2p[i] == 0.0 ? 0.0 : g2;
      const bool chromatic = C1p[i] * C2p[i] != 0.0;
      double d = g2 - g1;
      d = d > 180.0 ? d - 360.0 : (d < -180.0 ? d + 360.0 : d);
      const double sum = g1 + g2;
      double mean = std::abs(g1 - g2) <= 180.0 ? 0.5 * sum : (sum < 360.0 ? 0.5 * (sum + 360.0) : 0.5 * (sum - 360.0));
      // Exactly opposite chroma vectors (a colour and its mirror image; Sharma's pair 14 is one) put
      // |h'_1 - h'_2| at 180° exactly, on the paper's "<= 180" tie, which the angles' rounding (atan2
      // within a few ulp) must not decide: Δh' = +-180° and h'_bar = h'_1 +- 90°, as in exact arithmetic.
      const bool opposite = a1p[i] * B2[i] == B1[i] * a2p[i] && a1p[i] * a2p[i] + B1[i] * B2[i] < 0.0;
      d = opposite ? (g1 < 180.0 ? 180.0 : -180.0) : d;
      mean = opposite ? (g1 < 180.0 ? g1 + 90.0 : g1 - 90.0) : mean;
      dhp[i] = chromatic ? d : 0.0;
      hbar[i] = chromatic ? mean : sum;
      s[i] = 0.5 * dhp[i] * kDeg;
      c1[i] = hbar[i] * kDeg;
      const double hq = (hbar[i] - 275.0) / 25.0;
      e[i] = -hq * hq;
    }
    sin_n(s, s, n);  // sin(Δh'/2)
    sin_n(c1, s1, n);
    cos_n(c1, c1, n);
    exp_n(e, e, n);
    // R_T = -sin(2 Δθ) R_C with Δθ = 30° exp(-((h'_bar - 275°) / 25°)^2): the angle first, its sine next.
    for (std::size_t i = 0; i < n; ++i) r[i] = 2.0 * 30.0 * e[i] * kDeg;
    sin_n(r, r, n);
    for (std::size_t i = 0; i < n; ++i) {
      // step 2: ΔL', ΔC', ΔH'.
      const double dLp = L2[i] - L1[i], dCp = C2p[i] - C1p[i];
      const double dHp = 2.0 * std::sqrt(C1p[i] * C2p[i]) * s[i];
      // step 3. T = 1 - 0.17 cos(h - 30°) + 0.24 cos 2h + 0.32 cos(3h + 6°) - 0.20 cos(4h - 63°), from
      // one cos/sin pair through the multiple-angle and angle-sum identities instead of four cosines.
      const double Lp_bar = 0.5 * (L1[i] + L2[i]), Cp_bar = 0.5 * (C1p[i] + C2p[i]);
      const double cs1 = c1[i], sn1 = s1[i];
      const double c2 = 2.0 * cs1 * cs1 - 1.0, s2 = 2.0 * sn1 * cs1;
      const double c3 = cs1 * (2.0 * c2 - 1.0), s3 = sn1 * (2.0 * c2 + 1.0);  // 4c^3 - 3c, 3s - 4s^3
      const double c4 = 2.0 * c2 * c2 - 1.0, s4 = 2.0 * s2 * c2;
      constexpr double kCos30 = 0.86602540378443864676, kSin30 = 0.5;
      constexpr double kCos6 = 0.99452189536827333692, kSin6 = 0.10452846326765347140;
      constexpr double kCos63 = 0.45399049973954679156, kSin63 = 0.89100652418836786236;
      const double T = 1.0 - 0.17 * (cs1 * kCos30 + sn1 * kSin30) + 0.24 * c2 + 0.32 * (c3 * kCos6 - s3 * kSin6) -
                       0.20 * (c4 * kCos63 + s4 * kSin63);
      const double Cp2 = Cp_bar * Cp_bar, Cp7 = Cp2 * Cp2 * Cp2 * Cp_bar;
      const double R_C = 2.0 * std::sqrt(Cp7 / (Cp7 + k25To7));
      const double L50 = (Lp_bar - 50.0) * (Lp_bar - 50.0);
      const double S_L = 1.0 + 0.015 * L50 / std::sqrt(20.0 + L50);
      const double S_C = 1.0 + 0.045 * Cp_bar;
      const double S_H = 1.0 + 0.015 * Cp_bar * T;
      const double R_T = -r[i] * R_C;
      const double tL = dLp / (kL * S_L), tC = dCp / (kC * S_C), tH = dHp / (kH * S_H);
      // |R_T| <= 2 makes the sum >= (|tC| - |tH|)^2 >= 0; the select only absorbs rounding (and passes
      // NaN, which std::max(0.0, NaN) would turn into 0).
      const double q = tL * tL + tC * tC + tH * tH + R_T * tC * tH;
      out[o + i] = std::sqrt(q < 0.0 ? 0.0 : q);
    }
  }
}

double ciede2000(const Lab& lab1, const Lab& lab2, double kL, double kC, double kH) {
  double out;
  ciede2000_n({&lab1.L, &lab1.a, &lab1.b}, {&lab2.L, &lab2.a, &lab2.b}, &out, 1, kL, kC, kH);
  return out;
}

LabImage lab_image(const Image& xyz) {
  if (xyz.channels < 3) throw std::invalid_argument("lab_image: the image needs >= 3 channels (X, Y, Z)");
  const std::size_t n = xyz.pixel_count(), w = std::size_t(xyz.width);
  LabImage out{xyz.width, xyz.height, NoFillVector<double>(n), NoFillVector<double>(n), NoFillVector<double>(n)};
  parallel_for(long(xyz.height), [&](long y) {
    const std::size_t o = std::size_t(y) * w;
    xyz_to_lab_n(xyz.data.data() + o * xyz.channels, std::size_t(xyz.channels), w, &out.L[o], &out.a[o], &out.b[o]);
  });
  return out;
}

namespace {
// ΔE00 of every pixel of test_xyz, a block of a row at a time: the test's L*a*b* as planes beside
// the reference's, which ref_block(k, n, L, a, b) gives for pixels k .. k + n - 1 (n <= kBlock; into
// the scratch planes, or as pointers into planes it holds).
template <typename RefBlock>
Image ciede2000_rows(const Image& test_xyz, RefBlock&& ref_block) {
  Image m = Image::unfilled(test_xyz.width, test_xyz.height, 1);  // every pixel written below
  const std::size_t w = std::size_t(test_xyz.width), nc = std::size_t(test_xyz.channels);
  parallel_for(long(test_xyz.height), [&](long y) {
    double L[kBlock], a[kBlock], b[kBlock], de[kBlock], rL[kBlock], ra[kBlock], rb[kBlock];
    for (std::size_t x0 = 0; x0 < w; x0 += kBlock) {
      const std::size_t n = std::min(kBlock, w - x0), k = std::size_t(y) * w + x0;
      xyz_to_lab_n(test_xyz.data.data() + k * nc, nc, n, L, a, b);
      const LabPlanes ref = ref_block(k, n, rL, ra, rb);
      ciede2000_n({L, a, b}, ref, de, n);
      for (std::size_t i = 0; i < n; ++i) m.data[k + i] = float(de[i]);
    }
  });
  return m;
}
}  // namespace

Image ciede2000_map(const Image& test_xyz, const Image& ref_xyz) {
  require_same_size(test_xyz, ref_xyz, "ciede2000_map");
  // The reference converted block by block too (the blocks lab_image would convert): no plane of it kept.
  const std::size_t nc = std::size_t(ref_xyz.channels);
  return ciede2000_rows(test_xyz, [&](std::size_t k, std::size_t n, double* L, double* a, double* b) {
    xyz_to_lab_n(ref_xyz.data.data() + k * nc, nc, n, L, a, b);
    return LabPlanes{L, a, b};
  });
}

Image ciede2000_map(const Image& test_xyz, const LabImage& ref_lab) {
  require_reference_size(test_xyz, ref_lab.width, ref_lab.height, "ciede2000_map");
  return ciede2000_rows(test_xyz, [&](std::size_t k, std::size_t, double*, double*, double*) {
    return LabPlanes{&ref_lab.L[k], &ref_lab.a[k], &ref_lab.b[k]};
  });
}

}  // namespace glintlab::metrics

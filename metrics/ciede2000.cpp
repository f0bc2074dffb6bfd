#include "metrics/ciede2000.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "metrics/parallel.h"

#include "metrics/error_metrics.h"

namespace glintlab::metrics {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Hue angle in degrees in [0, 360); 0 when a' = b = 0 (Sharma et al. 2005, step 1).
double hue_deg(double b, double a_prime) {
  if (b == 0.0 && a_prime == 0.0) return 0.0;
  double h = std::atan2(b, a_prime) / kDeg;
  if (h < 0.0) h += 360.0;
  return h;
}
}  // namespace

Lab xyz_to_lab(double X, double Y, double Z) {
  const double fx = lab_f(X / kLabWhiteX), fy = lab_f(Y / kLabWhiteY), fz = lab_f(Z / kLabWhiteZ);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double ciede2000(const Lab& lab1, const Lab& lab2, double kL, double kC, double kH) {
  // Sharma et al. 2005, step 1: C'_i, h'_i with a'_i = (1 + G) a_i.
  // (Chromas as sqrt(a^2 + b^2): L*a*b* values are far from overflow, and hypot is slower.)
  const double C1ab = std::sqrt(lab1.a * lab1.a + lab1.b * lab1.b), C2ab = std::sqrt(lab2.a * lab2.a + lab2.b * lab2.b);
  const double Cab_bar = 0.5 * (C1ab + C2ab);
  const double Cab2 = Cab_bar * Cab_bar, Cab7 = Cab2 * Cab2 * Cab2 * Cab_bar;
  const double G = 0.5 * (1.0 - std::sqrt(Cab7 / (Cab7 + 6103515625.0)));  // 25^7
  const double a1p = (1.0 + G) * lab1.a, a2p = (1.0 + G) * lab2.a;
  const double C1p = std::sqrt(a1p * a1p + lab1.b * lab1.b), C2p = std::sqrt(a2p * a2p + lab2.b * lab2.b);
  const double h1p = hue_deg(lab1.b, a1p), h2p = hue_deg(lab2.b, a2p);
  // step 2: ΔL', ΔC', Δh' (0 when a chroma is 0), ΔH'.
  const double dLp = lab2.L - lab1.L;
  const double dCp = C2p - C1p;
  const double CpProd = C1p * C2p;
  double dhp = 0.0;
  if (CpProd != 0.0) {
    dhp = h2p - h1p;
    if (dhp > 180.0) dhp -= 360.0;
    else if (dhp < -180.0) dhp += 360.0;
  }
  const double dHp = 2.0 * std::sqrt(CpProd) * std::sin(0.5 * dhp * kDeg);
  // step 3: means; h'_bar per the four cases of the paper (sum when a chroma is 0).
  const double Lp_bar = 0.5 * (lab1.L + lab2.L);
  const double Cp_bar = 0.5 * (C1p + C2p);
  double hp_bar = h1p + h2p;
  if (CpProd != 0.0) {
    if (std::abs(h1p - h2p) <= 180.0) hp_bar = 0.5 * (h1p + h2p);
    else if (h1p + h2p < 360.0) hp_bar = 0.5 * (h1p + h2p + 360.0);
    else hp_bar = 0.5 * (h1p + h2p - 360.0);
  }
  // T = 1 - 0.17 cos(h - 30°) + 0.24 cos 2h + 0.32 cos(3h + 6°) - 0.20 cos(4h - 63°), from one cos/sin
  // pair through the multiple-angle and angle-sum identities instead of four calls of cos.
  const double c1 = std::cos(hp_bar * kDeg), s1 = std::sin(hp_bar * kDeg);
  const double c2 = 2.0 * c1 * c1 - 1.0, s2 = 2.0 * s1 * c1;
  const double c3 = c1 * (2.0 * c2 - 1.0), s3 = s1 * (2.0 * c2 + 1.0);  // 4c^3 - 3c, 3s - 4s^3
  const double c4 = 2.0 * c2 * c2 - 1.0, s4 = 2.0 * s2 * c2;
  constexpr double kCos30 = 0.86602540378443864676, kSin30 = 0.5;
  constexpr double kCos6 = 0.99452189536827333692, kSin6 = 0.10452846326765347140;
  constexpr double kCos63 = 0.45399049973954679156, kSin63 = 0.89100652418836786236;
  const double T = 1.0 - 0.17 * (c1 * kCos30 + s1 * kSin30) + 0.24 * c2 + 0.32 * (c3 * kCos6 - s3 * kSin6) -
                   0.20 * (c4 * kCos63 + s4 * kSin63);
  const double hq = (hp_bar - 275.0) / 25.0;
  const double dtheta = 30.0 * std::exp(-hq * hq);
  const double Cp2 = Cp_bar * Cp_bar, Cp7 = Cp2 * Cp2 * Cp2 * Cp_bar;
  const double R_C = 2.0 * std::sqrt(Cp7 / (Cp7 + 6103515625.0));
  const double L50 = (Lp_bar - 50.0) * (Lp_bar - 50.0);
  const double S_L = 1.0 + 0.015 * L50 / std::sqrt(20.0 + L50);
  const double S_C = 1.0 + 0.045 * Cp_bar;
  const double S_H = 1.0 + 0.015 * Cp_bar * T;
  const double R_T = -std::sin(2.0 * dtheta * kDeg) * R_C;
  const double tL = dLp / (kL * S_L), tC = dCp / (kC * S_C), tH = dHp / (kH * S_H);
  // |R_T| <= 2 makes the sum >= (|tC| - |tH|)^2 >= 0; the clamp only absorbs rounding (and passes NaN,
  // which std::max(0.0, NaN) would turn into 0).
  const double sum = tL * tL + tC * tC + tH * tH + R_T * tC * tH;
  return std::sqrt(sum < 0.0 ? 0.0 : sum);
}

Image ciede2000_map(const Image& test_xyz, const Image& ref_xyz) {
  require_same_size(test_xyz, ref_xyz, "ciede2000_map");
  return ciede2000_map(test_xyz, lab_image(ref_xyz));
}

LabImage lab_image(const Image& xyz) {
  if (xyz.channels < 3) throw std::invalid_argument("lab_image: the image needs >= 3 channels (X, Y, Z)");
  LabImage out{xyz.width, xyz.height, std::vector<Lab>(xyz.pixel_count())};
  parallel_for(long(out.lab.size()), [&](long i) {
    const float* p = xyz.data.data() + i * xyz.channels;
    out.lab[size_t(i)] = xyz_to_lab(p[0], p[1], p[2]);
  });
  return out;
}

Image ciede2000_map(const Image& test_xyz, const LabImage& ref_lab) {
  require_reference_size(test_xyz, ref_lab.width, ref_lab.height, "ciede2000_map");
  Image m(test_xyz.width, test_xyz.height, 1);
  parallel_for(long(m.pixel_count()), [&](long i) {
    const float* t = test_xyz.data.data() + i * test_xyz.channels;
    m.data[size_t(i)] = float(ciede2000(xyz_to_lab(t[0], t[1], t[2]), ref_lab.lab[size_t(i)]));
  });
  return m;
}

}  // namespace glintlab::metrics

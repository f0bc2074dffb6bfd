#include "metrics/ciede2000.h"

#include <algorithm>
#include <cmath>

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

double lab_f(double t) {
  constexpr double d = 6.0 / 29.0;
  if (t > d * d * d) return std::cbrt(t);
  return t / (3.0 * d * d) + 4.0 / 29.0;
}

Lab xyz_to_lab(double X, double Y, double Z) {
  const double fx = lab_f(X / kLabWhiteX), fy = lab_f(Y / kLabWhiteY), fz = lab_f(Z / kLabWhiteZ);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double ciede2000(const Lab& lab1, const Lab& lab2, double kL, double kC, double kH) {
  // Sharma et al. 2005, step 1: C'_i, h'_i with a'_i = (1 + G) a_i.
  const double C1ab = std::hypot(lab1.a, lab1.b), C2ab = std::hypot(lab2.a, lab2.b);
  const double Cab_bar = 0.5 * (C1ab + C2ab);
  const double Cab2 = Cab_bar * Cab_bar, Cab7 = Cab2 * Cab2 * Cab2 * Cab_bar;
  const double G = 0.5 * (1.0 - std::sqrt(Cab7 / (Cab7 + 6103515625.0)));  // 25^7
  const double a1p = (1.0 + G) * lab1.a, a2p = (1.0 + G) * lab2.a;
  const double C1p = std::hypot(a1p, lab1.b), C2p = std::hypot(a2p, lab2.b);
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
  const double T = 1.0 - 0.17 * std::cos((hp_bar - 30.0) * kDeg) + 0.24 * std::cos(2.0 * hp_bar * kDeg) +
                   0.32 * std::cos((3.0 * hp_bar + 6.0) * kDeg) - 0.20 * std::cos((4.0 * hp_bar - 63.0) * kDeg);
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
  // |R_T| <= 2 makes the sum >= (|tC| - |tH|)^2 >= 0; max() only absorbs rounding.
  return std::sqrt(std::max(0.0, tL * tL + tC * tC + tH * tH + R_T * tC * tH));
}

Image ciede2000_map(const Image& test_xyz, const Image& ref_xyz) {
  require_same_size(test_xyz, ref_xyz, "ciede2000_map");
  Image m(test_xyz.width, test_xyz.height, 1);
  parallel_for(long(m.pixel_count()), [&](long i) {
    const float* t = test_xyz.data.data() + i * test_xyz.channels;
    const float* r = ref_xyz.data.data() + i * ref_xyz.channels;
    m.data[i] = float(ciede2000(xyz_to_lab(t[0], t[1], t[2]), xyz_to_lab(r[0], r[1], r[2])));
  });
  return m;
}

}  // namespace glintlab::metrics

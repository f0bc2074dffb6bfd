// CIEDE2000 colour difference: G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 Color-Difference Formula:
// Implementation Notes, Supplementary Test Data, and Mathematical Observations", Color Res. Appl. 30(1),
// 2005. Lab is CIE 1976 L*a*b* relative to the D65 white XYZ (0.95047, 1.0, 1.08883) (CIE 1931 2 deg),
// Y = 1 being that white. ΔE00 is display-referred: values of Y far above 1 give L* > 100 (no clamping).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "core/util/image.h"

namespace glintlab::metrics {

struct Lab {
  double L = 0.0;
  double a = 0.0;
  double b = 0.0;
};

// Reference white of xyz_to_lab (CIE 1931 2 deg D65, Y = 1).
constexpr double kLabWhiteX = 0.95047;
constexpr double kLabWhiteY = 1.0;
constexpr double kLabWhiteZ = 1.08883;

// Cube root of a finite t > 0 within 4 ulp of std::cbrt (tests/metrics/ciede2000.cpp checks it over
// 2^-8 ... 2^60): a first guess from the exponent divided by 3 in the bit pattern (about 3 % off),
// then three steps of Halley's iteration y <- y (y^3 + 2t) / (2y^3 + t), each cubing the relative
// error. Inlined it took 7.0 ns where glibc's cbrt took 12.9 ns (a loop over 4M values), and cbrt was
// the largest single entry of the metrics' profile (every FLIP exposure takes three per pixel).
inline double cbrt_positive(double t) {
  std::uint64_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = bits / 3 + 0x2A9F7893782DA1CEull;  // exponent / 3, bias restored
  double y;
  std::memcpy(&y, &bits, sizeof y);
  for (int i = 0; i < 3; ++i) {
    const double y3 = y * y * y;
    y *= (y3 + 2.0 * t) / (2.0 * y3 + t);
  }
  return y;
}

// The same in single precision for finite t > 0, within 3 ulp of std::cbrt(float) (tested likewise):
// two Halley steps from the bit-pattern guess. Branch-free, so that loops over pixels vectorise.
inline float cbrt_positive(float t) {
  std::uint32_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = bits / 3 + 0x2A5137A0u;
  float y;
  std::memcpy(&y, &bits, sizeof y);
  for (int i = 0; i < 2; ++i) {
    const float y3 = y * y * y;
    y *= (y3 + 2.0f * t) / (2.0f * y3 + t);
  }
  return y;
}

// CIE 15:2004 eq. 8.3, the L*a*b* companding of a white-relative tristimulus
// value: t^(1/3) above (6/29)^3, linear below (also for negative t: no cube
// root of a negative is taken). NaN stays NaN, +inf gives +inf.
// In double (ΔE00) and in float (FLIP's colour pipeline, as FLIP's own code).
template <typename T>
inline T lab_f(T t) {
  constexpr T d = T(6.0 / 29.0);
  const T root = cbrt_positive(t), linear = t / (T(3) * d * d) + T(4.0 / 29.0);  // both: no branch
  return t > d * d * d ? (t <= std::numeric_limits<T>::max() ? root : t) : linear;
}

// CIE 1976 L*a*b* of XYZ (Y = 1 white) relative to the D65 white above (CIE 15:2004 eq. 8.1-8.3).
Lab xyz_to_lab(double X, double Y, double Z);

// ΔE00 (Sharma et al. 2005, steps 1-3). Symmetric in its arguments.
double ciede2000(const Lab& lab1, const Lab& lab2, double kL = 1.0, double kC = 1.0, double kH = 1.0);

// The same for `n` pairs given as planes: out[i] = ciede2000(lab1[i], lab2[i]) (ciede2000 is this with
// n = 1). The pixel loops' form: the paper's branches as selects, the hue terms' exp, sin, cos and
// atan2 through glibc's vector math (metrics/vector_math.h), so the passes run two pairs at a time.
struct LabPlanes {
  const double* L;
  const double* a;
  const double* b;
};
void ciede2000_n(const LabPlanes& lab1, const LabPlanes& lab2, double* out, std::size_t n, double kL = 1.0,
                 double kC = 1.0, double kH = 1.0);

// Per-pixel ΔE00 between two CIE XYZ images (first three channels), 1 channel, same size.
Image ciede2000_map(const Image& test_xyz, const Image& ref_xyz);

// The reference side of ciede2000_map converted once, for many test images: the L*a*b* of every pixel.
struct LabImage {
  int width = 0, height = 0;
  std::vector<Lab> lab;
};
LabImage lab_image(const Image& xyz);
// Equals ciede2000_map(test_xyz, ref_xyz) exactly for ref_lab = lab_image(ref_xyz).
Image ciede2000_map(const Image& test_xyz, const LabImage& ref_lab);

}  // namespace glintlab::metrics

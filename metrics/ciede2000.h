// CIEDE2000 colour difference: G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 Color-Difference Formula:
// Implementation Notes, Supplementary Test Data, and Mathematical Observations", Color Res. Appl. 30(1),
// 2005. Lab is CIE 1976 L*a*b* relative to the D65 white XYZ (0.95047, 1.0, 1.08883) (CIE 1931 2 deg),
// Y = 1 being that white. ΔE00 is display-referred: values of Y far above 1 give L* > 100 (no clamping).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "core/util/image.h"
#include "core/util/no_fill_vector.h"

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

// Cube root of a finite t > 0 within 3 ulp of std::cbrt(float) (tests/metrics/ciede2000.cpp checks it
// over 2^-8 ... 2^60), for FLIP's colour pipeline: a first guess from the exponent divided by 3 in the
// bit pattern (about 3 % off), then two steps of Halley's iteration y <- y (y^3 + 2t) / (2y^3 + t),
// each cubing the relative error. Branch-free, so that loops over pixels vectorise; glibc's cbrtf is a
// call per value.
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
// value t given its cube root: the root above (6/29)^3, linear below (also
// for negative t: no cube root of a negative is used). NaN stays NaN, +inf
// gives +inf. Both sides are computed and one selected, so loops vectorise.
template <typename T>
inline T lab_companding(T t, T root) {
  constexpr T d = T(6.0 / 29.0);
  const T linear = t / (T(3) * d * d) + T(4.0 / 29.0);
  return t > d * d * d ? (t <= std::numeric_limits<T>::max() ? root : t) : linear;
}
// In single precision, as FLIP's own code computes its per-pixel colours; in double for constants
// (FLIP's c_max).
inline float lab_f(float t) { return lab_companding(t, cbrt_positive(t)); }
inline double lab_f(double t) { return lab_companding(t, std::cbrt(t)); }

// CIE 1976 L*a*b* of XYZ (Y = 1 white) relative to the D65 white above (CIE 15:2004 eq. 8.1-8.3),
// in double, the cube roots through libmvec (vector_math.h). xyz_to_lab is xyz_to_lab_n for one pixel.
Lab xyz_to_lab(double X, double Y, double Z);
// n pixels whose X, Y, Z are the first three of every `stride` floats, into planes L, a, b.
void xyz_to_lab_n(const float* xyz, std::size_t stride, std::size_t n, double* L, double* a, double* b);

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

// The reference side of ciede2000_map converted once, for many test images: the L*a*b* of every pixel,
// as planes (what ciede2000_n reads).
struct LabImage {
  int width = 0, height = 0;
  NoFillVector<double> L, a, b;
};
LabImage lab_image(const Image& xyz);
// Equals ciede2000_map(test_xyz, ref_xyz) exactly for ref_lab = lab_image(ref_xyz).
Image ciede2000_map(const Image& test_xyz, const LabImage& ref_lab);

}  // namespace glintlab::metrics

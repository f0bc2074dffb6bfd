// CIEDE2000 colour difference: G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 Color-Difference Formula:
// Implementation Notes, Supplementary Test Data, and Mathematical Observations", Color Res. Appl. 30(1),
// 2005. Lab is CIE 1976 L*a*b* relative to the D65 white XYZ (0.95047, 1.0, 1.08883) (CIE 1931 2 deg),
// Y = 1 being that white. ΔE00 is display-referred: values of Y far above 1 give L* > 100 (no clamping).
#pragma once

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

// CIE 15:2004 eq. 8.3, the L*a*b* companding of a white-relative tristimulus
// value: t^(1/3) above (6/29)^3, linear below (also for negative t: no cube
// root of a negative is taken).
double lab_f(double t);

// CIE 1976 L*a*b* of XYZ (Y = 1 white) relative to the D65 white above (CIE 15:2004 eq. 8.1-8.3).
Lab xyz_to_lab(double X, double Y, double Z);

// ΔE00 (Sharma et al. 2005, steps 1-3). Symmetric in its arguments.
double ciede2000(const Lab& lab1, const Lab& lab2, double kL = 1.0, double kC = 1.0, double kH = 1.0);

// Per-pixel ΔE00 between two CIE XYZ images (first three channels), 1 channel, same size.
Image ciede2000_map(const Image& test_xyz, const Image& ref_xyz);

}  // namespace glintlab::metrics

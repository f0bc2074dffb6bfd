// Plain per-pixel error on the luminance Y (channel 1 of a CIE XYZ image): MSE, MAE, PSNR and the HDR
// relative error. Names say exactly what is computed (no "mae" that is really an MSE).
//
// Conventions shared by every metric in glintlab::metrics:
//  - inputs are CIE XYZ (D65), Y = 1 is the reference (diffuse) white, >= 3 channels (the first three are
//    X, Y, Z; further channels such as alpha are ignored);
//  - test and reference must have the same width and height (std::invalid_argument otherwise);
//  - non-finite inputs are not hidden: they propagate to the result (scan_pixels counts them).
#pragma once

#include "core/util/image.h"

namespace glintlab::metrics {

// eps of the HDR relative error |Y_t - Y_r| / (max(Y_r, 0) + eps).
constexpr double kRelativeErrorEpsilon = 1e-2;

// Throws std::invalid_argument naming `who` and both sizes when the images differ in size, or when
// either has fewer than 3 channels.
void require_same_size(const Image& test, const Image& ref, const char* who);
// For a reference converted once (HDR-FLIP, ΔE00, ΔE_ITP): throws std::invalid_argument naming `who`
// unless the test image is ref_width x ref_height with >= 3 channels.
void require_reference_size(const Image& test, int ref_width, int ref_height, const char* who);

// Y channel (index 1) of a CIE XYZ image as a 1-channel image.
Image luminance(const Image& xyz);

// Per-pixel (Y_t - Y_r)^2, 1 channel.
Image squared_error_map(const Image& test_xyz, const Image& ref_xyz);
// mean over pixels of (Y_t - Y_r)^2.
double mean_squared_error_y(const Image& test_xyz, const Image& ref_xyz);
// mean over pixels and the first three channels of |c_t - c_r|.
double mean_absolute_error_channels(const Image& test, const Image& ref);

// PSNR in dB of the luminance Y: 10 log10(peak^2 / MSE_Y), no clamping of Y (HDR values allowed).
// Identical images (MSE_Y == 0) give +infinity; peak must be > 0.
double psnr_from_mse(double mse, double peak);
double psnr_y(const Image& test_xyz, const Image& ref_xyz, double peak = 1.0);

// HDR relative error per pixel: |Y_t - Y_r| / (max(Y_r, 0) + eps), 1 channel. The max(.,0) keeps the
// denominator >= eps when a broken reference pixel is negative.
Image relative_error_map(const Image& test_xyz, const Image& ref_xyz, double eps = kRelativeErrorEpsilon);
// Channel variant: mean over the first three channels of |c_t - c_r| / (max(c_r, 0) + eps), 1 channel.
Image relative_error_channels_map(const Image& test, const Image& ref, double eps = kRelativeErrorEpsilon);

}  // namespace glintlab::metrics

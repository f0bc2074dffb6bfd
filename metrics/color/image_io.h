// Image files through OpenImageIO. Reads anything OIIO reads into RGBA float; writes scene-linear
// EXR (with chromaticities) and display-encoded 8-bit PNG. Every write is atomic: the file is
// written as `path.tmp-<pid>` in the same directory and renamed, so a crash never leaves half a file.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/util/image.h"

namespace glintlab::metrics {

// The largest image a header may claim before anything is allocated (64 Mpix; 8K UHD is 33 Mpix).
inline constexpr long long kMaxImagePixels = 64LL << 20;

// Only regular files are read (a FIFO or a device is never opened: it could block for ever):
// std::invalid_argument for anything else, for a path that names no file and for a header above
// kMaxImagePixels (bad input), IoError with the system's reason when an existing file cannot be opened.
void check_image_file(const std::string& path);

// Reads the first subimage as RGBA float (alpha 1 if absent; grey -> R = G = B). If colorspace_tag
// is given it receives the file's `oiio:ColorSpace` metadata ("" if none). Throws
// std::runtime_error naming the file (after check_image_file's checks).
// If file_channels is given it receives the file's channel count (1: grey; 2: grey + alpha).
Image read_image(const std::string& path, std::string* colorspace_tag = nullptr, int* file_channels = nullptr);

// Scene-linear float (or half) OpenEXR with the `chromaticities` attribute (Rx Ry Gx Gy Bx By Wx Wy,
// see ColorManager::chromaticities). Channels: 1 -> "Y", 2 -> "Y","A", 3 -> RGB, 4 -> RGBA.
void write_exr(const std::string& path, const Image& img, const std::array<float, 8>& chromaticities,
               bool half = false);

// Non-colour data (error maps, masks) as float/half OpenEXR without a chromaticities attribute.
// Channels named as for write_exr (a one-channel map is "Y"), or `names`, one per channel (no alpha).
void write_exr_data(const std::string& path, const Image& img, bool half = false,
                    const std::vector<std::string>& names = {});

// 8-bit PNG of display-encoded values (e.g. ColorManager::display output): each value is clamped
// to [0, 1] (NaN -> 0) and quantised with rounding, q = round(255 v). No transfer curve is applied.
// 1, 2, 3 or 4 channels.
void write_png(const std::string& path, const Image& display_encoded);

}  // namespace glintlab::metrics

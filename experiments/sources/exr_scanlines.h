// The fast way in for the files `glintlab measure` reads most: OpenEXR scanline
// files, uncompressed or ZIP / ZIPS (what Blender, Nuke and OpenImageIO write by
// default). The OpenEXR core library (libOpenEXRCore) parses the header and
// reads each chunk's bytes; libdeflate inflates them (several times faster than
// zlib, which OpenEXR 3.1 uses); the format's own byte predictor and interleave
// are undone here; halves become floats straight into the image. Everything
// else (tiled, deep, subsampled or UINT channels, PIZ, DWA, ... and every other
// format) is left to OpenImageIO by returning false. Same values either way: a
// test compares both on every case.
#pragma once

#include "core/util/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace glintlab {

// Reads the named channels (each from the first part, in file order, of size
// width x height whose channel list has it) into `out` (width x height x
// image_channels floats, any values): channel k of every pixel from
// channels[k], the channels after them 1. Returns true when every value is
// written; false when the file is not one this path reads, or is damaged: then
// read it with OpenImageIO, which names what is wrong with a damaged file.
bool read_exr_scanlines(const std::string& path, const std::vector<std::string>& channels, Image& out);

// The float of an IEEE 754 binary16 (OpenEXR's half), exactly, infinities and NaN payloads kept: what
// reads half channels on a processor without F16C.
float half_bits_to_float(std::uint16_t bits);

// What makes the OpenEXR file at `path` incomplete, "" when nothing does: every chunk of every
// scanline part must lie within the file (a file cut short, as a writer killed mid-write leaves it,
// has chunks that end past its end or a table of chunks that cannot be read). Reads only the table
// and each chunk's few header bytes. "" too for a file OpenEXRCore does not open (not an OpenEXR
// file: its reader names what is wrong) and for tiled and deep parts (not checked).
std::string exr_chunk_problem(const std::string& path);

// The header of a one-part OpenEXR file as OpenImageIO 2.4 describes it, for a file with one
// scanline part whose data window is its display window at (0, 0), whose channels are half or float,
// not subsampled and not luminance-chroma (Y, BY, RY), and which has no attribute named oiio:*: its
// size and every channel's name, in OpenImageIO's order (by layer, the name up to its last '.'; in a
// layer R, G, B, Y, A, Z, ... first, X, Y, Z together where the layer has X and Y or Z; then by name),
// with the colour space kExrColorSpace, which its OpenEXR reader gives every file. False for any other
// file (then ask OpenImageIO). No pixel is read. A Blender multilayer frame is such a file.
struct ExrLayout {
  int width = 0, height = 0;
  std::vector<std::string> channels;
};
bool read_exr_layout(const std::string& path, ExrLayout* layout);

// The header of a plain OpenEXR file: an ExrLayout whose channels are exactly R, G, B[, A] or Y[, A]
// (what read_image_file reads without OpenImageIO).
struct SimpleExrHeader {
  int width = 0, height = 0;
  std::vector<std::string> channels;
};
inline constexpr const char* kExrColorSpace = "Linear";
bool read_simple_exr_header(const std::string& path, SimpleExrHeader* header);

// metrics::read_image (metrics/color/image_io.h), the same image, colour-space tag, channel count and
// errors, with a plain OpenEXR file whose pixels read_exr_scanlines reads, and an sRGB PNG
// (experiments/sources/png_file.h), taken without OpenImageIO.
Image read_image_file(const std::string& path, std::string* colorspace_tag = nullptr, int* file_channels = nullptr);

}  // namespace glintlab

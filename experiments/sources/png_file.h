// The fast way in for PNG files, the other format `glintlab compare` is
// given most: libpng reads 8- and 16-bit PNGs whose colour is sRGB (an sRGB
// chunk, or no gAMA, cHRM or iCCP chunk at all) without OpenImageIO and the
// few hundred libraries it loads. The image is what OpenImageIO 2.4 gives for
// such a file (a test compares both on every colour type and depth): RGBA
// floats, code values / (2^bits - 1), palette and low-bit grey expanded to 8
// bits, a tRNS chunk as alpha, alpha as stored (not premultiplied), grey
// copied to R, G and B, alpha 1 where the file has none; the colour-space tag
// "sRGB"; the file's channel count after that expansion. Any other PNG (a
// gamma, chromaticities or an ICC profile), and every damaged file, is left to
// OpenImageIO by returning false.
#pragma once

#include "core/util/image.h"

#include <string>

namespace glintlab {

// True when `path` is a PNG this path reads and `out`, `colorspace_tag` and
// `file_channels` are set; false (nothing set) otherwise.
bool read_plain_png(const std::string& path, Image& out, std::string* colorspace_tag, int* file_channels);

}  // namespace glintlab

#include "experiments/sources/png_file.h"

#include "metrics/color/image_io.h"

#include <dlfcn.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

namespace glintlab {

namespace {

// libpng's functions, opened with dlopen by the first PNG read rather than linked: a command that reads
// no PNG (`compare` of OpenEXR files, `check`) never loads libpng and zlib, two libraries fewer at every
// start. Each member has the type and name of the function png.h declares.
#define GLINTLAB_PNG_FUNCTIONS(X)                                                                          \
  X(png_sig_cmp) X(png_create_read_struct) X(png_create_info_struct) X(png_destroy_read_struct)           \
  X(png_set_longjmp_fn) X(png_longjmp) X(png_init_io) X(png_set_sig_bytes) X(png_read_info) X(png_get_valid) \
  X(png_get_image_width) X(png_get_image_height) X(png_set_expand) X(png_get_bit_depth) X(png_set_swap)   \
  X(png_set_interlace_handling) X(png_read_update_info) X(png_get_channels) X(png_get_rowbytes)          \
  X(png_read_image) X(png_read_end)
struct Png {
#define GLINTLAB_PNG_MEMBER(f) decltype(&::f) f = nullptr;
  GLINTLAB_PNG_FUNCTIONS(GLINTLAB_PNG_MEMBER)
#undef GLINTLAB_PNG_MEMBER
};

// The functions of libpng16.so.16, loaded once; nullptr where it cannot be loaded (the file is then
// left to OpenImageIO, as every PNG this path does not read is).
const Png* libpng() {
  static const Png* const loaded = [] () -> const Png* {
    void* lib = ::dlopen("libpng16.so.16", RTLD_NOW | RTLD_LOCAL);
    if (!lib) return nullptr;
    static Png p;
#define GLINTLAB_PNG_LOAD(f) \
  if (!(p.f = reinterpret_cast<decltype(p.f)>(::dlsym(lib, #f)))) return nullptr;
    GLINTLAB_PNG_FUNCTIONS(GLINTLAB_PNG_LOAD)
#undef GLINTLAB_PNG_LOAD
    return &p;
  }();
  return loaded;
}

struct File {
  std::FILE* f = nullptr;
  ~File() {
    if (f) std::fclose(f);
  }
};

struct Reader {
  const Png& lib;
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~Reader() { lib.png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

// libpng reports an error by this function's longjmp to the setjmp of read_plain_png (which
// declines the file: OpenImageIO then names what is wrong); warnings are not errors here.
[[noreturn]] void on_error(png_structp png, png_const_charp) {
  libpng()->png_longjmp(png, 1);
  std::abort();  // (png_longjmp does not return)
}
void on_warning(png_structp, png_const_charp) {}

}  // namespace

bool read_plain_png(const std::string& path, Image& out, std::string* colorspace_tag, int* file_channels) {
  File file;
  file.f = std::fopen(path.c_str(), "rb");
  if (!file.f) return false;
  const Png* lib = libpng();
  if (!lib) return false;
  const Png& P = *lib;
  unsigned char sig[8];
  if (std::fread(sig, 1, 8, file.f) != 8 || P.png_sig_cmp(sig, 0, 8) != 0) return false;
  Reader r{P};
  r.png = P.png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, on_error, on_warning);
  if (!r.png) return false;
  r.info = P.png_create_info_struct(r.png);
  if (!r.info) return false;
  // Declared before setjmp and not changed between it and a longjmp, as setjmp requires.
  std::vector<unsigned char> pixels;
  std::vector<png_bytep> rows;
  // png_jmpbuf(r.png), through the loaded function; a damaged file: OpenImageIO names what is wrong
  if (setjmp(*P.png_set_longjmp_fn(r.png, std::longjmp, sizeof(std::jmp_buf)))) return false;
  P.png_init_io(r.png, file.f);
  P.png_set_sig_bytes(r.png, 8);
  P.png_read_info(r.png, r.info);
  const bool srgb = P.png_get_valid(r.png, r.info, PNG_INFO_sRGB) != 0;
  const bool described = P.png_get_valid(r.png, r.info, PNG_INFO_gAMA | PNG_INFO_cHRM | PNG_INFO_iCCP) != 0;
  if (!srgb && described) return false;
  const png_uint_32 w = P.png_get_image_width(r.png, r.info), h = P.png_get_image_height(r.png, r.info);
  if (w == 0 || h == 0 || (long long)w * h > metrics::kMaxImagePixels) return false;
  P.png_set_expand(r.png);  // palette -> RGB, grey < 8 bits -> 8 bits, tRNS -> alpha
  if (P.png_get_bit_depth(r.png, r.info) == 16) P.png_set_swap(r.png);  // host (little-endian) order
  P.png_set_interlace_handling(r.png);
  P.png_read_update_info(r.png, r.info);
  const int n = P.png_get_channels(r.png, r.info);
  const int depth = P.png_get_bit_depth(r.png, r.info);
  if (n < 1 || n > 4 || (depth != 8 && depth != 16)) return false;
  const size_t row_bytes = P.png_get_rowbytes(r.png, r.info);
  pixels.resize(row_bytes * h);
  rows.resize(h);
  for (png_uint_32 y = 0; y < h; ++y) rows[y] = pixels.data() + y * row_bytes;
  P.png_read_image(r.png, rows.data());
  P.png_read_end(r.png, nullptr);

  Image img = Image::unfilled(int(w), int(h), 4);
  const float scale = depth == 16 ? 1.0f / 65535.0f : 1.0f / 255.0f;
  auto value = [&](const unsigned char* row, size_t k) {
    return depth == 16 ? float(reinterpret_cast<const uint16_t*>(row)[k]) * scale : float(row[k]) * scale;
  };
  for (png_uint_32 y = 0; y < h; ++y)
    for (png_uint_32 x = 0; x < w; ++x) {
      float* d = img.data.data() + (size_t(y) * w + x) * 4;
      const size_t s = size_t(x) * size_t(n);
      if (n >= 3) {
        d[0] = value(rows[y], s), d[1] = value(rows[y], s + 1), d[2] = value(rows[y], s + 2);
      } else {
        d[0] = d[1] = d[2] = value(rows[y], s);
      }
      d[3] = n == 2 ? value(rows[y], s + 1) : n == 4 ? value(rows[y], s + 3) : 1.0f;
    }
  out = std::move(img);
  if (colorspace_tag) *colorspace_tag = "sRGB";
  if (file_channels) *file_channels = n;
  return true;
}

}  // namespace glintlab

#include "experiments/sources/exr_scanlines.h"
#include "experiments/sources/png_file.h"

#include "metrics/color/image_io.h"

#include <OpenEXR/openexr.h>
#include <libdeflate.h>

#include <algorithm>
#include <iterator>
#include <cstdint>
#include <cstring>
#include <strings.h>
#include <string>
#include <sys/stat.h>
#include <utility>
#include <vector>
#if defined(__x86_64__)
#include <cpuid.h>
#include <immintrin.h>
#endif

namespace glintlab {
namespace {

// The OpenEXR core library reports errors through this; they are not printed: a file this path
// cannot read goes to OpenImageIO, whose message names what is wrong.
void quiet(exr_const_context_t, exr_result_t, const char*) {}

struct Context {
  exr_context_t c = nullptr;
  ~Context() {
    if (c) exr_finish(&c);
  }
};

struct Inflater {
  libdeflate_decompressor* d = libdeflate_alloc_decompressor();
  ~Inflater() { libdeflate_free_decompressor(d); }
};

// Undoes what OpenEXR's ZIP and ZIPS compressors do after deflate's inverse (the file format's
// definition; OpenEXR's internal_zip.c): a byte predictor (each byte stored as the difference to
// the one before, plus 128) over the whole chunk, then the two halves of the chunk interleaved
// (byte 2i from the first half, 2i+1 from the second).
// Each has a scalar loop and, where SSE2 is there (every x86-64), a loop over 16 bytes at a time
// before it that computes the same bytes: the predictor as a prefix sum within the register, plus
// the running sum of the blocks before (`carry`, in every byte). Only that one add is carried from
// block to block, so the blocks' prefix sums overlap in the CPU.
void undo_zip_predictor(std::uint8_t* t, size_t n) {
  size_t i = 1;
#if defined(__SSE2__)
  if (n >= 17) {
    const __m128i bias = _mm_set1_epi8(char(-128));
    __m128i carry = _mm_set1_epi8(char(t[0]));
    for (; i + 16 <= n; i += 16) {
      __m128i x = _mm_add_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(t + i)), bias);
      x = _mm_add_epi8(x, _mm_slli_si128(x, 1));
      x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
      x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
      x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(t + i), _mm_add_epi8(x, carry));
      const __m128i last = _mm_unpacklo_epi8(_mm_srli_si128(x, 15), _mm_srli_si128(x, 15));  // byte 15, twice
      carry = _mm_add_epi8(carry, _mm_shuffle_epi32(_mm_shufflelo_epi16(last, 0), 0));      // in every byte
    }
  }
#endif
  for (; i < n; ++i) t[i] = std::uint8_t(int(t[i - 1]) + int(t[i]) - 128);
}
void deinterleave(const std::uint8_t* in, std::uint8_t* out, size_t n) {
  const std::uint8_t* a = in;
  const std::uint8_t* b = in + (n + 1) / 2;
  size_t i = 0;
#if defined(__SSE2__)
  for (; i + 32 <= n; i += 32, a += 16, b += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a));
    const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_unpacklo_epi8(x, y));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i + 16), _mm_unpackhi_epi8(x, y));
  }
#endif
  for (; i + 1 < n; i += 2) out[i] = *a++, out[i + 1] = *b++;
  if (i < n) out[i] = *a;
}

#if defined(__x86_64__)
// Whether the CPU converts halves (F16C) and the OS saves the AVX registers it uses, from CPUID
// (clang 14's __builtin_cpu_supports does not know "f16c").
bool cpu_has_f16c() {
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(1, &a, &b, &c, &d) || !(c & bit_F16C) || !(c & bit_OSXSAVE)) return false;
  unsigned lo = 0, hi = 0;
  __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  return (lo & 6) == 6;  // XMM and YMM state
}
#endif

// n halves (little-endian bits) to floats at dst[0], dst[stride], ...: with F16C where the CPU has it.
#if defined(__x86_64__)
__attribute__((target("f16c"))) void halves_to_floats_f16c(const std::uint8_t* src, float* dst, size_t stride,
                                                           size_t n) {
  size_t x = 0;
  alignas(16) float f[8];
  for (; x + 8 <= n; x += 8) {
    _mm256_store_ps(f, _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(src + 2 * x))));
    for (size_t j = 0; j < 8; ++j) dst[(x + j) * stride] = f[j];
  }
  for (; x < n; ++x) dst[x * stride] = _cvtsh_ss(std::uint16_t(src[2 * x] | (src[2 * x + 1] << 8)));
}
#endif
void halves_to_floats(const std::uint8_t* src, float* dst, size_t stride, size_t n) {
#if defined(__x86_64__)
  static const bool f16c = cpu_has_f16c();
  if (f16c) return halves_to_floats_f16c(src, dst, stride, n);
#endif
  for (size_t x = 0; x < n; ++x) dst[x * stride] = half_bits_to_float(std::uint16_t(src[2 * x] | (src[2 * x + 1] << 8)));
}

// The common layout: a line's planes (one per channel) to the four channels of RGBA pixels, four
// pixels at a time (4 x 4 transposes). src[c] is channel c's plane of w samples (a plane of ones for
// the alpha under R, G, B: no read of what the image holds there), or nullptr to keep what the pixels
// hold in that channel (one another part of the file gives). Moves and shuffles only: the bits.
#if defined(__x86_64__)
inline __m128 kept(const float* px, int c) { return _mm_setr_ps(px[c], px[4 + c], px[8 + c], px[12 + c]); }
void float_planes_to_rgba(const std::uint8_t* const src[4], float* dst, size_t w) {
  size_t x = 0;
  for (; x + 4 <= w; x += 4) {
    float* px = dst + 4 * x;
    __m128 v[4];
    for (int c = 0; c < 4; ++c)
      v[c] = src[c] ? _mm_loadu_ps(reinterpret_cast<const float*>(src[c] + 4 * x)) : kept(px, c);
    _MM_TRANSPOSE4_PS(v[0], v[1], v[2], v[3]);
    for (int j = 0; j < 4; ++j) _mm_storeu_ps(px + 4 * j, v[j]);
  }
  for (; x < w; ++x)
    for (int c = 0; c < 4; ++c)
      if (src[c]) std::memcpy(dst + 4 * x + c, src[c] + 4 * x, 4);
}
__attribute__((target("f16c"))) void half_planes_to_rgba_f16c(const std::uint8_t* const src[4], float* dst, size_t w) {
  size_t x = 0;
  for (; x + 4 <= w; x += 4) {
    float* px = dst + 4 * x;
    __m128 v[4];
    for (int c = 0; c < 4; ++c)
      v[c] = src[c] ? _mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(src[c] + 2 * x))) : kept(px, c);
    _MM_TRANSPOSE4_PS(v[0], v[1], v[2], v[3]);
    for (int j = 0; j < 4; ++j) _mm_storeu_ps(px + 4 * j, v[j]);
  }
  for (; x < w; ++x)
    for (int c = 0; c < 4; ++c)
      if (src[c]) dst[4 * x + c] = _cvtsh_ss(std::uint16_t(src[c][2 * x] | (src[c][2 * x + 1] << 8)));
}
#endif

constexpr float kOne = 1.0f;

struct Wanted {
  int channel = 0;     // index in the part's (alphabetical) channel list
  size_t image_channel = 0;
  exr_pixel_type_t type = EXR_PIXEL_HALF;
};

// Whether this host is little-endian (the file's byte order): only such hosts take this path.
bool little_endian_host() {
  const std::uint16_t one = 1;
  std::uint8_t b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

// Opens the regular file at `path` for reading its header and chunks; its size bounds every chunk.
bool open_exr(const std::string& path, Context& ctx, std::uint64_t& file_size) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  file_size = std::uint64_t(st.st_size);
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet;
  return exr_start_read(&ctx.c, path.c_str(), &init) == EXR_ERR_SUCCESS;
}

// Which part gives which channel (plan[p]: part p's), as OpenImageIO's path: the first part of the
// image's size that has it. False where a channel is missing or subsampled, or neither half nor float.
bool plan_channels(exr_const_context_t c, int parts, const std::vector<std::string>& channels, const Image& out,
                   std::vector<std::vector<Wanted>>& plan) {
  plan.assign(static_cast<size_t>(parts), {});
  std::vector<bool> found(channels.size(), false);
  for (int p = 0; p < parts; ++p) {
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t* list = nullptr;
    if (exr_get_data_window(c, p, &dw) != EXR_ERR_SUCCESS || exr_get_channels(c, p, &list) != EXR_ERR_SUCCESS)
      return false;
    if (std::int64_t(dw.max.x) - dw.min.x + 1 != out.width || std::int64_t(dw.max.y) - dw.min.y + 1 != out.height)
      continue;
    for (size_t k = 0; k < channels.size(); ++k)
      for (int ch = 0; ch < list->num_channels && !found[k]; ++ch) {
        const exr_attr_chlist_entry_t& e = list->entries[ch];
        if (channels[k].size() != size_t(e.name.length) ||
            std::memcmp(channels[k].data(), e.name.str, channels[k].size()) != 0)
          continue;
        if (e.x_sampling != 1 || e.y_sampling != 1 || (e.pixel_type != EXR_PIXEL_HALF && e.pixel_type != EXR_PIXEL_FLOAT))
          return false;
        plan[size_t(p)].push_back({ch, k, e.pixel_type});
        found[k] = true;
      }
  }
  for (bool f : found)
    if (!f) return false;  // OpenImageIO's path names the missing channel
  return true;
}

// How one part stores its lines.
struct PartLayout {
  exr_compression_t comp = EXR_COMPRESSION_NONE;
  exr_attr_box2i_t dw{};
  int32_t lines = 0;           // per chunk
  std::vector<size_t> offset;  // where channel c's samples start in one uncompressed line
  size_t line_bytes = 0;       // one uncompressed line: each channel's samples in turn, in the list's order
};

// The layout of part p, w pixels wide; false unless it is scanlines, uncompressed or ZIP / ZIPS.
bool read_part_layout(exr_const_context_t c, int p, size_t w, PartLayout& part) {
  exr_storage_t storage;
  const exr_attr_chlist_t* list = nullptr;
  if (exr_get_storage(c, p, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE ||
      exr_get_compression(c, p, &part.comp) != EXR_ERR_SUCCESS ||
      (part.comp != EXR_COMPRESSION_NONE && part.comp != EXR_COMPRESSION_ZIPS && part.comp != EXR_COMPRESSION_ZIP) ||
      exr_get_data_window(c, p, &part.dw) != EXR_ERR_SUCCESS || exr_get_channels(c, p, &list) != EXR_ERR_SUCCESS ||
      exr_get_scanlines_per_chunk(c, p, &part.lines) != EXR_ERR_SUCCESS || part.lines <= 0)
    return false;
  part.offset.assign(size_t(list->num_channels) + 1, 0);
  for (int ch = 0; ch < list->num_channels; ++ch)
    part.offset[size_t(ch) + 1] = part.offset[size_t(ch)] + w * (list->entries[ch].pixel_type == EXR_PIXEL_HALF ? 2 : 4);
  part.line_bytes = part.offset.back();
  return true;
}

// How one part's lines become the image's pixels: the transposing copy where three or four channels
// of one type go into an RGBA image (kFloat, kHalf), else one channel at a time (kNo).
enum class Rgba { kNo, kFloat, kHalf };
struct LineCopy {
  const std::vector<Wanted>& want;    // the channels the part gives
  const std::vector<size_t>& offset;  // of PartLayout
  size_t named, w, nc;                // the channels named; the image's width and channels
  Rgba rgba = Rgba::kNo;
  std::vector<std::uint8_t> ones;  // a line of 1.0 in the part's type: the channels after the named ones
};

// The copy of a part's lines, for the transposing copy where the CPU has it.
LineCopy line_copy(const std::vector<Wanted>& want, const PartLayout& part, size_t named, size_t w, size_t nc) {
  LineCopy copy{want, part.offset, named, w, nc};
#if defined(__x86_64__)
  static const bool f16c = cpu_has_f16c();
  bool one_type = nc == 4 && want.size() >= 3;
  for (const Wanted& x : want) one_type = one_type && x.type == want[0].type;
  if (one_type) copy.rgba = want[0].type == EXR_PIXEL_FLOAT ? Rgba::kFloat : f16c ? Rgba::kHalf : Rgba::kNo;
#endif
  if (copy.rgba == Rgba::kFloat) {
    copy.ones.resize(4 * w);
    for (size_t x = 0; x < w; ++x) std::memcpy(&copy.ones[4 * x], &kOne, 4);
  } else if (copy.rgba == Rgba::kHalf) {
    copy.ones.resize(2 * w);
    for (size_t x = 0; x < w; ++x) copy.ones[2 * x] = 0x00, copy.ones[2 * x + 1] = 0x3c;  // half 1.0, little-endian
  }
  return copy;
}

// One line of a part (its channels' planes at `line`) into the image row `row`.
void copy_line(const LineCopy& copy, const std::uint8_t* line, float* row) {
#if defined(__x86_64__)
  if (copy.rgba != Rgba::kNo) {
    const std::uint8_t* src[4] = {nullptr, nullptr, nullptr, nullptr};
    for (size_t c = copy.named; c < 4; ++c) src[c] = copy.ones.data();
    for (const Wanted& want : copy.want) src[want.image_channel] = line + copy.offset[size_t(want.channel)];
    if (copy.rgba == Rgba::kFloat) float_planes_to_rgba(src, row, copy.w);
    else half_planes_to_rgba_f16c(src, row, copy.w);
    return;
  }
#endif
  for (const Wanted& want : copy.want) {
    const std::uint8_t* src = line + copy.offset[size_t(want.channel)];
    float* dst = row + want.image_channel;
    if (want.type == EXR_PIXEL_FLOAT) {
      for (size_t x = 0; x < copy.w; ++x) std::memcpy(dst + x * copy.nc, src + 4 * x, 4);
    } else {
      halves_to_floats(src, dst, copy.nc, copy.w);
    }
  }
}

// The buffers of a chunk's bytes, reused from chunk to chunk.
struct ChunkBytes {
  std::vector<std::uint8_t> packed, inflated, unpacked;
};

// Reads the chunk of part p that holds line y0: its info, the data window's lines first .. last in it,
// and its bytes as stored (into bytes.packed). False where the chunk's sizes do not fit the part or
// the file.
bool read_chunk(exr_const_context_t c, int p, std::int64_t y0, const PartLayout& part, std::uint64_t file_size,
                exr_chunk_info_t& ci, std::int64_t& first, std::int64_t& last, ChunkBytes& bytes) {
  if (exr_read_scanline_chunk_info(c, p, int(y0), &ci) != EXR_ERR_SUCCESS) return false;
  first = std::max<std::int64_t>(ci.start_y, part.dw.min.y);
  last = std::min<std::int64_t>(std::int64_t(ci.start_y) + ci.height - 1, part.dw.max.y);
  if (first > last || ci.unpacked_size != size_t(last - first + 1) * part.line_bytes || ci.packed_size > file_size ||
      ci.data_offset > file_size - ci.packed_size)
    return false;
  bytes.packed.resize(ci.packed_size);
  return exr_read_chunk(c, p, &ci, bytes.packed.data()) == EXR_ERR_SUCCESS;
}

// The chunk's uncompressed lines (`lines`): its stored bytes, or those inflated with the ZIP predictor
// and interleave undone. False where it does not inflate to its size.
bool unpack_chunk(exr_compression_t comp, const exr_chunk_info_t& ci, libdeflate_decompressor* inflater,
                  ChunkBytes& bytes, const std::uint8_t*& lines) {
  lines = bytes.packed.data();
  if (comp != EXR_COMPRESSION_NONE && ci.packed_size < ci.unpacked_size) {
    // smaller than its pixels: deflated (a chunk that would not shrink is stored as it is)
    bytes.inflated.resize(ci.unpacked_size);
    bytes.unpacked.resize(ci.unpacked_size);
    size_t got = 0;
    if (libdeflate_zlib_decompress(inflater, bytes.packed.data(), bytes.packed.size(), bytes.inflated.data(),
                                   bytes.inflated.size(), &got) != LIBDEFLATE_SUCCESS ||
        got != ci.unpacked_size)
      return false;
    undo_zip_predictor(bytes.inflated.data(), bytes.inflated.size());
    deinterleave(bytes.inflated.data(), bytes.unpacked.data(), bytes.unpacked.size());
    lines = bytes.unpacked.data();
    return true;
  }
  return ci.packed_size == ci.unpacked_size;
}

// Every chunk of part p, decoded and copied line by line into `out`.
bool read_part(exr_const_context_t c, int p, const PartLayout& part, const LineCopy& copy, std::uint64_t file_size,
               libdeflate_decompressor* inflater, ChunkBytes& bytes, Image& out) {
  for (std::int64_t y0 = part.dw.min.y; y0 <= part.dw.max.y; y0 += part.lines) {
    exr_chunk_info_t ci;
    std::int64_t first = 0, last = 0;
    const std::uint8_t* lines = nullptr;
    if (!read_chunk(c, p, y0, part, file_size, ci, first, last, bytes) ||
        !unpack_chunk(part.comp, ci, inflater, bytes, lines))
      return false;
    for (std::int64_t y = first; y <= last; ++y)
      copy_line(copy, lines + size_t(y - first) * part.line_bytes,
                out.data.data() + size_t(y - part.dw.min.y) * copy.w * copy.nc);
  }
  return true;
}

}  // namespace

float half_bits_to_float(std::uint16_t h) {
  const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16, exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  std::uint32_t bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // infinity, or NaN with its payload
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112u) << 23) | (mantissa << 13);  // rebias 15 -> 127
  } else {
    const float subnormal = float(mantissa) * 0x1p-24f;  // mantissa 2^-24 (or a zero), exact in float
    std::memcpy(&bits, &subnormal, 4);
    bits |= sign;
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

bool read_exr_scanlines(const std::string& path, const std::vector<std::string>& channels, Image& out) {
  if (!little_endian_host()) return false;
  Context ctx;
  std::uint64_t file_size = 0;
  int parts = 0;
  if (!open_exr(path, ctx, file_size) || exr_get_count(ctx.c, &parts) != EXR_ERR_SUCCESS) return false;
  std::vector<std::vector<Wanted>> plan;
  if (!plan_channels(ctx.c, parts, channels, out, plan)) return false;

  Inflater inflater;
  if (!inflater.d) return false;
  ChunkBytes bytes;
  const size_t nc = size_t(out.channels), w = size_t(out.width);
  bool ones_written = false;  // the channels after the named ones (a part read by the transposing copy writes them)
  for (int p = 0; p < parts; ++p) {
    if (plan[size_t(p)].empty()) continue;
    PartLayout part;
    if (!read_part_layout(ctx.c, p, w, part)) return false;
    const LineCopy copy = line_copy(plan[size_t(p)], part, channels.size(), w, nc);
    ones_written = ones_written || copy.rgba != Rgba::kNo;
    if (!read_part(ctx.c, p, part, copy, file_size, inflater.d, bytes, out)) return false;
  }
  if (!ones_written)
    for (size_t i = 0; i < out.pixel_count(); ++i)
      for (size_t c = channels.size(); c < nc; ++c) out.data[i * nc + c] = 1.0f;
  return true;
}

std::string exr_chunk_problem(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "";
  const std::uint64_t file_size = std::uint64_t(st.st_size);
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet;
  Context ctx;
  int parts = 0;
  if (exr_start_read(&ctx.c, path.c_str(), &init) != EXR_ERR_SUCCESS || exr_get_count(ctx.c, &parts) != EXR_ERR_SUCCESS)
    return "";
  for (int p = 0; p < parts; ++p) {
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    int32_t lines = 0;
    if (exr_get_storage(ctx.c, p, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE) continue;
    if (exr_get_data_window(ctx.c, p, &dw) != EXR_ERR_SUCCESS ||
        exr_get_scanlines_per_chunk(ctx.c, p, &lines) != EXR_ERR_SUCCESS || lines <= 0)
      return "part " + std::to_string(p) + " has no readable data window";
    for (std::int64_t y = dw.min.y; y <= dw.max.y; y += lines) {
      exr_chunk_info_t ci;
      const std::string chunk = "the chunk of line " + std::to_string(y) + " of part " + std::to_string(p);
      if (exr_read_scanline_chunk_info(ctx.c, p, int(y), &ci) != EXR_ERR_SUCCESS)
        return chunk + " cannot be found (the file is " + std::to_string(file_size) + " bytes)";
      if (ci.packed_size > file_size || ci.data_offset > file_size - ci.packed_size)
        return chunk + " ends at byte " + std::to_string(ci.data_offset + ci.packed_size) + ", past the end of the file (" +
               std::to_string(file_size) + " bytes)";
    }
  }
  return "";
}

namespace {

bool iequals(const std::string& a, const char* b) { return strcasecmp(a.c_str(), b) == 0; }

// OpenImageIO's split of a channel name: the layer up to and including its last '.', the suffix after.
std::pair<std::string, std::string> layer_and_suffix(const std::string& name) {
  const size_t dot = name.rfind('.');
  if (dot == std::string::npos) return {"", name};
  return {name.substr(0, dot + 1), name.substr(dot + 1)};
}

// OpenImageIO 2.4's order of an OpenEXR part's channels: by layer (the name up to and including its
// last '.'), within a layer by the rank of the names it knows (R, G, B, Y, A, Z, ... in any case;
// X, Y, Z together where the layer has X and Y or Z: a position or a normal), then by name.
struct ChannelRank {
  std::string name, layer, suffix;
  int special = 10000;
};
void order_as_openimageio(std::vector<std::string>& names) {
  static const char* const kUsual[] = {"R", "Red", "G", "Green", "B", "Blue", "Y", "real", "imag", "A",
                                       "Alpha", "AR", "RA", "AG", "GA", "AB", "BA", "Z", "Depth", "Zback"};
  static const char* const kXyz[] = {"R", "Red", "G", "Green", "B", "Blue", "X", "Y", "Z", "real", "imag",
                                     "A", "Alpha", "AR", "RA", "AG", "GA", "AB", "BA", "Depth", "Zback"};
  std::vector<ChannelRank> ranks;
  for (const auto& n : names) {
    auto [layer, suffix] = layer_and_suffix(n);
    ranks.push_back({n, std::move(layer), std::move(suffix)});
  }
  std::sort(ranks.begin(), ranks.end(), [](const ChannelRank& a, const ChannelRank& b) { return a.layer < b.layer; });
  for (auto begin = ranks.begin(); begin != ranks.end();) {
    auto end = begin;
    while (end != ranks.end() && end->layer == begin->layer) ++end;
    auto has = [&](const char* suffix) {
      return std::any_of(begin, end, [&](const ChannelRank& c) { return iequals(c.suffix, suffix); });
    };
    const bool xyz = has("X") && (has("Y") || has("Z"));
    const char* const* table = xyz ? kXyz : kUsual;
    const size_t known = xyz ? std::size(kXyz) : std::size(kUsual);
    for (auto c = begin; c != end; ++c) {
      for (size_t i = 0; i < known; ++i)
        if (iequals(c->suffix, table[i])) {
          c->special = int(i);
          break;
        }
    }
    std::sort(begin, end, [](const ChannelRank& a, const ChannelRank& b) {
      return a.special != b.special ? a.special < b.special : a.suffix < b.suffix;
    });
    begin = end;
  }
  for (size_t i = 0; i < names.size(); ++i) names[i] = ranks[i].name;
}

// Luminance-chroma (Y, BY, RY[, A or Alpha], nothing else): OpenImageIO converts it to RGB.
bool is_luminance_chroma(const std::vector<std::string>& names) {
  auto has = [&](const char* suffix) {
    return std::any_of(names.begin(), names.end(),
                       [&](const std::string& n) { return iequals(layer_and_suffix(n).second, suffix); });
  };
  if (names.size() < 3 || names.size() > 4 || !has("Y") || !has("BY") || !has("RY")) return false;
  return names.size() == 3 || has("A") || has("Alpha");
}

}  // namespace

bool read_exr_layout(const std::string& path, ExrLayout* h) {
  Context ctx;
  std::uint64_t file_size = 0;
  if (!open_exr(path, ctx, file_size)) return false;
  int parts = 0;
  exr_storage_t storage;
  exr_attr_box2i_t dw, disp;
  const exr_attr_chlist_t* list = nullptr;
  if (exr_get_count(ctx.c, &parts) != EXR_ERR_SUCCESS || parts != 1 ||
      exr_get_storage(ctx.c, 0, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE ||
      exr_get_data_window(ctx.c, 0, &dw) != EXR_ERR_SUCCESS ||
      exr_get_display_window(ctx.c, 0, &disp) != EXR_ERR_SUCCESS || dw.min.x != disp.min.x ||
      dw.min.y != disp.min.y || dw.max.x != disp.max.x || dw.max.y != disp.max.y || dw.min.x != 0 || dw.min.y != 0 ||
      exr_get_channels(ctx.c, 0, &list) != EXR_ERR_SUCCESS || list->num_channels < 1)
    return false;
  const std::int64_t w = std::int64_t(dw.max.x) + 1, hh = std::int64_t(dw.max.y) + 1;
  if (w < 1 || hh < 1 || w * hh > metrics::kMaxImagePixels) return false;
  std::vector<std::string> names;
  for (int c = 0; c < list->num_channels; ++c) {
    const exr_attr_chlist_entry_t& e = list->entries[c];
    if (e.x_sampling != 1 || e.y_sampling != 1 || (e.pixel_type != EXR_PIXEL_HALF && e.pixel_type != EXR_PIXEL_FLOAT))
      return false;
    names.emplace_back(e.name.str, size_t(e.name.length));
  }
  if (is_luminance_chroma(names)) return false;
  int count = 0;
  if (exr_get_attribute_count(ctx.c, 0, &count) != EXR_ERR_SUCCESS) return false;
  for (int i = 0; i < count; ++i) {
    const exr_attribute_t* a = nullptr;
    if (exr_get_attribute_by_index(ctx.c, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) != EXR_ERR_SUCCESS || !a || !a->name)
      return false;
    if (std::strncmp(a->name, "oiio:", 5) == 0) return false;  // OpenImageIO would read it as its own metadata
  }
  order_as_openimageio(names);
  h->width = int(w);
  h->height = int(hh);
  h->channels = std::move(names);
  return true;
}

bool read_simple_exr_header(const std::string& path, SimpleExrHeader* h) {
  ExrLayout layout;
  if (!read_exr_layout(path, &layout)) return false;
  static const std::vector<std::vector<std::string>> kPlain = {{"R", "G", "B"}, {"R", "G", "B", "A"}, {"Y"}, {"Y", "A"}};
  if (std::find(kPlain.begin(), kPlain.end(), layout.channels) == kPlain.end()) return false;
  h->width = layout.width;
  h->height = layout.height;
  h->channels = std::move(layout.channels);
  return true;
}

Image read_image_file(const std::string& path, std::string* colorspace_tag, int* file_channels) {
  metrics::check_image_file(path);
  SimpleExrHeader h;
  if (read_simple_exr_header(path, &h)) {
    const int n = int(h.channels.size());
    // As metrics::read_image: RGBA, grey copied to R, G and B, alpha 1 where the file has none.
    Image img = Image::unfilled(h.width, h.height, 4);
    bool read = false;
    if (n >= 3) {
      read = read_exr_scanlines(path, h.channels, img);  // R, G, B[, A]; a missing alpha is 1
    } else {
      Image grey = Image::unfilled(h.width, h.height, n);
      read = read_exr_scanlines(path, h.channels, grey);
      for (std::size_t i = 0; read && i < img.pixel_count(); ++i) {
        float* d = img.data.data() + 4 * i;
        d[0] = d[1] = d[2] = grey.data[i * std::size_t(n)];
        d[3] = n == 2 ? grey.data[i * 2 + 1] : 1.0f;
      }
    }
    if (read) {
      if (colorspace_tag) *colorspace_tag = kExrColorSpace;
      if (file_channels) *file_channels = n;
      return img;
    }
  }
  Image png;
  if (read_plain_png(path, png, colorspace_tag, file_channels)) return png;
  return metrics::read_image(path, colorspace_tag, file_channels);
}

}  // namespace glintlab

// libFuzzer harness: the image path of `glintlab compare` (glintlab::run_compare: OpenImageIO read,
// pixel scan, OCIO conversion to CIE XYZ, every metric of the registry, text/JSON/CSV/map output).
//
// Input: byte 0 selects the file type and the options, the rest is the image file:
//   bits 0-1  extension of the test file: 0 .exr, 1 .png, 2 .hdr, 3 .exr
//   bit 2     --flip-ldr              bit 3  --view sRGB/Standard (display-referred metrics)
//   bit 4     --json                  bit 5  --map <tmp>/map.exr
//   bit 6     --csv <tmp>/out.csv     bit 7  roles swapped: the fuzzed file is the reference
// The other image is a clean (finite, positive) float EXR of the fuzzed image's size, written once
// per size into the harness's temp directory. (With the fuzzed file as the reference, HDR-FLIP's
// exposure range comes from it.) Test images whose header says more than
// GLINTLAB_FUZZ_MAX_SIDE (default 64) pixels on a side or more than 16 channels are skipped
// (return -1) before run_compare, so every execution stays fast; so is an input over 64 KiB.
//
// Oracle (anything else is a finding, see fuzz_common.h): run_compare returns 0, 1 or 2 and throws
// nothing; with --json its output parses as JSON. ASan/UBSan/LSan reports, timeouts and
// out-of-memory are findings too.
//
// OpenImageIO tries every reader it has when the one of the extension cannot open a file
// (attribute "try_all_readers", as `glintlab compare` does); GLINTLAB_FUZZ_TRY_ALL_READERS=0
// restricts it to the EXR, PNG and HDR readers (OpenEXR, libpng and OIIO's RGBE code).

#include "experiments/cli/compare.h"
#include "core/util/image.h"
#include "tests/fuzz/fuzz_common.h"

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <utility>

using namespace glintlab_fuzz;

namespace {

constexpr size_t kMaxInput = 64 * 1024;
constexpr int kMaxChannels = 16;
const char* const kExt[4] = {".exr", ".png", ".hdr", ".exr"};

std::string g_dir;
int g_max_side = 64;
bool g_size_check = true;  // skip EXR/PNG files that declare more bytes than they have (see below)
std::map<std::pair<int, int>, std::string> g_refs;  // (w, h) -> reference file

struct Counts {
  unsigned long compared = 0, unreadable = 0, too_big = 0, size_check = 0;
  unsigned long rc[3] = {0, 0, 0};
} g_counts;

// Third-party exclusion (GLINTLAB_FUZZ_SIZE_CHECK=0 turns it off). Two decoders allocate the size a
// file declares before reading it, so a file of a few hundred bytes takes ~2 GiB and seconds inside
// OIIO's open -- an out-of-memory in the decoder, not in glintlab:
//   * OpenEXR 3.1.5 (Debian 12): a header attribute's declared size
//     (Imf_3_1::TypedAttribute<std::string>::readValueFrom <- Header::readFrom);
//   * libpng 1.6.39 as OIIO 2.4.7 uses it (no png_set_chunk_malloc_max): a chunk's declared length
//     (e.g. tEXt, in png_read_info <- OIIO PNG_pvt::read_info).
// Such inputs are skipped: false when data is an EXR or PNG (by content: OIIO tries every reader,
// whatever the extension) that declares an attribute or chunk more than kSlack bytes longer than
// the rest of the file (files merely cut short still run: their error paths are ours to test).
constexpr size_t kSlack = size_t(1) << 20;
uint32_t le32(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24; }
uint32_t be32(const uint8_t* p) { return uint32_t(p[3]) | uint32_t(p[2]) << 8 | uint32_t(p[1]) << 16 | uint32_t(p[0]) << 24; }

bool declared_sizes_plausible(const uint8_t* p, size_t n) {
  if (n >= 8 && std::memcmp(p, "\x89PNG\r\n\x1a\n", 8) == 0) {
    for (size_t i = 8; n - i >= 8;) {  // chunks: length, type, data, CRC
      const uint32_t len = be32(p + i);
      if (len > n - i - 8 + kSlack) return false;
      if (len > n - i - 8) return true;  // cut short
      i += 8 + size_t(len) + std::min<size_t>(4, n - i - 8 - len);
    }
    return true;
  }
  if (n < 8 || std::memcmp(p, "\x76\x2f\x31\x01", 4) != 0) return true;
  const bool multipart = p[5] & 0x10;  // EXR version field, bit 12
  size_t i = 8;
  while (i < n) {
    if (p[i] == 0) {  // end of a header; a multi-part file ends its header list with an empty one
      ++i;
      if (!multipart || (i < n && p[i] == 0)) return true;
      continue;
    }
    for (int field = 0; field < 2; ++field) {  // attribute name, type name
      const void* nul = std::memchr(p + i, 0, n - i);
      if (!nul) return true;
      i = size_t(static_cast<const uint8_t*>(nul) - p) + 1;
    }
    if (n - i < 4) return true;
    const uint32_t size = le32(p + i);
    i += 4;
    if (size > n - i + kSlack) return false;
    if (size > n - i) return true;  // cut short
    i += size;
  }
  return true;
}

const std::string& reference(int w, int h) {
  auto it = g_refs.find({w, h});
  if (it != g_refs.end()) return it->second;
  glintlab::Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = img.px(x, y);
      p[0] = 0.05f + 1.5f * float(x + 1) / float(w);  // HDR-ish, > 0, finite
      p[1] = 0.05f + 0.9f * float(y + 1) / float(h);
      p[2] = 0.2f + 0.1f * float((x + y) % 3);
    }
  // Tiled: OIIO 2.4 reads a scanline file through a 64 MiB conversion buffer whatever its size,
  // which ASan makes the slowest part of an execution; a tiled file is read without it.
  std::string path = g_dir + "/ref_" + std::to_string(w) + "x" + std::to_string(h) + ".exr";
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  spec.tile_width = spec.tile_height = 16;
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, img.data.data()) || !out->close()) {
    std::fprintf(stderr, "glintlab fuzz: cannot write the reference %s: %s\n", path.c_str(), OIIO::geterror().c_str());
    std::abort();
  }
  return g_refs.emplace(std::make_pair(w, h), path).first->second;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = make_temp_dir("compare");
  unsetenv("OCIO");  // the shipped config, whatever the environment says
  if (const char* s = std::getenv("GLINTLAB_FUZZ_MAX_SIDE")) g_max_side = std::max(1, std::atoi(s));
  const char* sc = std::getenv("GLINTLAB_FUZZ_SIZE_CHECK");
  g_size_check = !(sc && std::string(sc) == "0");
  const char* all = std::getenv("GLINTLAB_FUZZ_TRY_ALL_READERS");
  OIIO::attribute("try_all_readers", all && std::string(all) == "0" ? 0 : 1);
  OIIO::attribute("threads", 1);  // no thread pool fan-out for 64x64 images
  OIIO::attribute("exr_threads", 0);
  (void)reference(4, 4);
  std::atexit([] {
    std::fprintf(stderr,
                 "glintlab fuzz: compare: %lu compared (exit 0: %lu, 1: %lu, 2: %lu), %lu unreadable by the "
                 "pre-check, %lu skipped as larger than %dx%d or %d channels, %lu skipped for EXR/PNG sizes "
                 "larger than the file\n",
                 g_counts.compared, g_counts.rc[0], g_counts.rc[1], g_counts.rc[2], g_counts.unreadable,
                 g_counts.too_big, g_max_side, g_max_side, kMaxChannels, g_counts.size_check);
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > kMaxInput) return -1;
  if (g_size_check && !declared_sizes_plausible(data + 1, size - 1)) {
    ++g_counts.size_check;
    return -1;
  }
  const uint8_t sel = data[0];
  const std::string test = g_dir + "/test" + kExt[sel & 3];
  write_file(test, data + 1, size - 1);

  // The decoded size, from the header (OIIO's public API), to keep every run small.
  int w = 4, h = 4;
  {
    auto in = OIIO::ImageInput::open(test);
    if (in) {
      const OIIO::ImageSpec& spec = in->spec();
      if (spec.width > g_max_side || spec.height > g_max_side || spec.nchannels > kMaxChannels) {
        ++g_counts.too_big;
        return -1;
      }
      if (spec.width > 0 && spec.height > 0) w = spec.width, h = spec.height;
    } else {
      ++g_counts.unreadable;  // run_compare must say so (exit 2); the 4x4 image is enough for that
      (void)OIIO::geterror();
    }
  }

  glintlab::CompareOptions o;
  o.test = test;
  o.ref = reference(w, h);
  if (sel & 128) std::swap(o.test, o.ref);
  o.flip_ldr = sel & 4;
  if (sel & 8) o.display_view = "sRGB/Standard";
  o.json = sel & 16;
  if (sel & 32) o.map_path = g_dir + "/map.exr";
  if (sel & 64) o.csv_path = g_dir + "/out.csv";

  std::ostringstream out, err;
  int rc = -1;
  try {
    rc = glintlab::run_compare(o, out, err);
  } catch (...) {
    finding("exception", "run_compare threw " + current_exception_text() + " (stderr: " + err.str() + ")");
    return 0;
  }
  ++g_counts.compared;
  if (rc < 0 || rc > 2) {
    finding("exit-code", "run_compare returned " + std::to_string(rc) + "; expected 0, 1 or 2 (stderr: " + err.str() + ")");
    return 0;
  }
  ++g_counts.rc[rc];
  if (o.json && rc != 2) {
    try {
      (void)nlohmann::json::parse(out.str());
    } catch (const nlohmann::json::exception& e) {
      finding("json-output", std::string("compare --json printed invalid JSON: ") + e.what() + "\n" + out.str());
    }
  }
  return 0;
}

// The fast way into OpenEXR scanline files (experiments/sources/exr_scanlines.h) gives the values
// OpenImageIO gives, to the bit, for every layout it takes, and declines the others.
#include "experiments/sources/exr_scanlines.h"
#include "experiments/sources/sequence.h"

#include "tests/support/temp_dir.h"
#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

constexpr int kW = 37, kH = 35;  // odd: the vector loops' tails; 35 lines: a partial 16-line ZIP chunk

// Channels R, G, B, A, Z: smooth ramps (they compress), noise (it does not: stored as is), and
// NaN, Inf, negative, subnormal values.
std::vector<float> test_pixels(bool noise) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 4.0f);
  std::vector<float> px(size_t(kW) * kH * 5);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 5; ++c)
        px[(size_t(y) * kW + x) * 5 + c] = noise ? u(rng) : 0.01f * float(x + 2 * y) + 0.5f * float(c);
  const float special[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(), -2.5f, 6e-8f, -0.0f, 65504.0f};
  for (size_t k = 0; k < sizeof special / sizeof special[0]; ++k) px[(k * 131) % px.size()] = special[k];
  return px;
}

void write(const fs::path& path, const std::vector<float>& px, OIIO::TypeDesc type, const std::string& compression,
           int origin_x = 0, int origin_y = 0, bool tiled = false) {
  OIIO::ImageSpec spec(kW, kH, 5, type);
  spec.channelnames = {"R", "G", "B", "A", "Z"};
  spec.alpha_channel = 3;
  spec.z_channel = 4;
  spec.x = origin_x;
  spec.y = origin_y;
  spec.full_x = spec.full_y = 0;
  spec.full_width = kW + origin_x;
  spec.full_height = kH + origin_y;
  if (tiled) spec.tile_width = spec.tile_height = 16;
  spec.attribute("compression", compression);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// What OpenImageIO reads of the named channels of part `part`, as floats.
std::vector<std::vector<float>> oiio_channels(const fs::path& path, const std::vector<std::string>& names,
                                              int part = 0) {
  auto in = OIIO::ImageInput::open(path.string());
  EXPECT_TRUE(in && in->seek_subimage(part, 0));
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(part, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()));
  std::vector<std::vector<float>> out;
  for (const auto& n : names) {
    const int c = spec.channelindex(n);
    EXPECT_GE(c, 0) << n;
    std::vector<float> v(size_t(spec.width) * spec.height);
    for (size_t i = 0; i < v.size(); ++i) v[i] = all[i * size_t(spec.nchannels) + size_t(c)];
    out.push_back(v);
  }
  return out;
}

// Every value of channel k of `im` has the bits of want[k]; the channels after them are still 1.
void expect_same_bits(const Image& im, const std::vector<std::vector<float>>& want, const std::string& what) {
  size_t differ = 0;
  for (size_t k = 0; k < want.size(); ++k)
    for (size_t i = 0; i < im.pixel_count(); ++i)
      differ += std::memcmp(&im.data[i * size_t(im.channels) + k], &want[k][i], 4) != 0;
  EXPECT_EQ(differ, 0u) << what;
  for (size_t i = 0; i < im.pixel_count(); ++i)
    for (int c = int(want.size()); c < im.channels; ++c) ASSERT_EQ(im.data[i * size_t(im.channels) + c], 1.0f) << what;
}

}  // namespace

TEST(ExrScanlines, SameBitsAsOpenImageIOForEveryLayoutItReads) {
  test::TempDir dir("exr_scanlines");
  // Not in file order, with a channel after alpha; the colour channels (alpha kept at 1); all four.
  // The last two take the transposing copy, the first the channel-by-channel one.
  const std::vector<std::vector<std::string>> name_sets = {{"B", "R", "Z"}, {"R", "G", "B"}, {"A", "B", "G", "R"}};
  int read = 0;
  for (const auto& names : name_sets)
    for (bool noise : {false, true})
      for (OIIO::TypeDesc type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT})
        for (const char* comp : {"none", "zip", "zips", "piz", "rle"})
          for (int origin : {0, 5}) {
            const std::string what = names[0] + names[1] + names[2] + " " + comp +
                                     (type == OIIO::TypeDesc::HALF ? " half" : " float") +
                                     (noise ? " noise" : " ramps") + " origin " + std::to_string(origin);
            const fs::path path = dir.path() / "f.exr";
            write(path, test_pixels(noise), type, comp, origin, origin / 2);
            Image im(kW, kH, 4, -7.0f);  // not what it reads: every value is written, the channels after the named 1
            const bool fast = read_exr_scanlines(path.string(), names, im);
            const bool supported =
                std::string(comp) == "none" || std::string(comp) == "zip" || std::string(comp) == "zips";
            EXPECT_EQ(fast, supported) << what;
            if (fast) {
              expect_same_bits(im, oiio_channels(path, names), what);
              ++read;
            }
            // Whichever path reads it, read_frame_channels gives OpenImageIO's values.
            expect_same_bits(read_frame_channels(path.string(), names, 4), oiio_channels(path, names), what);
          }
  EXPECT_EQ(read, 24 * 3);
}

TEST(ExrScanlines, DeclinesTiledFilesMissingChannelsAndDamage) {
  test::TempDir dir("exr_scanlines_no");
  Image im(kW, kH, 4, 1.0f);
  write(dir.path() / "tiled.exr", test_pixels(false), OIIO::TypeDesc::HALF, "zip", 0, 0, true);
  EXPECT_FALSE(read_exr_scanlines((dir.path() / "tiled.exr").string(), {"R"}, im));
  write(dir.path() / "f.exr", test_pixels(false), OIIO::TypeDesc::HALF, "zip");
  EXPECT_FALSE(read_exr_scanlines((dir.path() / "f.exr").string(), {"R", "Q"}, im));  // no channel Q
  Image small(kW - 1, kH, 4, 1.0f);
  EXPECT_FALSE(read_exr_scanlines((dir.path() / "f.exr").string(), {"R"}, small));  // another size
  // Truncated: declined, and read_frame_channels says what OpenImageIO says of it, naming the file.
  const auto bytes = fs::file_size(dir.path() / "f.exr");
  fs::copy_file(dir.path() / "f.exr", dir.path() / "cut.exr");
  fs::resize_file(dir.path() / "cut.exr", bytes * 2 / 3);
  EXPECT_FALSE(read_exr_scanlines((dir.path() / "cut.exr").string(), {"R"}, im));
  try {
    read_frame_channels((dir.path() / "cut.exr").string(), {"R"});
    ADD_FAILURE() << "a truncated file was read";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("cut.exr"), std::string::npos) << e.what();
  }
  // Not an EXR at all.
  std::ofstream(dir.path() / "x.exr") << "not an image";
  EXPECT_FALSE(read_exr_scanlines((dir.path() / "x.exr").string(), {"R"}, im));
}

// A multi-layer file of a renderer none of us wrote (Cycles, tests/data/blender): its layers' channels.
TEST(ExrScanlines, CyclesMultiLayerFrame) {
  const fs::path path = fs::path(GLINTLAB_SOURCE_DIR) / "tests/data/blender/ref/frame_0001.exr";
  const FrameHeader h = read_frame_header(path.string());
  std::vector<std::string> names;
  for (const auto& c : h.channels)
    if (c.find("Combined.") != std::string::npos || c.find("Vector.") != std::string::npos) names.push_back(c);
  ASSERT_GE(names.size(), 7u);
  Image im(h.width, h.height, int(names.size()) + 1, 1.0f);
  ASSERT_TRUE(read_exr_scanlines(path.string(), names, im));
  expect_same_bits(im, oiio_channels(path, names), path.string());
}

// Damaged files of every kind (bytes flipped in the header, the chunk table and the chunks): each is
// read (by one path or the other) or refused with an error; nothing crashes, nothing hangs.
TEST(ExrScanlines, DamagedBytesAreReadOrRefusedNeverACrash) {
  test::TempDir dir("exr_scanlines_damage");
  write(dir.path() / "f.exr", test_pixels(false), OIIO::TypeDesc::HALF, "zip");
  std::string good;
  {
    std::ifstream in(dir.path() / "f.exr", std::ios::binary);
    good.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::mt19937 rng(17);
  int refused = 0, read = 0;
  for (int k = 0; k < 300; ++k) {
    std::string bad = good;
    const int flips = 1 + int(rng() % 4);
    for (int f = 0; f < flips; ++f) bad[rng() % bad.size()] = char(rng());
    const fs::path path = dir.path() / ("d" + std::to_string(k) + ".exr");
    std::ofstream(path, std::ios::binary) << bad;
    try {
      const Image im = read_frame_channels(path.string(), {"R", "G", "B"}, 4);
      EXPECT_EQ(im.width, kW);
      ++read;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos) << e.what();
      ++refused;
    }
    fs::remove(path);
  }
  EXPECT_EQ(read + refused, 300);
  EXPECT_GT(refused, 0);
}

namespace {

// `values` (float, interleaved) as the file `spec` describes, written by OpenImageIO.
void write_with_oiio(const fs::path& path, const OIIO::ImageSpec& spec, const std::vector<float>& values) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values.data()));
  ASSERT_TRUE(out->close());
}

}  // namespace

// A plain OpenEXR file (read_simple_exr_header) is described and read as OpenImageIO does: the same
// channels in the same order, colour-space tag, channel count and pixels from read_image_file as
// from metrics::read_image (OpenImageIO); what is not plain is declined and still read the same.
TEST(ExrScanlines, PlainFilesAsOpenImageIODescribesAndReadsThem) {
  test::TempDir dir("exr_plain");
  const std::vector<float> px = test_pixels(true);
  int plain = 0;
  for (const std::vector<std::string>& names :
       std::vector<std::vector<std::string>>{{"R", "G", "B"}, {"R", "G", "B", "A"}, {"Y"}, {"Y", "A"}, {"R", "G", "Z"}})
    for (OIIO::TypeDesc type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT})
      for (const char* comp : {"zip", "piz"})
        for (int origin : {0, 3}) {
          const std::string what = std::to_string(names.size()) + " channels from " + names[0] + ", " + comp +
                                   (type == OIIO::TypeDesc::HALF ? " half" : " float") + ", origin " +
                                   std::to_string(origin);
          const fs::path path = dir.path() / "p.exr";
          {
            OIIO::ImageSpec spec(kW, kH, int(names.size()), type);
            spec.channelnames = names;
            spec.alpha_channel = names.back() == "A" ? int(names.size()) - 1 : -1;
            spec.x = spec.y = origin;
            spec.full_x = spec.full_y = 0;
            spec.full_width = kW + origin;
            spec.full_height = kH + origin;
            spec.attribute("compression", comp);
            std::vector<float> mine(size_t(kW) * kH * names.size());
            for (size_t i = 0; i < mine.size(); ++i) mine[i] = px[i % px.size()];
            write_with_oiio(path, spec, mine);
          }
          auto in = OIIO::ImageInput::open(path.string());
          ASSERT_TRUE(in);
          SimpleExrHeader h;
          const bool is_plain = read_simple_exr_header(path.string(), &h);
          const bool plain_layout = names != std::vector<std::string>{"R", "G", "Z"};
          EXPECT_EQ(is_plain, origin == 0 && plain_layout) << what;
          if (is_plain) {
            ++plain;
            EXPECT_EQ(h.width, in->spec().width) << what;
            EXPECT_EQ(h.height, in->spec().height) << what;
            EXPECT_EQ(h.channels, in->spec().channelnames) << what;
            EXPECT_EQ(kExrColorSpace, in->spec().get_string_attribute("oiio:ColorSpace")) << what;
            const FrameHeader f = read_frame_header(path.string());
            EXPECT_EQ(f.channels, in->spec().channelnames) << what;
            EXPECT_EQ(f.colorspace, kExrColorSpace) << what;
          }
          std::string tag_fast, tag_oiio;
          int n_fast = 0, n_oiio = 0;
          const Image fast = read_image_file(path.string(), &tag_fast, &n_fast);
          const Image oiio = metrics::read_image(path.string(), &tag_oiio, &n_oiio);
          EXPECT_EQ(tag_fast, tag_oiio) << what;
          EXPECT_EQ(n_fast, n_oiio) << what;
          ASSERT_EQ(fast.data.size(), oiio.data.size()) << what;
          EXPECT_EQ(std::memcmp(fast.data.data(), oiio.data.data(), fast.data.size() * sizeof(float)), 0) << what;
        }
  EXPECT_EQ(plain, 4 * 2 * 2);  // every plain layout, half and float, ZIP and PIZ (the header is plain either way)
}

// Any one-part scanline file, a Blender multilayer frame among them, is described as OpenImageIO 2.4
// describes it: the same channels in the same order (layers; R, G, B, Y, A, Z first in any case; X, Y,
// Z together in a layer that has X and Y or Z), the same size and colour-space tag, and its pixels
// read by name are OpenImageIO's. A luminance-chroma file, which OpenImageIO turns into RGB, is left
// to OpenImageIO.
TEST(ExrScanlines, LayeredFilesAsOpenImageIODescribesThem) {
  test::TempDir dir("exr_layers");
  const std::vector<float> px = test_pixels(false);
  const std::vector<std::vector<std::string>> cases = {
      {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B", "ViewLayer.Combined.A",
       "ViewLayer.Depth.Z", "ViewLayer.Vector.X", "ViewLayer.Vector.Y", "ViewLayer.Vector.Z", "ViewLayer.Vector.W"},
      {"A-x.R", "A.R", "A.G", "a.B", "Z", "depth", "Y", "N.X", "N.Y", "N.z", "P.X", "P.W", "u", "v", "alpha", "RA", "AR",
       "b", "Red", "x.y.Blue", "x.y.green", "x.Y"},
      {"X", "Y", "Z", "A"},   // a layer with X and Y: a position, X, Y, Z
      {"X", "W", "A", "R"},   // X without Y or Z: the usual order
      {"R", "G", "B"},
      {"Y", "BY", "RY"},      // luminance-chroma: OpenImageIO's
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    const auto& names = cases[k];
    const fs::path path = dir.path() / ("layers" + std::to_string(k) + ".exr");
    {
      OIIO::ImageSpec spec(kW, kH, int(names.size()), OIIO::TypeDesc::FLOAT);
      spec.channelnames = names;
      spec.attribute("compression", "zip");
      std::vector<float> mine(size_t(kW) * kH * names.size());
      for (size_t i = 0; i < mine.size(); ++i) mine[i] = px[(i * 7 + k) % px.size()];
      write_with_oiio(path, spec, mine);
    }
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    ExrLayout layout;
    const bool mine = read_exr_layout(path.string(), &layout);
    EXPECT_EQ(mine, k != cases.size() - 1) << names[0];
    const FrameHeader h = read_frame_header(path.string());
    EXPECT_EQ(h.channels, in->spec().channelnames) << names[0];
    EXPECT_EQ(h.width, in->spec().width);
    EXPECT_EQ(h.height, in->spec().height);
    EXPECT_EQ(h.colorspace, in->spec().get_string_attribute("oiio:ColorSpace"));
    if (!mine) continue;
    EXPECT_EQ(layout.channels, in->spec().channelnames) << names[0];
    std::vector<float> theirs(size_t(kW) * kH * names.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, int(names.size()), OIIO::TypeDesc::FLOAT, theirs.data()));
    const Image read = read_frame_channels(path.string(), layout.channels);
    ASSERT_EQ(read.data.size(), theirs.size());
    EXPECT_EQ(std::memcmp(read.data.data(), theirs.data(), theirs.size() * sizeof(float)), 0) << names[0];
  }
  // Blender's own frames (tests/data/blender: Cycles, ZIP, a Combined, Depth and Vector layer).
  for (const char* seq : {"ref", "spp1"}) {
    const std::string path = std::string(GLINTLAB_TEST_DATA_DIR) + "/blender/" + seq + "/frame_0001.exr";
    ExrLayout layout;
    ASSERT_TRUE(read_exr_layout(path, &layout)) << path;
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    EXPECT_EQ(layout.channels, in->spec().channelnames) << path;
    EXPECT_EQ(layout.channels.size(), 9u);
  }
}

// The conversion of half channels on a processor without F16C: every one of the 65 536 halves to the
// float Imath gives (zeros and subnormals, normals, infinities, NaN payloads), bit for bit.
TEST(ExrScanlines, EveryHalfConvertsAsImathConvertsIt) {
  int differ = 0;
  for (std::uint32_t b = 0; b <= 0xffffu; ++b) {
    Imath::half h;
    h.setBits(std::uint16_t(b));
    const float theirs = float(h), ours = half_bits_to_float(std::uint16_t(b));
    if (std::memcmp(&theirs, &ours, 4) != 0 && differ++ < 5)
      ADD_FAILURE() << "half 0x" << std::hex << b << ": " << ours << " against Imath's " << theirs;
  }
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(half_bits_to_float(0x3c00), 1.0f);
  EXPECT_EQ(half_bits_to_float(0x0001), 0x1p-24f);
  EXPECT_EQ(half_bits_to_float(0xfbff), -65504.0f);
}

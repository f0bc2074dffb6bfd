// The fast way into PNG files (experiments/sources/png_file.h) gives the image, colour-space tag
// and channel count OpenImageIO gives, to the bit, for every colour type and depth it takes, and
// declines PNGs that carry a gamma, chromaticities or an ICC profile, and damaged files.
#include "experiments/sources/exr_scanlines.h"
#include "experiments/sources/png_file.h"
#include "metrics/color/image_io.h"

#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

constexpr int kW = 23, kH = 17;

struct PngCase {
  std::string name;
  int color_type, depth;
  bool interlace = false, trns = false, srgb = false, gama = false, chrm = false;
};

// Writes a PNG with libpng: random samples, a palette of 16 entries for palette images.
void write_png_case(const fs::path& path, const PngCase& c) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  ASSERT_EQ(setjmp(png_jmpbuf(png)), 0);
  png_init_io(png, f);
  png_set_IHDR(png, info, kW, kH, c.depth, c.color_type, c.interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  std::mt19937 rng(7);
  if (c.color_type == PNG_COLOR_TYPE_PALETTE) {
    png_color pal[16];
    for (auto& p : pal) p = {png_byte(rng()), png_byte(rng()), png_byte(rng())};
    png_set_PLTE(png, info, pal, 16);
    if (c.trns) {
      png_byte alpha[16];
      for (auto& a : alpha) a = png_byte(rng());
      png_set_tRNS(png, info, alpha, 16, nullptr);
    }
  } else if (c.trns) {
    png_color_16 t{};
    t.gray = 1, t.red = 1, t.green = 2, t.blue = 3;
    png_set_tRNS(png, info, nullptr, 0, &t);
  }
  if (c.srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  if (c.gama) png_set_gAMA(png, info, 1.0 / 2.2);
  if (c.chrm) png_set_cHRM(png, info, 0.3127, 0.329, 0.64, 0.33, 0.3, 0.6, 0.15, 0.06);
  png_write_info(png, info);
  const int channels = c.color_type == PNG_COLOR_TYPE_RGB         ? 3
                       : c.color_type == PNG_COLOR_TYPE_RGBA      ? 4
                       : c.color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                                                                   : 1;
  const size_t row_bytes = (size_t(kW) * channels * c.depth + 7) / 8;
  std::vector<png_byte> row(row_bytes);
  const int passes = png_set_interlace_handling(png);
  std::vector<std::vector<png_byte>> rows(kH, std::vector<png_byte>(row_bytes));
  for (auto& r : rows)
    for (auto& b : r) b = png_byte(rng());
  if (c.color_type == PNG_COLOR_TYPE_PALETTE)  // indices below 16
    for (auto& r : rows)
      for (auto& b : r) b &= c.depth == 8 ? 0x0f : 0xff;
  for (int p = 0; p < passes; ++p)
    for (auto& r : rows) png_write_row(png, r.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

}  // namespace

TEST(PngFile, EveryColourTypeAndDepthReadsAsOpenImageIOReadsIt) {
  test::TempDir dir("png_file");
  const std::vector<PngCase> cases = {
      {"grey1", PNG_COLOR_TYPE_GRAY, 1},
      {"grey2", PNG_COLOR_TYPE_GRAY, 2},
      {"grey4", PNG_COLOR_TYPE_GRAY, 4},
      {"grey8", PNG_COLOR_TYPE_GRAY, 8},
      {"grey16", PNG_COLOR_TYPE_GRAY, 16},
      {"grey8-trns", PNG_COLOR_TYPE_GRAY, 8, false, true},
      {"grey-alpha8", PNG_COLOR_TYPE_GRAY_ALPHA, 8},
      {"grey-alpha16", PNG_COLOR_TYPE_GRAY_ALPHA, 16},
      {"rgb8", PNG_COLOR_TYPE_RGB, 8},
      {"rgb16", PNG_COLOR_TYPE_RGB, 16},
      {"rgb8-trns", PNG_COLOR_TYPE_RGB, 8, false, true},
      {"rgba8", PNG_COLOR_TYPE_RGBA, 8},
      {"rgba16", PNG_COLOR_TYPE_RGBA, 16},
      {"rgba8-interlaced", PNG_COLOR_TYPE_RGBA, 8, true},
      {"palette4", PNG_COLOR_TYPE_PALETTE, 4},
      {"palette8", PNG_COLOR_TYPE_PALETTE, 8},
      {"palette8-trns", PNG_COLOR_TYPE_PALETTE, 8, false, true},
      {"rgb8-srgb", PNG_COLOR_TYPE_RGB, 8, false, false, true},
      {"rgb8-srgb-gama-chrm", PNG_COLOR_TYPE_RGB, 8, false, false, true, true, true},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path p = dir.path() / (c.name + ".png");
    write_png_case(p, c);
    Image fast;
    std::string fast_tag, slow_tag;
    int fast_n = 0, slow_n = 0;
    ASSERT_TRUE(read_plain_png(p.string(), fast, &fast_tag, &fast_n));
    const Image slow = metrics::read_image(p.string(), &slow_tag, &slow_n);  // OpenImageIO
    EXPECT_EQ(fast_tag, slow_tag);
    EXPECT_EQ(fast_n, slow_n);
    ASSERT_EQ(fast.width, slow.width);
    ASSERT_EQ(fast.height, slow.height);
    ASSERT_EQ(fast.channels, slow.channels);
    size_t differ = 0;
    for (size_t i = 0; i < fast.data.size(); ++i) differ += std::memcmp(&fast.data[i], &slow.data[i], sizeof(float)) != 0;
    EXPECT_EQ(differ, 0u);
    // and the reader every command uses takes it
    std::string tag;
    const Image any = read_image_file(p.string(), &tag);
    EXPECT_EQ(std::memcmp(any.data.data(), fast.data.data(), fast.data.size() * sizeof(float)), 0);
  }
}

TEST(PngFile, PngsWithAGammaOrChromaticitiesAndDamagedFilesAreLeftToOpenImageIO) {
  test::TempDir dir("png_file_declined");
  Image img;
  for (const PngCase& c : {PngCase{"gama", PNG_COLOR_TYPE_RGB, 8, false, false, false, true},
                           PngCase{"chrm", PNG_COLOR_TYPE_RGB, 8, false, false, false, false, true}}) {
    const fs::path p = dir.path() / (c.name + ".png");
    write_png_case(p, c);
    EXPECT_FALSE(read_plain_png(p.string(), img, nullptr, nullptr)) << c.name;
  }
  // cut short: declined here, and OpenImageIO names the file
  const fs::path whole = dir.path() / "whole.png", cut = dir.path() / "cut.png";
  write_png_case(whole, {"whole", PNG_COLOR_TYPE_RGB, 8});
  std::ifstream in(whole, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_FALSE(read_plain_png(cut.string(), img, nullptr, nullptr));
  try {
    read_image_file(cut.string());
    ADD_FAILURE() << "a damaged PNG was read";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("cut.png"), std::string::npos) << e.what();
  }
  // not a PNG at all
  std::ofstream(dir.path() / "text.png") << "not a png";
  EXPECT_FALSE(read_plain_png((dir.path() / "text.png").string(), img, nullptr, nullptr));
}

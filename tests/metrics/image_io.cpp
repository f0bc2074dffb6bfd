// Image file I/O through OpenImageIO: bit-exact EXR round trips, chromaticities metadata, PNG
// quantisation, atomic writes.
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <string>

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include "metrics/color/image_io.h"

namespace fs = std::filesystem;
using glintlab::Image;
namespace gm = glintlab::metrics;

namespace {

class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tmp_ = std::make_unique<glintlab::test::TempDir>(std::string("image_io_") +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    dir_ = tmp_->path();
  }
  void TearDown() override { tmp_.reset(); }
  std::unique_ptr<glintlab::test::TempDir> tmp_;
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  // Names in dir_ that are not the given files (e.g. left-over temporaries).
  int count_entries() const { return static_cast<int>(std::distance(fs::directory_iterator(dir_), {})); }

  fs::path dir_;
};

bool bit_equal(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

const std::array<float, 8> kRec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

}  // namespace

TEST_F(ImageIoTest, ExrFloatRoundTripIsBitExactWithChromaticities) {
  Image img(5, 3, 4);
  // Values that stress float: negatives, denormal-ish tiny, huge, non-representable decimals.
  for (std::size_t i = 0; i < img.data.size(); ++i)
    img.data[i] = static_cast<float>((i % 7 == 0 ? -1.0 : 1.0) * std::pow(10.0, double(i % 13) - 6.0) / 3.0);
  img.data[5] = 1e-40f;  // subnormal
  img.data[6] = 6.5e4f * 1000.0f;
  const std::string path = file("a.exr");
  gm::write_exr(path, img, kRec709);
  std::string tag;
  const Image back = gm::read_image(path, &tag);
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  ASSERT_EQ(back.channels, 4);
  for (std::size_t i = 0; i < img.data.size(); ++i) EXPECT_TRUE(bit_equal(back.data[i], img.data[i])) << i;

  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT);
  const OIIO::ParamValue* p = in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_NE(p, nullptr);
  const float* c = static_cast<const float*>(p->data());
  for (int i = 0; i < 8; ++i) EXPECT_EQ(c[i], kRec709[i]) << i;
  EXPECT_EQ(count_entries(), 1);  // no temporary left behind
}

TEST_F(ImageIoTest, ExrHalfRoundTripIsBitExactForHalfValues) {
  Image img(4, 4, 3);
  // Half-representable: k/1024 (11-bit mantissa), powers of two, the half max 65504.
  for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(int(i) * 37 - 500) / 1024.0f;
  img.data[0] = 65504.0f;
  img.data[1] = std::ldexp(1.0f, -14);
  const std::string path = file("h.exr");
  gm::write_exr(path, img, kRec709, /*half=*/true);
  const Image back = gm::read_image(path);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::HALF);
  ASSERT_EQ(back.channels, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      for (int ch = 0; ch < 3; ++ch) EXPECT_TRUE(bit_equal(back.at(x, y, ch), img.at(x, y, ch))) << x << "," << y;
      EXPECT_EQ(back.at(x, y, 3), 1.0f);  // alpha 1 when absent
    }
  // A value between two halves is rounded, not kept: half really is half.
  Image odd(1, 1, 3, 1.0f + 1.0f / 4096.0f);
  gm::write_exr(file("odd.exr"), odd, kRec709, true);
  EXPECT_NE(gm::read_image(file("odd.exr")).data[0], odd.data[0]);
}

TEST_F(ImageIoTest, SingleChannelMapReadsAsGrey) {
  Image map(3, 2, 1);
  for (std::size_t i = 0; i < map.data.size(); ++i) map.data[i] = 0.125f * float(i) - 0.1f;
  const std::string path = file("map.exr");
  gm::write_exr_data(path, map);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 1);
  EXPECT_EQ(in->spec().channelnames[0], "Y");
  EXPECT_EQ(in->spec().find_attribute("chromaticities"), nullptr);
  const Image back = gm::read_image(path);
  ASSERT_EQ(back.channels, 4);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      for (int c = 0; c < 3; ++c) EXPECT_EQ(back.at(x, y, c), map.at(x, y, 0));
      EXPECT_EQ(back.at(x, y, 3), 1.0f);
    }
}

TEST_F(ImageIoTest, PngQuantisesWithRoundingAndClamps) {
  Image img(6, 1, 4);
  const float v[6] = {0.0f, 1.0f, 0.5f, 2.0f / 255.0f + 0.49f / 255.0f, -3.0f, 7.0f};
  for (int x = 0; x < 6; ++x) {
    for (int c = 0; c < 3; ++c) img.at(x, 0, c) = v[x];
    img.at(x, 0, 3) = 1.0f - x / 10.0f;
  }
  img.at(0, 0, 1) = std::numeric_limits<float>::quiet_NaN();
  const std::string path = file("p.png");
  gm::write_png(path, img);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
  in.reset();
  const Image back = gm::read_image(path);
  // Expected codes: round(255 clamp(v, 0, 1)); 127.5 rounds to 128 (half away from zero).
  const int code[6] = {0, 255, 128, 2, 0, 255};
  for (int x = 0; x < 6; ++x) {
    EXPECT_NEAR(255.0f * back.at(x, 0, 0), code[x], 1e-3) << x;
    EXPECT_NEAR(255.0f * back.at(x, 0, 2), code[x], 1e-3) << x;
    // Alpha stored as given (not premultiplied / un-premultiplied).
    EXPECT_NEAR(255.0f * back.at(x, 0, 3), std::round(255.0f * (1.0f - x / 10.0f)), 1e-3) << x;
  }
  EXPECT_EQ(back.at(0, 0, 1), 0.0f);  // NaN -> 0
  // Quantised values round-trip exactly.
  gm::write_png(path, back);
  const Image again = gm::read_image(path);
  for (std::size_t i = 0; i < back.data.size(); ++i) EXPECT_EQ(again.data[i], back.data[i]) << i;
  EXPECT_EQ(count_entries(), 1);
}

TEST_F(ImageIoTest, GreyPngReadsAsRgbWithTag) {
  Image g(2, 2, 1);
  g.data = {0.0f, 1.0f / 255.0f, 100.0f / 255.0f, 1.0f};
  gm::write_png(file("g.png"), g);
  std::string tag;
  const Image back = gm::read_image(file("g.png"), &tag);
  EXPECT_EQ(tag, "sRGB");  // OIIO tags 8-bit PNG as sRGB-encoded
  ASSERT_EQ(back.channels, 4);
  EXPECT_NEAR(255.0f * back.at(0, 1, 0), 100.0f, 1e-3);
  EXPECT_NEAR(255.0f * back.at(0, 1, 1), 100.0f, 1e-3);
  EXPECT_NEAR(255.0f * back.at(1, 0, 2), 1.0f, 1e-3);
  EXPECT_EQ(back.at(1, 1, 3), 1.0f);
}

TEST_F(ImageIoTest, FailedWritesLeaveExistingFileAndNoTemporary) {
  const std::string path = file("keep.exr");
  Image good(2, 2, 4, 0.5f);
  gm::write_exr(path, good, kRec709);
  const std::string before = slurp(path);
  ASSERT_FALSE(before.empty());

  // Invalid image (data does not match its size): rejected, file untouched.
  Image bad(2, 2, 4, 0.0f);
  bad.data.resize(3);
  EXPECT_THROW(gm::write_exr(path, bad, kRec709), std::invalid_argument);
  EXPECT_THROW(gm::write_png(file("keep.png"), bad), std::invalid_argument);
  EXPECT_EQ(slurp(path), before);

  // The target is a directory: the image is written, the rename fails, the temporary is removed.
  fs::create_directories(dir_ / "taken.exr" / "inside");
  try {
    gm::write_exr(file("taken.exr"), good, kRec709);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("taken.exr"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(dir_ / "taken.exr" / "inside"));

  // The parent is a regular file: cannot open, error names the file.
  try {
    gm::write_png((dir_ / "keep.exr" / "x.png").string(), good);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("x.png"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(path), before);
  EXPECT_EQ(count_entries(), 2);  // keep.exr and taken.exr/ only: no temporaries

  // Overwriting works and replaces the content.
  gm::write_exr(path, Image(2, 2, 4, 0.25f), kRec709);
  EXPECT_EQ(gm::read_image(path).data[0], 0.25f);
}

TEST_F(ImageIoTest, ReadErrorNamesTheFile) {
  const std::string missing = file("nope.exr");
  try {  // a path that names no file is bad input (std::invalid_argument: exit 2 in the CLI)
    (void)gm::read_image(missing);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  std::ofstream(file("junk.exr")) << "not an image";
  EXPECT_THROW((void)gm::read_image(file("junk.exr")), std::runtime_error);
}

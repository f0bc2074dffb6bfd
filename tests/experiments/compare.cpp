// `glintlab compare` logic end to end: real image files in a temp dir, the shipped OCIO config and the
// metric registry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "experiments/cli/compare.h"
#include "metrics/color/color_manager.h"
#include "metrics/color/image_io.h"
#include "metrics/metric_registry.h"

namespace fs = std::filesystem;
using glintlab::CompareOptions;
using glintlab::Image;
using glintlab::run_compare;
namespace gm = glintlab::metrics;

namespace {

const std::array<float, 8> kRec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

// The registry's CIEDE2000 metric, whatever its exact spelling.
std::string delta_e_2000_name() {
  for (const auto& n : gm::metric_names())
    if (n.find("2000") != std::string::npos) return n;
  return {};
}

// A smooth scene-linear test pattern with some HDR values.
Image pattern(int w, int h) {
  Image img(w, h, 4, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = 0.05f + 0.9f * float(x) / float(w);
      img.at(x, y, 1) = 0.02f + 0.6f * float(y) / float(h);
      img.at(x, y, 2) = (x + y) % 5 == 0 ? 2.0f : 0.3f;
    }
  return img;
}

class CompareTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("glintlab_compare_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    de_ = delta_e_2000_name();
    ASSERT_FALSE(de_.empty()) << "no CIEDE2000 metric in the registry";
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  int run(CompareOptions o) {
    out_.str("");
    err_.str("");
    o.ocio_config = GLINTLAB_OCIO_CONFIG;
    return run_compare(o, out_, err_);
  }
  nlohmann::json json_out() const { return nlohmann::json::parse(out_.str()); }

  fs::path dir_;
  std::string de_;
  std::ostringstream out_, err_;
};

}  // namespace

TEST_F(CompareTest, IdenticalImagesGiveZeroAndJsonSchema) {
  const Image img = pattern(16, 12);
  gm::write_exr(file("a.exr"), img, kRec709);
  gm::write_exr(file("b.exr"), img, kRec709);
  CompareOptions o;
  o.test = file("a.exr");
  o.ref = file("b.exr");
  o.json = true;
  ASSERT_EQ(run(o), 0) << err_.str();
  const nlohmann::json j = json_out();
  ASSERT_TRUE(j.is_object());
  ASSERT_EQ(j.size(), 1u);
  ASSERT_TRUE(j.at("metrics").is_object());
  // Every registered metric, each exactly {"mean", "max"}, numbers (or null for +inf PSNR).
  EXPECT_EQ(j["metrics"].size(), gm::metric_names().size());
  for (const auto& n : gm::metric_names()) {
    ASSERT_TRUE(j["metrics"].contains(n)) << n;
    const auto& m = j["metrics"][n];
    EXPECT_EQ(m.size(), 2u) << n;
    EXPECT_TRUE(m.at("mean").is_number() || m.at("mean").is_null()) << n;
    EXPECT_TRUE(m.at("max").is_number() || m.at("max").is_null()) << n;
  }
  EXPECT_EQ(j["metrics"][de_]["mean"].get<double>(), 0.0);
  EXPECT_EQ(j["metrics"][de_]["max"].get<double>(), 0.0);
  EXPECT_EQ(err_.str().find("assuming"), std::string::npos) << err_.str();  // EXR tag "Linear" is known
}

TEST_F(CompareTest, TextOutputOneLinePerMetric) {
  const Image img = pattern(8, 8);
  gm::write_exr(file("a.exr"), img, kRec709);
  CompareOptions o;
  o.test = o.ref = file("a.exr");
  o.metrics = {de_};
  ASSERT_EQ(run(o), 0) << err_.str();
  const std::string text = out_.str();
  EXPECT_EQ(text.rfind(de_ + ": mean 0 ", 0), 0u) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
}

TEST_F(CompareTest, SizeMismatchNamesBothFiles) {
  gm::write_exr(file("small.exr"), pattern(8, 6), kRec709);
  gm::write_exr(file("large.exr"), pattern(9, 6), kRec709);
  CompareOptions o;
  o.test = file("small.exr");
  o.ref = file("large.exr");
  EXPECT_EQ(run(o), 2);
  const std::string e = err_.str();
  EXPECT_NE(e.find(o.test), std::string::npos) << e;
  EXPECT_NE(e.find(o.ref), std::string::npos) << e;
  EXPECT_NE(e.find("8x6"), std::string::npos) << e;
  EXPECT_NE(e.find("9x6"), std::string::npos) << e;
  EXPECT_TRUE(out_.str().empty());
}

TEST_F(CompareTest, BadInputsExitTwoWithMessage) {
  gm::write_exr(file("a.exr"), pattern(4, 4), kRec709);
  CompareOptions o;
  o.test = o.ref = file("a.exr");
  o.metrics = {"no_such_metric"};
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("no_such_metric"), std::string::npos) << err_.str();
  EXPECT_NE(err_.str().find(de_), std::string::npos) << err_.str();  // lists the allowed ones

  o.metrics.clear();
  o.space = "NotASpace";
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("NotASpace"), std::string::npos) << err_.str();

  o.space.clear();
  o.ref = file("missing.exr");
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find(o.ref), std::string::npos) << err_.str();
}

TEST_F(CompareTest, MapIsPerPixelErrorOfFirstMetric) {
  const Image ref = pattern(10, 7);
  Image test = ref;
  test.at(3, 2, 0) += 0.4f;  // one changed pixel
  gm::write_exr(file("t.exr"), test, kRec709);
  gm::write_exr(file("r.exr"), ref, kRec709);
  CompareOptions o;
  o.test = file("t.exr");
  o.ref = file("r.exr");
  o.metrics = {de_};
  o.map_path = file("map.exr");
  o.json = true;
  ASSERT_EQ(run(o), 0) << err_.str();
  auto in = OIIO::ImageInput::open(o.map_path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 10);
  EXPECT_EQ(in->spec().height, 7);
  EXPECT_EQ(in->spec().nchannels, 1);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT);
  in.reset();
  const Image map = gm::read_image(o.map_path);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 10; ++x) {
      if (x == 3 && y == 2) EXPECT_GT(map.at(x, y, 0), 1.0f);
      else EXPECT_EQ(map.at(x, y, 0), 0.0f) << x << "," << y;
    }
  // The JSON max is that pixel's error, the mean is it over the pixel count.
  const auto j = json_out();
  EXPECT_NEAR(j["metrics"][de_]["max"].get<double>(), map.at(3, 2, 0), 1e-4);
  EXPECT_NEAR(j["metrics"][de_]["mean"].get<double>(), map.at(3, 2, 0) / 70.0, 1e-5);
}

TEST_F(CompareTest, FileColourSpaceTagsAreHonoured) {
  // Reference: scene-linear EXR in [0, 1]. Test: the same image as an 8-bit sRGB PNG. Read by its
  // tag (sRGB) the PNG differs only by quantisation; forced to scene-linear it is visibly wrong.
  Image ref = pattern(12, 12);
  for (float& v : ref.data) v = std::min(v, 1.0f);
  gm::write_exr(file("ref.exr"), ref, kRec709);
  gm::ColorManager cm(GLINTLAB_OCIO_CONFIG);
  gm::write_png(file("test.png"), cm.display(ref, "lin_rec709", "sRGB", "Standard"));
  CompareOptions o;
  o.test = file("test.png");
  o.ref = file("ref.exr");
  o.metrics = {de_};
  o.json = true;
  ASSERT_EQ(run(o), 0) << err_.str();
  const double by_tag = json_out()["metrics"][de_]["mean"].get<double>();
  EXPECT_GT(by_tag, 0.0);
  EXPECT_LT(by_tag, 0.5);  // 8-bit sRGB quantisation is below one JND
  o.space = "scene_linear";
  ASSERT_EQ(run(o), 0) << err_.str();
  EXPECT_GT(json_out()["metrics"][de_]["mean"].get<double>(), 5.0);
}

TEST_F(CompareTest, DisplayReferredSeesWhatTheViewClips) {
  // Test and reference differ only in values above 1, which the sRGB/Standard
  // view clips: scene-referred they differ, display-referred they are equal.
  Image ref(6, 4, 4, 1.0f), test = ref;
  for (size_t i = 0; i < ref.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      ref.data[i * 4 + c] = 1.5f;
      test.data[i * 4 + c] = 3.0f;
    }
  ref.at(0, 0, 1) = test.at(0, 0, 1) = 0.25f;  // an in-gamut pixel, identical in both
  gm::write_exr(file("t.exr"), test, kRec709);
  gm::write_exr(file("r.exr"), ref, kRec709);
  CompareOptions o;
  o.test = file("t.exr");
  o.ref = file("r.exr");
  o.metrics = {de_};
  o.json = true;
  ASSERT_EQ(run(o), 0) << err_.str();
  EXPECT_GT(json_out()["metrics"][de_]["mean"].get<double>(), 5.0);
  o.display_view = "sRGB/Standard";
  ASSERT_EQ(run(o), 0) << err_.str();
  EXPECT_NEAR(json_out()["metrics"][de_]["mean"].get<double>(), 0.0, 1e-3);
  o.display_view = "sRGB";  // not DISPLAY/VIEW
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("DISPLAY/VIEW"), std::string::npos) << err_.str();
  o.display_view = "sRGB/NoSuchView";
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("NoSuchView"), std::string::npos) << err_.str();
}

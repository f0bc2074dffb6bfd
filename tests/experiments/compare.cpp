// `glintlab compare` logic end to end: real image files in a temp dir, the shipped OCIO config and the
// metric registry.
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <unistd.h>
#include <cstring>

#include "experiments/cli/commands.h"
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
    tmp_ = std::make_unique<glintlab::test::TempDir>(std::string("compare_") +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    dir_ = tmp_->path();
    de_ = delta_e_2000_name();
    ASSERT_FALSE(de_.empty()) << "no CIEDE2000 metric in the registry";
  }
  void TearDown() override { tmp_.reset(); }
  std::unique_ptr<glintlab::test::TempDir> tmp_;
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
  // {"metrics": ...} and the documented additions (compare.h): the files, the input pixel counts and
  // the FLIP settings. (Before FLIP's pooled values and the input counts, "metrics" was the only key.)
  for (const auto& [key, value] : j.items())
    EXPECT_TRUE(key == "metrics" || key == "input" || key == "flip" || key == "test" || key == "reference") << key;
  ASSERT_TRUE(j.at("metrics").is_object());
  // Every registered metric, each with {"mean", "max", "p95"}, numbers (or null for +inf PSNR, and p95
  // of psnr); flip also has FLIP's pooled values.
  EXPECT_EQ(j["metrics"].size(), gm::metric_names().size());
  for (const auto& n : gm::metric_names()) {
    ASSERT_TRUE(j["metrics"].contains(n)) << n;
    const auto& m = j["metrics"][n];
    EXPECT_EQ(m.size(), n == "flip" ? 7u : 3u) << n;
    EXPECT_TRUE(m.at("mean").is_number() || m.at("mean").is_null()) << n;
    EXPECT_TRUE(m.at("max").is_number() || m.at("max").is_null()) << n;
    EXPECT_TRUE(n == "psnr" ? m.at("p95").is_null() : m.at("p95").get<double>() == 0.0) << n;  // identical images
  }
  for (const char* k : {"min", "weighted_median", "weighted_quartile_1", "weighted_quartile_3"})
    EXPECT_EQ(j["metrics"]["flip"].at(k).get<double>(), 0.0) << k;
  EXPECT_EQ(j["input"]["test"], nlohmann::json({{"pixels", 192}, {"nan", 0}, {"inf", 0}, {"negative", 0}}));
  EXPECT_EQ(j["input"]["ref"], j["input"]["test"]);
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

// ------------------------------------------------------------------------------------------------
// FLIP through `glintlab compare`, against NVIDIA FLIP v1.6 (github.com/NVlabs/flip, commit
// 1eb247cabcf2862c2c8207ab15314304394132b9; C++ tool from src/cpp/tool/FLIP-tool.cpp, `g++ -O2
// -std=c++17 -fopenmp`), run on the committed images of tests/data/flip/ (tests/metrics/flip.cpp makes
// them) as
//   flip -r tests/data/flip/<ref> -t tests/data/flip/<test> [<test> ...] -nerm -nexm [options]
// Expected values: its printed mean, weighted median, 1st and 3rd weighted quartile, min and max.
// Here the images go through glintlab's reader and OCIO (PNG: the config's sRGB space); measured
// agreement within 1.1e-5.
namespace {
std::string flip_data(const std::string& name) { return std::string(GLINTLAB_TEST_DATA_DIR) + "/flip/" + name; }

struct FlipExpected {
  double mean, weighted_median, q1, q3, min, max;
};
void expect_flip(const nlohmann::json& m, const FlipExpected& e, const std::string& what) {
  constexpr double tol = 1e-4;
  EXPECT_NEAR(m.at("mean").get<double>(), e.mean, tol) << what;
  EXPECT_NEAR(m.at("weighted_median").get<double>(), e.weighted_median, tol) << what;
  EXPECT_NEAR(m.at("weighted_quartile_1").get<double>(), e.q1, tol) << what;
  EXPECT_NEAR(m.at("weighted_quartile_3").get<double>(), e.q3, tol) << what;
  EXPECT_NEAR(m.at("min").get<double>(), e.min, tol) << what;
  EXPECT_NEAR(m.at("max").get<double>(), e.max, tol) << what;
}

// An image with bad pixels: NaN, +Inf, -Inf and a negative value in separate pixels.
Image with_bad_pixels(const Image& img) {
  Image b = img;
  b.at(1, 1, 0) = std::numeric_limits<float>::quiet_NaN();
  b.at(2, 1, 1) = std::numeric_limits<float>::infinity();
  b.at(3, 1, 2) = -std::numeric_limits<float>::infinity();
  b.at(4, 2, 0) = -0.25f;
  return b;
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}
}  // namespace

TEST_F(CompareTest, FlipMatchesNvidiaFlipLdrSeveralTests) {
  // flip -r ldr_ref.png -t ldr_test_noise.png ldr_test_shift.png -nerm
  CompareOptions o;
  o.ref = flip_data("ldr_ref.png");
  o.tests = {flip_data("ldr_test_noise.png"), flip_data("ldr_test_shift.png")};
  o.metrics = {"flip"};
  o.flip_ldr = true;
  o.json = true;
  ASSERT_EQ(run(o), 0) << err_.str();
  const auto j = json_out();
  EXPECT_EQ(j["reference"], o.ref);
  EXPECT_EQ(j["flip"]["mode"], "ldr");
  EXPECT_NEAR(j["flip"]["ppd"].get<double>(), 67.0206, 1e-4);
  ASSERT_EQ(j["tests"].size(), 2u);
  EXPECT_EQ(j["tests"][0]["test"], o.tests[0]);
  EXPECT_EQ(j["tests"][1]["test"], o.tests[1]);
  expect_flip(j["tests"][0]["metrics"]["flip"], {0.081440, 0.090092, 0.069457, 0.114668, 0.007287, 0.221094}, "noise");
  expect_flip(j["tests"][1]["metrics"]["flip"], {0.295312, 0.374807, 0.291198, 0.427104, 0.023947, 0.868661}, "shift");
  // ... -t ldr_test_noise.png -ppd 40
  o.tests.resize(1);
  o.ppd = 40;
  ASSERT_EQ(run(o), 0) << err_.str();
  expect_flip(json_out()["metrics"]["flip"], {0.122746, 0.134524, 0.105719, 0.172262, 0.014452, 0.319318}, "ppd 40");
}

TEST_F(CompareTest, FlipMatchesNvidiaFlipHdrBimodal) {
  CompareOptions o;
  o.test = flip_data("hdr_bimodal_test.exr");
  o.ref = flip_data("hdr_bimodal_ref.exr");
  o.metrics = {"flip"};
  o.json = true;
  // flip -r hdr_bimodal_ref.exr -t hdr_bimodal_test.exr -nerm -nexm
  //   ("Start exposure: -4.2029", "Stop exposure: -0.9069", "Number of exposures: 4")
  ASSERT_EQ(run(o), 0) << err_.str();
  auto j = json_out();
  expect_flip(j["metrics"]["flip"], {0.049458, 0.068389, 0.045050, 0.098722, 0.000593, 0.862510}, "defaults");
  EXPECT_EQ(j["flip"]["mode"], "hdr");
  EXPECT_EQ(j["flip"]["tone_mapper"], "aces");
  EXPECT_NEAR(j["flip"]["start_exposure"].get<double>(), -4.2029, 1e-4);
  EXPECT_NEAR(j["flip"]["stop_exposure"].get<double>(), -0.9069, 1e-4);
  EXPECT_EQ(j["flip"]["num_exposures"], 4);
  // -tm hable (FLIP takes any case)
  o.tone_mapper = "Hable";
  ASSERT_EQ(run(o), 0) << err_.str();
  j = json_out();
  expect_flip(j["metrics"]["flip"], {0.051696, 0.063526, 0.043313, 0.089486, 0.002940, 0.845463}, "hable");
  EXPECT_EQ(j["flip"]["tone_mapper"], "hable");
  // -tm reinhard
  o.tone_mapper = "reinhard";
  ASSERT_EQ(run(o), 0) << err_.str();
  expect_flip(json_out()["metrics"]["flip"], {0.080044, 0.104290, 0.073943, 0.132843, 0.004091, 0.814486}, "reinhard");
  // -vc 0.5 0.6 1920
  o.tone_mapper.clear();
  o.monitor_distance = 0.5;
  o.monitor_width = 0.6;
  o.monitor_width_pixels = 1920;
  ASSERT_EQ(run(o), 0) << err_.str();
  expect_flip(json_out()["metrics"]["flip"], {0.098777, 0.145679, 0.092118, 0.197087, 0.001141, 0.982250}, "vc");
  // -ppd 30
  o.monitor_distance = o.monitor_width = o.monitor_width_pixels = NAN;
  o.ppd = 30;
  ASSERT_EQ(run(o), 0) << err_.str();
  expect_flip(json_out()["metrics"]["flip"], {0.092305, 0.135361, 0.085996, 0.185222, 0.001319, 0.979886}, "ppd 30");
  // -cstart -3 -cstop 2 -n 6
  o.ppd = NAN;
  o.start_exposure = -3;
  o.stop_exposure = 2;
  o.num_exposures = 6;
  ASSERT_EQ(run(o), 0) << err_.str();
  j = json_out();
  expect_flip(j["metrics"]["flip"], {0.065192, 0.076480, 0.054088, 0.104283, 0.004056, 0.858680}, "explicit");
  EXPECT_EQ(j["flip"]["num_exposures"], 6);
  // -cstart -2.5 (stop from the reference; 2 exposures)
  o.stop_exposure = NAN;
  o.num_exposures = 0;
  o.start_exposure = -2.5;
  ASSERT_EQ(run(o), 0) << err_.str();
  j = json_out();
  expect_flip(j["metrics"]["flip"], {0.037086, 0.048125, 0.030694, 0.077228, 0.000558, 0.855361}, "start");
  EXPECT_EQ(j["flip"]["num_exposures"], 2);
  // -n 3
  o.start_exposure = NAN;
  o.num_exposures = 3;
  ASSERT_EQ(run(o), 0) << err_.str();
  expect_flip(json_out()["metrics"]["flip"], {0.049096, 0.067796, 0.044553, 0.097621, 0.000558, 0.862510}, "n 3");
}

TEST_F(CompareTest, FlipMedianZeroReference) {
  // More than half of hdr_black_ref.exr is black. FLIP v1.6 at its defaults prints "Stop exposure: inf",
  // "Number of exposures: -2147483648" and 0.000000 for every pooled value; glintlab takes the median
  // of the positive luminances (metrics/flip.h) and prints the stop it used; FLIP given that stop,
  //   flip -r hdr_black_ref.exr -t hdr_black_test.exr -nerm -nexm -cstop 2.838110505
  // prints the expected values (and "Start exposure: -4.5606", "Number of exposures: 8").
  CompareOptions o;
  o.test = flip_data("hdr_black_test.exr");
  o.ref = flip_data("hdr_black_ref.exr");
  o.metrics = {"flip"};
  o.json = true;
  ASSERT_EQ(run(o), 0) << err_.str();
  const auto j = json_out();
  EXPECT_NEAR(j["flip"]["start_exposure"].get<double>(), -4.5606, 1e-4);
  EXPECT_NEAR(j["flip"]["stop_exposure"].get<double>(), 2.838110505, 1e-6);
  EXPECT_EQ(j["flip"]["num_exposures"], 8);
  expect_flip(j["metrics"]["flip"], {0.067461, 0.069428, 0.062303, 0.077556, 0.011289, 0.172801}, "median zero");
}

TEST_F(CompareTest, FlipTextShowsPooledValuesAndSettings) {
  CompareOptions o;
  o.test = flip_data("hdr_bimodal_test.exr");
  o.ref = flip_data("hdr_bimodal_ref.exr");
  o.metrics = {"flip"};
  ASSERT_EQ(run(o), 0) << err_.str();
  const std::string t = out_.str();
  EXPECT_EQ(t.rfind("flip: mean 0.04945", 0), 0u) << t;
  EXPECT_NE(t.find("weighted median 0.0683"), std::string::npos) << t;
  EXPECT_NE(t.find("1st weighted quartile 0.0450"), std::string::npos) << t;
  EXPECT_NE(t.find("3rd weighted quartile 0.0987"), std::string::npos) << t;
  EXPECT_NE(t.find("HDR-FLIP, 67.0206 px/deg, tone mapper aces, exposures -4.20288 to -0.906875 (4)"),
            std::string::npos)
      << t;
  EXPECT_EQ(std::count(t.begin(), t.end(), '\n'), 3) << t;
}

TEST_F(CompareTest, CsvHasOneRowPerTestAndMetric) {
  const Image ref = pattern(12, 8);
  Image t1 = ref, t2 = ref;
  t1.at(2, 2, 0) += 0.3f;
  t2.at(5, 5, 1) += 0.3f;
  gm::write_exr(file("r.exr"), ref, kRec709);
  gm::write_exr(file("a.exr"), t1, kRec709);
  gm::write_exr(file("b,c.exr"), t2, kRec709);  // a comma: quoted in the CSV
  CompareOptions o;
  o.ref = file("r.exr");
  o.tests = {file("a.exr"), file("b,c.exr")};
  o.metrics = {de_, "flip"};
  o.csv_path = file("out.csv");
  ASSERT_EQ(run(o), 0) << err_.str();
  const auto lines = read_lines(o.csv_path);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0],
            "reference,test,metric,unit,mean,max,min,weighted_median,weighted_quartile_1,weighted_quartile_3,"
            "test_nan,test_inf,test_negative,ref_nan,ref_inf,ref_negative");
  EXPECT_EQ(lines[1].rfind(o.ref + "," + o.tests[0] + "," + de_ + ",", 0), 0u) << lines[1];
  EXPECT_EQ(lines[2].rfind(o.ref + "," + o.tests[0] + ",flip,FLIP,", 0), 0u) << lines[2];
  EXPECT_EQ(lines[3].rfind(o.ref + ",\"" + o.tests[1] + "\"," + de_ + ",", 0), 0u) << lines[3];
  EXPECT_EQ(lines[4].rfind(o.ref + ",\"" + o.tests[1] + "\",flip,FLIP,", 0), 0u) << lines[4];
  EXPECT_NE(lines[1].find(",,,,0,0,0,0,0,0"), std::string::npos) << lines[1];  // no pooled values for ΔE
  // The text names each test.
  const std::string t = out_.str();
  EXPECT_NE(t.find("test '" + o.tests[0] + "':\n  " + de_ + ": mean "), std::string::npos) << t;
  EXPECT_NE(t.find("test '" + o.tests[1] + "':\n"), std::string::npos) << t;
  // An unwritable CSV path is an I/O failure: exit 4.
  o.csv_path = file("no_such_dir/out.csv");
  EXPECT_EQ(run(o), 4);
  EXPECT_NE(err_.str().find("no_such_dir"), std::string::npos) << err_.str();
}

TEST_F(CompareTest, ThresholdOnMeanFlipError) {
  // FLIP's -et: exit 1 when the mean FLIP error of any test is above the threshold.
  CompareOptions o;
  o.ref = flip_data("ldr_ref.png");
  o.tests = {flip_data("ldr_test_noise.png"), flip_data("ldr_test_shift.png")};  // means 0.0814, 0.2953 (LDR)
  o.metrics = {"flip"};
  o.flip_ldr = true;
  o.json = true;
  o.threshold = 0.5;
  EXPECT_EQ(run(o), 0) << err_.str();
  EXPECT_EQ(json_out()["tests"][1]["threshold_exceeded"], false);
  o.threshold = 0.1;
  EXPECT_EQ(run(o), 1) << err_.str();
  auto j = json_out();
  EXPECT_EQ(j["tests"][0]["threshold_exceeded"], false);
  EXPECT_EQ(j["tests"][1]["threshold_exceeded"], true);
  EXPECT_NE(err_.str().find("ldr_test_shift.png"), std::string::npos) << err_.str();
  EXPECT_EQ(err_.str().find("ldr_test_noise.png"), std::string::npos) << err_.str();
  o.threshold = 0.05;
  EXPECT_EQ(run(o), 1);
  // Bad values and a threshold without the flip metric: bad input.
  o.threshold = 1.5;
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("--threshold must be a number in [0, 1]"), std::string::npos) << err_.str();
  o.threshold = 0.1;
  o.metrics = {de_};
  o.flip_ldr = false;
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("--threshold"), std::string::npos) << err_.str();
  EXPECT_NE(err_.str().find("flip"), std::string::npos) << err_.str();
}

TEST_F(CompareTest, NonFiniteAndNegativePixelsMakeEveryMetricNan) {
  const Image ref = pattern(8, 6);
  Image test = ref;
  test.at(6, 4, 1) += 0.2f;
  gm::write_exr(file("r.exr"), ref, kRec709);
  gm::write_exr(file("t.exr"), test, kRec709);
  gm::write_exr(file("bad.exr"), with_bad_pixels(test), kRec709);
  gm::write_exr(file("badref.exr"), with_bad_pixels(ref), kRec709);
  const auto names = gm::metric_names();

  // Bad test image: counted, reported, every metric null, exit 1.
  CompareOptions o;
  o.test = file("bad.exr");
  o.ref = file("r.exr");
  o.json = true;
  o.map_path = file("map.exr");
  o.metrics = {de_, "flip", "psnr", "deltaEITP", "relative"};
  EXPECT_EQ(run(o), 1) << err_.str();
  auto j = json_out();
  EXPECT_EQ(j["input"]["test"], nlohmann::json({{"pixels", 48}, {"nan", 1}, {"inf", 2}, {"negative", 1}}));
  EXPECT_EQ(j["input"]["ref"], nlohmann::json({{"pixels", 48}, {"nan", 0}, {"inf", 0}, {"negative", 0}}));
  for (const auto& n : names) {
    for (const auto& [k, v] : j["metrics"][n].items()) EXPECT_TRUE(v.is_null()) << n << " " << k;
  }
  EXPECT_NE(err_.str().find("1 NaN, 2 Inf, 1 negative"), std::string::npos) << err_.str();
  // The map is written, NaN at the bad pixels.
  const Image map = gm::read_image(o.map_path);
  EXPECT_TRUE(std::isnan(map.at(1, 1, 0)));
  EXPECT_TRUE(std::isnan(map.at(2, 1, 0)));
  EXPECT_TRUE(std::isnan(map.at(3, 1, 0)));
  EXPECT_TRUE(std::isnan(map.at(4, 2, 0)));
  EXPECT_EQ(map.at(0, 5, 0), 0.0f);

  // Text: the counts line and "nan" for every metric, never "mean 0".
  o.json = false;
  o.map_path.clear();
  EXPECT_EQ(run(o), 1);
  std::string t = out_.str();
  EXPECT_NE(t.find("input test '" + o.test + "': 1 NaN, 2 Inf, 1 negative (of 48 pixels)"), std::string::npos) << t;
  EXPECT_NE(t.find(de_ + ": mean nan"), std::string::npos) << t;
  EXPECT_NE(t.find("flip: mean nan"), std::string::npos) << t;
  EXPECT_NE(t.find("weighted median nan"), std::string::npos) << t;
  EXPECT_EQ(t.find("mean 0 "), std::string::npos) << t;

  // Bad reference: the same, counted under "ref"; also in the CSV.
  o.test = file("t.exr");
  o.ref = file("badref.exr");
  o.json = true;
  o.csv_path = file("bad.csv");
  EXPECT_EQ(run(o), 1);
  j = json_out();
  EXPECT_EQ(j["input"]["ref"], nlohmann::json({{"pixels", 48}, {"nan", 1}, {"inf", 2}, {"negative", 1}}));
  EXPECT_EQ(j["input"]["test"]["nan"], 0);
  for (const auto& n : names) EXPECT_TRUE(j["metrics"][n]["mean"].is_null()) << n;
  const auto lines = read_lines(o.csv_path);
  ASSERT_EQ(lines.size(), 1 + o.metrics.size());
  EXPECT_NE(lines[1].find("," + de_ + ",ΔE00,,,,,,,0,0,0,1,2,1"), std::string::npos) << lines[1];

  // Only a negative pixel (finite): still reported and NaN, exit 1.
  Image neg = test;
  neg.at(0, 0, 1) = -0.01f;
  gm::write_exr(file("neg.exr"), neg, kRec709);
  o.test = file("neg.exr");
  o.ref = file("r.exr");
  o.csv_path.clear();
  EXPECT_EQ(run(o), 1);
  j = json_out();
  EXPECT_EQ(j["input"]["test"]["negative"], 1);
  EXPECT_TRUE(j["metrics"]["flip"]["mean"].is_null());

  // Several tests: only the bad one is NaN; the exit code is still 1.
  o.test.clear();
  o.tests = {file("t.exr"), file("bad.exr")};
  EXPECT_EQ(run(o), 1);
  j = json_out();
  EXPECT_TRUE(j["tests"][0]["metrics"][de_]["mean"].is_number());
  EXPECT_GT(j["tests"][0]["metrics"][de_]["mean"].get<double>(), 0.0);
  EXPECT_TRUE(j["tests"][1]["metrics"][de_]["mean"].is_null());
  EXPECT_EQ(j["tests"][1]["input"]["test"]["inf"], 2);
}

TEST_F(CompareTest, BadFlipOptionsNameTheOption) {
  gm::write_exr(file("a.exr"), pattern(6, 6), kRec709);
  const auto expect_bad = [&](CompareOptions o, const std::string& needle) {
    o.test = o.ref = file("a.exr");
    EXPECT_EQ(run(o), 2) << needle;
    EXPECT_NE(err_.str().find(needle), std::string::npos) << err_.str();
    EXPECT_TRUE(out_.str().empty()) << out_.str();
  };
  CompareOptions o;
  o.ppd = 0;
  expect_bad(o, "--ppd must be a finite number > 0");
  o = {};
  o.ppd = 50;
  o.monitor_width = 0.5;
  expect_bad(o, "--ppd and --monitor-distance");
  o = {};
  o.monitor_distance = -1;
  expect_bad(o, "--monitor-distance must be a finite number > 0");
  o = {};
  o.monitor_width_pixels = INFINITY;
  expect_bad(o, "--monitor-width-pixels");
  o = {};
  o.tone_mapper = "filmic";
  expect_bad(o, "--tone-mapper must be one of \"aces\", \"hable\", \"reinhard\"");
  o = {};
  o.start_exposure = 2;
  o.stop_exposure = 1;
  expect_bad(o, "--start-exposure (2) must not be above --stop-exposure (1)");
  o = {};
  o.start_exposure = 30;  // above the stop computed from the reference
  expect_bad(o, "--start-exposure (30) is above the stop exposure");
  o = {};
  o.stop_exposure = -30;  // below the start computed from the reference
  expect_bad(o, "--stop-exposure (-30) is below the start exposure");
  o = {};
  o.num_exposures = -1;
  expect_bad(o, "--num-exposures must be an integer >= 1");
  o = {};
  o.flip_ldr = true;
  o.tone_mapper = "hable";
  expect_bad(o, "do not go with --flip-ldr");
  o = {};
  o.tests = {file("a.exr")};
  o.map_path = file("m.exr");
  expect_bad(o, "--map writes one map");
  // No test image at all.
  o = {};
  o.ref = file("a.exr");
  EXPECT_EQ(run(o), 2);
  EXPECT_NE(err_.str().find("need a test image"), std::string::npos) << err_.str();
  // FLIP options without the flip metric: a warning, not an error.
  o = {};
  o.test = o.ref = file("a.exr");
  o.metrics = {de_};
  o.ppd = 40;
  EXPECT_EQ(run(o), 0);
  EXPECT_NE(err_.str().find("warning: FLIP options given"), std::string::npos) << err_.str();
}

TEST_F(CompareTest, DefaultPixelsPerDegreeIsFlips) {
  // 67.0206 px/deg (FLIP's default viewing conditions), not 67: the same result as giving it explicitly,
  // or as FLIP's viewing conditions 0.7 m, 0.7 m, 3840 px.
  CompareOptions o;
  o.test = flip_data("ldr_test_shift.png");
  o.ref = flip_data("ldr_ref.png");
  o.metrics = {"flip"};
  o.json = true;
  ASSERT_EQ(run(o), 0);
  const double by_default = json_out()["metrics"]["flip"]["mean"].get<double>();
  o.ppd = 3840.0 * M_PI / 180.0;
  ASSERT_EQ(run(o), 0);
  EXPECT_EQ(json_out()["metrics"]["flip"]["mean"].get<double>(), by_default);
  o.ppd = NAN;
  o.monitor_distance = 0.7;
  o.monitor_width = 0.7;
  o.monitor_width_pixels = 3840;
  ASSERT_EQ(run(o), 0);
  EXPECT_EQ(json_out()["metrics"]["flip"]["mean"].get<double>(), by_default);
  o.monitor_distance = o.monitor_width = o.monitor_width_pixels = NAN;
  o.ppd = 67.0;
  ASSERT_EQ(run(o), 0);
  EXPECT_NE(json_out()["metrics"]["flip"]["mean"].get<double>(), by_default);
}

// The command line as a user types it (CLI11 wiring of add_compare_command).
namespace {
struct CliRun {
  int code = -1;
  std::string out, err;
};
CliRun run_cli(std::vector<std::string> args) {
  CLI::App app{"glintlab"};
  app.require_subcommand(1);
  int exit_code = 0;
  glintlab::add_compare_command(app, exit_code);
  args.insert(args.begin(), "compare");
  args.push_back("--ocio-config");
  args.push_back(GLINTLAB_OCIO_CONFIG);
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 parses a reversed vector
  CliRun r;
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  try {
    app.parse(reversed);
    r.code = exit_code;
  } catch (const CLI::ParseError& e) {
    r.code = app.exit(e) == 0 ? 0 : 2;
  }
  r.out = ::testing::internal::GetCapturedStdout();
  r.err = ::testing::internal::GetCapturedStderr();
  return r;
}
}  // namespace

TEST_F(CompareTest, CommandLineForms) {
  const std::string ref = flip_data("ldr_ref.png"), a = flip_data("ldr_test_noise.png"),
                    b = flip_data("ldr_test_shift.png");
  // compare TEST REF
  CliRun r = run_cli({a, ref, "--metric", "flip", "--flip-ldr", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["test"], a);
  EXPECT_EQ(j["reference"], ref);
  EXPECT_NEAR(j["metrics"]["flip"]["mean"].get<double>(), 0.081440, 1e-4);
  // compare -r REF -t A B, and --reference REF --test A --test B
  for (const auto& args : {std::vector<std::string>{"-r", ref, "-t", a, b},
                           std::vector<std::string>{"--reference", ref, "--test", a, "--test", b}}) {
    std::vector<std::string> full = args;
    for (const char* s : {"--metric", "flip", "--flip-ldr", "--json"}) full.push_back(s);
    r = run_cli(full);
    ASSERT_EQ(r.code, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["tests"].size(), 2u) << r.out;
    EXPECT_EQ(j["tests"][0]["test"], a);
    EXPECT_EQ(j["tests"][1]["test"], b);
    EXPECT_NEAR(j["tests"][1]["metrics"]["flip"]["mean"].get<double>(), 0.295312, 1e-4);
  }
  // FLIP's HDR options by name, and --threshold's exit code.
  r = run_cli({flip_data("hdr_bimodal_test.exr"), flip_data("hdr_bimodal_ref.exr"), "--metric", "flip", "--json",
               "--tone-mapper", "HABLE", "--num-exposures", "4", "--start-exposure", "-3.6411", "--threshold", "0.01"});
  EXPECT_EQ(r.code, 1) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["flip"]["tone_mapper"], "hable");
  EXPECT_EQ(j["threshold_exceeded"], true);
  r = run_cli({a, ref, "--metric", "flip", "--pixels-per-degree", "40", "--flip-ldr", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["metrics"]["flip"]["mean"].get<double>(), 0.122746, 1e-4);
  r = run_cli({a, ref, "--metric", "flip", "--monitor-distance", "0.5", "--monitor-width", "0.6",
               "--monitor-width-pixels", "1920", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["flip"]["ppd"].get<double>(), 0.5 * 1920 / 0.6 * M_PI / 180, 1e-9);
  // Mixed or incomplete forms and bad values: exit 2 with a message.
  r = run_cli({a, ref, "--test", b});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("not both forms"), std::string::npos) << r.err;
  r = run_cli({"-t", a});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--test needs --reference"), std::string::npos) << r.err;
  r = run_cli({"-r", ref});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--reference needs one or more --test"), std::string::npos) << r.err;
  r = run_cli({a});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("need TEST and REF"), std::string::npos) << r.err;
  r = run_cli({a, ref, "--num-exposures", "0"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--num-exposures must be an integer >= 1, got 0"), std::string::npos) << r.err;
  r = run_cli({a, ref, "--ppd", "many"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--ppd"), std::string::npos) << r.err;
}

// Hostile input: numbers that would become huge kernels or counts, files that are not regular files
// (a read that never ends, an open that blocks), a header that claims a huge image. Each is exit 2
// with the option or file named, at once.
TEST_F(CompareTest, HostileInputIsBadInputNotACrashOrAHang) {
  gm::write_exr(file("a.exr"), pattern(6, 6), kRec709);
  const auto expect_bad = [&](CompareOptions o, const std::string& needle) {
    if (o.test.empty()) o.test = file("a.exr");
    if (o.ref.empty()) o.ref = file("a.exr");
    EXPECT_EQ(run(o), 2) << needle << ": " << err_.str();
    EXPECT_NE(err_.str().find(needle), std::string::npos) << err_.str();
  };
  CompareOptions o;
  o.ppd = 1e30;
  expect_bad(o, "allowed: up to 1000");
  o = {};
  o.ppd = 1e8;
  expect_bad(o, "--ppd");
  o = {};
  o.monitor_distance = 1e12;
  expect_bad(o, "--monitor-distance");
  o = {};
  o.num_exposures = 1000000000;
  expect_bad(o, "at most 256");
  o = {};
  o.start_exposure = -1e6;
  o.stop_exposure = 1e6;
  expect_bad(o, "at most 256 exposures");
  o = {};
  o.test = "/dev/zero";
  expect_bad(o, "not a regular file");
  const std::string fifo = file("fifo.exr");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  o = {};
  o.ref = fifo;
  expect_bad(o, "not a regular file");
  // An OpenEXR header whose data window claims 100000 x 100000 pixels (the file holds 6 x 6).
  {
    std::ifstream in(file("a.exr"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const std::string key = std::string("dataWindow") + '\0' + "box2i" + '\0';
    const size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos);
    const int32_t box[4] = {0, 0, 99999, 99999};  // after the attribute's 4-byte size
    std::memcpy(&bytes[at + key.size() + 4], box, sizeof box);
    std::ofstream(file("huge.exr"), std::ios::binary) << bytes;
  }
  o = {};
  o.test = file("huge.exr");
  expect_bad(o, "huge.exr");  // OpenImageIO stops at the missing offset table; nothing is allocated
  // A tiled EXR of 20000 x 20000 whose tiles were never written (its offset table is there): the
  // header's size is refused before 1.6 GB are allocated and zero-filled.
  {
    OIIO::ImageSpec spec(20000, 20000, 1, OIIO::TypeDesc::HALF);
    spec.tile_width = spec.tile_height = 256;
    auto out = OIIO::ImageOutput::create("exr");
    ASSERT_TRUE(out && out->open(file("tiles.exr"), spec)) << OIIO::geterror();
    out->close();
  }
  o = {};
  o.test = file("tiles.exr");
  expect_bad(o, "20000x20000");
}

// A one- or two-channel image is read as grey (and alpha), and compare says so.
TEST_F(CompareTest, GreyAndAlphaImagesAreSaidToBeRead) {
  gm::write_exr(file("a.exr"), pattern(6, 6), kRec709);
  Image grey_alpha(6, 6, 2, 0.5f);
  gm::write_exr_data(file("ga.exr"), grey_alpha);
  CompareOptions o;
  o.test = file("ga.exr");
  o.ref = file("a.exr");
  EXPECT_EQ(run(o), 0) << err_.str();
  EXPECT_NE(err_.str().find("has 2 channels: read as grey (the first) and alpha (the second)"), std::string::npos)
      << err_.str();
}

// `glintlab measure` and frame sources of experiment files, end to end: glintlab's own sequences
// written with `"output": {"motion": true}` and read back (every motion convention, depth-only
// disocclusion, estimated flow, wrong conventions), a real Cycles sequence (tests/data/blender),
// no reference, resume, and bad input.
#include "core/util/content_hash.h"
#include "experiments/cli/check.h"
#include "experiments/runner/measure.h"
#include "experiments/sources/motion_convention.h"
#include "experiments/sources/sequence.h"
#include "experiments/runner/runner.h"
#include "metrics/color/image_io.h"

#include "tests/support/csv.h"
#include "tests/support/temp_dir.h"
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

// A pan over glinting sand (about 2 px/frame across and 0.7 down at 96x54): no AA, 4x4 SSAA and TAA against an 8x8 truth,
// with the float EXRs and the motion vectors written out.
const char* kOrbit = R"({
  "name": "measure-orbit",
  "resolution": [96, 54],
  "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 48, "amplitude": 0.4, "wavelength": 5},
            "sky": {"turbidity": 3, "sky_intensity": 0.5, "sun_elevation_deg": 25, "sun_azimuth_deg": 30, "sun_intensity": 6}},
  "camera_path": {"type": "keyframes", "fps": 30, "frames": 8, "interpolation": "linear", "keyframes": [
      {"time": 0.0, "position": [-3.6252, 1.6905, 0.0], "target": [0, 0, 0], "fov": 10},
      {"time": 0.2333333, "position": [-3.6252, 1.7305, 0.1], "target": [0, 0.04, 0.1], "fov": 10}]},
  "material": {"preset": "thesis-hdri-match", "noise_scale": 400, "glint_sigma": 0.002, "I_glints": [20, 20, 20],
               "sigmoid_a": 2, "sigmoid_b": 6},
  "variants": [{"name": "no-aa"}, {"name": "ssaa-4x4", "aa": "ssaa", "ssaa_grid": 4}, {"name": "taa", "aa": "taa"}],
  "reference": {"grid": 8},
  "metrics": ["deltaE2000", "flip"],
  "output": {"exr": true, "png": false, "every": 1, "motion": true}
})";

std::string frame_name(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", k);
  return name;
}

using Rows = std::map<std::pair<std::string, int>, std::map<std::string, std::string>>;

Rows read_csv(const fs::path& p) {
  Rows rows;
  for (auto& r : test::read_csv_rows(p)) rows[{r["variant"], std::stoi(r["frame"])}] = r;
  return rows;
}

double cell(const Rows& rows, const std::string& variant, int frame, const std::string& column) {
  const auto& r = rows.at({variant, frame});
  const std::string& s = r.at(column);
  return s.empty() ? std::nan("") : std::stod(s);
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

double summary_mean(const nlohmann::json& s, const std::string& variant, const std::string& metric) {
  for (const auto& v : s.at("variants"))
    if (v.at("name") == variant) {
      if (!v.at("metrics").contains(metric)) return std::nan("");
      const auto& m = v.at("metrics").at(metric).at("mean");
      return m.is_number() ? m.get<double>() : std::nan("");
    }
  return std::nan("");
}

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Writes a float EXR with the given channel names.
void write_channels(const fs::path& path, const Image& img, const std::vector<std::string>& names) {
  OIIO::ImageSpec spec(img.width, img.height, img.channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  spec.alpha_channel = -1;
  auto out = OIIO::ImageOutput::create("exr");
  ASSERT_TRUE(out && out->open(path.string(), spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, img.data.data()));
  out->close();
}

class Measure : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("measure");
    std::ofstream(*dir_ / "orbit.json") << kOrbit;
    RunOptions opt;
    opt.report = false;
    opt.experiment = (*dir_ / "orbit.json").string();
    opt.out_dir = run_dir().string();
    opt.cache_dir = (*dir_ / "cache").string();
    opt.validation = true;
    std::ostringstream log;
    ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path run_dir() { return *dir_ / "run"; }
  static fs::path scratch(const std::string& name) { return *dir_ / name; }

  // glintlab's motion frames read back, in glintlab's convention with their distances.
  static std::vector<MotionVectors> own_vectors() {
    std::vector<MotionVectors> out;
    for (int k = 0; k < 8; ++k) {
      const std::string name = frame_name(k);
      const Image m = metrics::read_image((run_dir() / "motion" / name).string());
      MotionVectors v;
      v.backward = Image(m.width, m.height, 2);
      v.distances = Image(m.width, m.height, 2);
      for (size_t i = 0; i < m.pixel_count(); ++i) {
        v.backward.data[2 * i] = m.data[4 * i], v.backward.data[2 * i + 1] = m.data[4 * i + 1];
        v.distances->data[2 * i] = m.data[4 * i + 2], v.distances->data[2 * i + 1] = m.data[4 * i + 3];
      }
      out.push_back(std::move(v));
    }
    for (size_t k = 0; k < out.size(); ++k)  // the vector to the next frame: the next frame's backward one
      out[k].forward = out[std::min(k + 1, out.size() - 1)].backward;
    return out;
  }

  // The motion sequence in convention c (no distances but for `pixels` when keep_distances), scaled
  // by (sx, sy) in glintlab's convention first (mirrors), under dir/ as frame_NNNN.exr.
  static fs::path write_motion(const std::string& dirname, MotionConvention c, bool keep_distances, double sx = 1,
                               double sy = 1) {
    const fs::path dir = scratch(dirname);
    fs::create_directories(dir);
    const std::string layer = c == MotionConvention::Blender ? "ViewLayer.Vector." : "";
    for (const auto& [k, v0] : [&] {
           std::vector<std::pair<int, MotionVectors>> all;
           int k = 0;
           for (auto& v : own_vectors()) all.emplace_back(k++, std::move(v));
           return all;
         }()) {
      MotionVectors v = v0;
      if (!keep_distances) v.distances.reset();
      for (Image* img : {&v.backward, v.forward ? &*v.forward : nullptr})
        if (img)
          for (size_t i = 0; i < img->pixel_count(); ++i) img->data[2 * i] *= float(sx), img->data[2 * i + 1] *= float(sy);
      const Image raw = to_convention(c, v);
      std::vector<std::string> names;
      if (c == MotionConvention::Blender)
        names = {layer + "X", layer + "Y", layer + "Z", layer + "W"};
      else
        names = raw.channels == 4 ? std::vector<std::string>{"R", "G", "B", "A"} : std::vector<std::string>{"R", "G"};
      const std::string name = frame_name(k);
      write_channels(dir / name, raw, names);
    }
    return dir;
  }

  static MeasureOptions own_options(const std::string& out) {
    MeasureOptions o;
    o.reference = (run_dir() / "reference").string();
    for (const char* v : {"no-aa", "ssaa-4x4", "taa"}) o.tests.push_back({v, (run_dir() / v).string(), ""});
    o.out_dir = scratch(out).string();
    o.metrics = {"deltaE2000", "flip"};
    o.report = false;
    return o;
  }

  static int measure(const MeasureOptions& o, std::string* log_text = nullptr) {
    std::ostringstream log;
    const int rc = measure_sequences(o, log);
    if (log_text) *log_text = log.str();
    return rc;
  }

  static test::TempDir* dir_;
};
test::TempDir* Measure::dir_ = nullptr;

const char* const kVariants[] = {"no-aa", "ssaa-4x4", "taa"};

}  // namespace

// With glintlab's own vectors and distance channels, measure reproduces run's per-frame metrics.
TEST_F(Measure, OwnSequenceReproducesTheRunExactly) {
  MeasureOptions o = own_options("own");
  o.motion = (run_dir() / "motion").string();
  std::string log;
  ASSERT_EQ(measure(o, &log), 0) << log;
  const Rows run = read_csv(run_dir() / "frames.csv"), got = read_csv(scratch("own") / "frames.csv");
  int compared = 0;
  for (const char* v : kVariants)
    for (int k = 0; k < 8; ++k)
      for (const char* m : {"flicker_ratio", "temporal_error_mc", "temporal_error", "temporal_score", "deltaE2000",
                            "flip", "flicker_contrast", "glint_density_test", "pooled_error", "flicker_valid_px"}) {
        const double a = cell(run, v, k, m), b = cell(got, v, k, m);
        if (std::isnan(a)) {
          EXPECT_TRUE(std::isnan(b)) << v << " frame " << k << " " << m;
          continue;
        }
        EXPECT_NEAR(b, a, 1e-6 * std::abs(a)) << v << " frame " << k << " " << m;
        ++compared;
      }
  EXPECT_GT(compared, 3 * 7 * 8);
  const nlohmann::json s = read_json(scratch("own") / "summary.json");
  EXPECT_EQ(s["schema"], "glintlab-summary/1");
  EXPECT_EQ(s["motion"], "exact");
  EXPECT_EQ(s["disocclusion"], "glintlab's distance channels");
  EXPECT_TRUE(s["warnings"].empty()) << s["warnings"];
  // The truth's glints twinkle as the view turns: the vectors explain part of its change, and much
  // more of it than their mirror images do.
  const auto& me = s["motion_explained"];
  EXPECT_LT(me["mean"].get<double>(), 1.0) << me;
  for (const char* mirror : {"negated", "flip_y", "flip_x"})
    EXPECT_LT(me["mean"].get<double>(), 0.98 * me[mirror].get<double>()) << mirror << ": " << me;
}

// --view: temporal_score through another OCIO view (the display-referred frames' sRGB/Standard instead
// of the default ACES tone curve) changes it and is recorded; every other metric stays as it was. A
// display or view the config lacks is exit 2 naming --view and what is allowed, before any output.
TEST_F(Measure, ViewChoosesTheDisplayOfTemporalScore) {
  MeasureOptions standard = own_options("view-standard");
  standard.display = "sRGB", standard.view = "Standard";
  std::string log;
  ASSERT_EQ(measure(standard, &log), 0) << log;
  ASSERT_EQ(measure(own_options("view-default"), &log), 0) << log;
  const nlohmann::json a = read_json(scratch("view-default") / "summary.json"),
                       b = read_json(scratch("view-standard") / "summary.json");
  EXPECT_EQ(a["temporal_score_view"], "sRGB/ACES 1.0 SDR-video");
  EXPECT_EQ(b["temporal_score_view"], "sRGB/Standard");
  for (const char* v : kVariants) {
    EXPECT_NE(summary_mean(a, v, "temporal_score"), summary_mean(b, v, "temporal_score")) << v;
    for (const char* m : {"deltaE2000", "flip", "temporal_error_mc", "flicker_excess"})
      EXPECT_EQ(summary_mean(a, v, m), summary_mean(b, v, m)) << v << " " << m;
  }
  for (const auto& [display, view, says] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"sRGB", "Nope", "display \"sRGB\" has no view \"Nope\"; allowed: "}, {"Nope", "Standard", "unknown display"}}) {
    MeasureOptions bad = own_options("view-bad");
    bad.display = display, bad.view = view;
    EXPECT_EQ(measure(bad, &log), 2) << log;
    EXPECT_NE(log.find("--view: " + says), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(scratch("view-bad"))) << "nothing written before the check";
  }
}

// --metrics names groups too: deltaE2000,flicker measures those two alone (no glint or pooled columns,
// no time spent on them), deltaE2000,glints adds the glint statistics; the values measured are those of
// the run that measures every group.
TEST_F(Measure, MetricGroupsMeasureJustWhatIsNamed) {
  auto run_with = [&](const std::string& out, std::vector<std::string> metrics_list) {
    MeasureOptions o = own_options(out);
    o.motion = (run_dir() / "motion").string();
    o.metrics = std::move(metrics_list);
    std::string log;
    EXPECT_EQ(measure(o, &log), 0) << log;
    return read_csv(scratch(out) / "frames.csv");
  };
  const Rows every = run_with("groups-every", {"deltaE2000"});
  const Rows pair = run_with("groups-pair", {"deltaE2000", "flicker"});
  const Rows glints = run_with("groups-glints", {"glints", "deltaE2000"});
  const auto& every_row = every.at({"taa", 3});
  const auto& pair_row = pair.at({"taa", 3});
  const auto& glint_row = glints.at({"taa", 3});
  for (const char* c : {"glint_density_test", "glint_hist_emd_oct", "pooled_error", "pooled_rms_8"}) {
    EXPECT_TRUE(every_row.count(c)) << c;
    EXPECT_FALSE(pair_row.count(c)) << c;
  }
  EXPECT_TRUE(glint_row.count("glint_density_test"));
  EXPECT_FALSE(glint_row.count("pooled_error"));
  int compared = 0;
  for (const char* v : kVariants)
    for (int k = 0; k < 8; ++k) {
      for (const char* m : {"deltaE2000", "flicker_ratio", "temporal_error_mc", "flicker_contrast", "motion_explained"}) {
        const double a = cell(every, v, k, m);
        if (std::isnan(a)) continue;
        EXPECT_EQ(cell(pair, v, k, m), a) << v << " frame " << k << " " << m;
        ++compared;
      }
      EXPECT_EQ(cell(glints, v, k, "glint_density_test"), cell(every, v, k, "glint_density_test")) << v << " " << k;
    }
  EXPECT_GT(compared, 3 * 7 * 4);
  const nlohmann::json s = read_json(scratch("groups-pair") / "summary.json");
  EXPECT_FALSE(s["variants"][0]["metrics"].contains("pooled_error")) << s["variants"][0]["metrics"];
  EXPECT_TRUE(s["variants"][0]["metrics"].contains("flicker_ratio"));
}

// Every convention round-trips: vectors converted into it and read back give the metrics of
// glintlab's own vectors without distances (same disocclusion rule), to float precision.
TEST_F(Measure, EveryConventionRoundTrips) {
  MeasureOptions base = own_options("conv-base");
  base.motion = write_motion("motion-pixels2", MotionConvention::Pixels, false).string();
  ASSERT_EQ(measure(base), 0);
  const Rows want = read_csv(scratch("conv-base") / "frames.csv");
  for (const auto& [c, name] : kMotionConventionNames) {
    if (c == MotionConvention::Blender) continue;  // has vectors to the next frame: its own disocclusion, below
    MeasureOptions o = own_options(std::string("conv-") + name);
    o.motion = write_motion(std::string("motion-") + name, c, false).string();
    o.motion_convention = name;
    std::string log;
    ASSERT_EQ(measure(o, &log), 0) << name << ": " << log;
    const Rows got = read_csv(scratch(std::string("conv-") + name) / "frames.csv");
    for (const char* v : kVariants)
      for (int k = 1; k < 8; ++k)
        for (const char* m : {"flicker_ratio", "temporal_error_mc", "motion_explained"})
          EXPECT_NEAR(cell(got, v, k, m), cell(want, v, k, m), 1e-5 * std::abs(cell(want, v, k, m)))
              << name << " " << v << " frame " << k << " " << m;
  }
  // Blender's pair of vectors: forward-backward consistency masks nothing on a camera orbit that
  // hides nothing, so its metrics are those of the same vectors without the forward pair.
  MeasureOptions o = own_options("conv-blender");
  o.motion = write_motion("motion-blender", MotionConvention::Blender, false).string() + "/frame_####.exr:ViewLayer.Vector";
  o.motion_convention = "blender";
  std::string log;
  ASSERT_EQ(measure(o, &log), 0) << log;
  const nlohmann::json s = read_json(scratch("conv-blender") / "summary.json");
  EXPECT_EQ(s["disocclusion"], "forward-backward consistency");
  const Rows got = read_csv(scratch("conv-blender") / "frames.csv");
  for (const char* v : kVariants)
    for (int k = 1; k < 7; ++k)
      EXPECT_NEAR(cell(got, v, k, "flicker_ratio"), cell(want, v, k, "flicker_ratio"),
                  2e-3 * cell(want, v, k, "flicker_ratio"))
          << v << " frame " << k;
}

// Depth instead of glintlab's distance channels: the disocclusion rule differs (the depth now
// against the previous frame's depth at the reprojected point), so the figures move a little; the
// ranking does not.
TEST_F(Measure, DepthOnlyDisocclusionStaysCloseToTheExactRule) {
  const fs::path depth = scratch("depth");
  fs::create_directories(depth);
  const auto vectors = own_vectors();
  for (int k = 0; k < 8; ++k) {
    Image d(vectors[size_t(k)].backward.width, vectors[size_t(k)].backward.height, 1);
    for (size_t i = 0; i < d.pixel_count(); ++i) d.data[i] = vectors[size_t(k)].distances->data[2 * i];
    const std::string name = frame_name(k);
    write_channels(depth / name, d, {"Z"});
  }
  MeasureOptions o = own_options("depth-only");
  o.motion = write_motion("motion-pixels2-depth", MotionConvention::Pixels, false).string();
  o.depth = depth.string();
  ASSERT_EQ(measure(o), 0);
  const nlohmann::json s = read_json(scratch("depth-only") / "summary.json");
  EXPECT_EQ(s["disocclusion"], "depth");
  const nlohmann::json run = read_json(run_dir() / "summary.json");
  for (const char* v : kVariants) {
    const double exact = summary_mean(run, v, "flicker_ratio"), got = summary_mean(s, v, "flicker_ratio");
    std::cout << "[ measure ] " << v << " flicker_ratio exact " << exact << ", depth-only " << got << "\n";
    EXPECT_NEAR(got, exact, 0.02 * exact) << v;
  }
  EXPECT_GT(summary_mean(s, "no-aa", "flicker_ratio"), summary_mean(s, "ssaa-4x4", "flicker_ratio"));
  EXPECT_GT(summary_mean(s, "ssaa-4x4", "flicker_ratio"), summary_mean(s, "taa", "flicker_ratio"));
}

// Vectors in a wrong convention do not pass silently: negated or with y flipped, a mirror image
// explains the reference's change better, and the run says so in its log and summary.
TEST_F(Measure, WrongSignOrYAxisWarns) {
  struct Case {
    const char* name;
    double sx, sy;
    const char* says;
  };
  for (const Case& c : {Case{"negated", -1, -1, "sign"}, Case{"y-flipped", 1, -1, "y axis"}}) {
    MeasureOptions o = own_options(std::string("wrong-") + c.name);
    o.motion = write_motion(std::string("motion-") + c.name, MotionConvention::Pixels, false, c.sx, c.sy).string();
    std::string log;
    ASSERT_EQ(measure(o, &log), 0) << log;
    const nlohmann::json s = read_json(scratch(std::string("wrong-") + c.name) / "summary.json");
    ASSERT_EQ(s["warnings"].size(), 1u) << c.name << ": " << s["motion_explained"];
    EXPECT_NE(s["warnings"][0].get<std::string>().find(c.says), std::string::npos) << s["warnings"][0];
    EXPECT_NE(log.find("warning: the motion vectors look wrong"), std::string::npos) << log;
  }
}

// Without vectors the flow is estimated (OpenCV DIS), marked so, and ranks the variants as the
// exact vectors do.
TEST_F(Measure, EstimatedFlowRanksLikeExactVectors) {
  MeasureOptions o = own_options("estimated");
  std::string log;
  ASSERT_EQ(measure(o, &log), 0) << log;
  EXPECT_NE(log.find("estimated"), std::string::npos);
  const nlohmann::json s = read_json(scratch("estimated") / "summary.json");
  const nlohmann::json run = read_json(run_dir() / "summary.json");
  EXPECT_EQ(s["motion"], "estimated");
  for (const char* v : kVariants)
    std::cout << "[ measure ] " << v << " flicker_ratio exact " << summary_mean(run, v, "flicker_ratio")
              << ", estimated flow " << summary_mean(s, v, "flicker_ratio") << "\n";
  for (const auto* sum : {&run, &s}) {
    EXPECT_GT(summary_mean(*sum, "no-aa", "flicker_ratio"), summary_mean(*sum, "ssaa-4x4", "flicker_ratio"));
    EXPECT_GT(summary_mean(*sum, "ssaa-4x4", "flicker_ratio"), summary_mean(*sum, "taa", "flicker_ratio"));
  }
  EXPECT_LT(s["motion_explained"]["mean"].get<double>(), 1.0);
  EXPECT_TRUE(s["warnings"].empty()) << s["warnings"];
}

// A real renderer none of us wrote: Cycles renders the same camera move at 1, 4 and 16 samples per
// pixel and at 4096 (tests/data/blender/make.sh). Fewer samples flicker more, the Vector pass
// explains the reference's motion in Blender's convention, and read as glintlab's it is flagged.
TEST_F(Measure, BlenderCyclesSequence) {
  const std::string d = std::string(GLINTLAB_TEST_DATA_DIR) + "/blender/";
  MeasureOptions o;
  o.reference = d + "ref/frame_####.exr:ViewLayer.Combined";
  for (const char* spp : {"spp1", "spp4", "spp16"}) o.tests.push_back({spp, d + spp + "/frame_####.exr:ViewLayer.Combined", ""});
  o.motion_from = "reference";
  o.motion_convention = "blender";
  o.depth = d + "ref/frame_####.exr:ViewLayer.Depth";
  o.out_dir = scratch("blender").string();
  o.report = false;
  std::string log;
  ASSERT_EQ(measure(o, &log), 0) << log;
  const nlohmann::json s = read_json(scratch("blender") / "summary.json");
  EXPECT_EQ(s["disocclusion"], "depth, and forward-backward consistency");
  const double f1 = summary_mean(s, "spp1", "flicker_ratio"), f4 = summary_mean(s, "spp4", "flicker_ratio"),
               f16 = summary_mean(s, "spp16", "flicker_ratio");
  std::cout << "[ measure ] Cycles flicker_ratio spp1 " << f1 << ", spp4 " << f4 << ", spp16 " << f16
            << "; motion_explained " << s["motion_explained"] << "\n";
  EXPECT_GT(f1, f4);
  EXPECT_GT(f4, f16);
  EXPECT_GT(f16, 1.05);
  const auto& me = s["motion_explained"];
  EXPECT_LT(me["mean"].get<double>(), 0.9);
  for (const char* mirror : {"negated", "flip_y", "flip_x"}) EXPECT_LT(me["mean"].get<double>(), me[mirror].get<double>());
  EXPECT_TRUE(s["warnings"].empty()) << s["warnings"];

  // The same Vector pass read as glintlab's own convention (sign and y axis both wrong).
  MeasureOptions wrong = o;
  wrong.motion_from.clear();
  wrong.motion = d + "ref/frame_####.exr:ViewLayer.Vector";
  wrong.motion_convention = "pixels";
  wrong.depth.clear();
  wrong.out_dir = scratch("blender-wrong").string();
  ASSERT_EQ(measure(wrong, &log), 0) << log;
  const nlohmann::json w = read_json(scratch("blender-wrong") / "summary.json");
  EXPECT_FALSE(w["warnings"].empty()) << w["motion_explained"];
}

// Without a reference: each test's own flicker along the motion, which `check` gates on.
TEST_F(Measure, NoReferenceGivesFlickerContrastThatCheckGates) {
  MeasureOptions o = own_options("no-ref");
  o.reference.clear();
  o.motion = (run_dir() / "motion").string();
  ASSERT_EQ(measure(o), 0);
  const nlohmann::json s = read_json(scratch("no-ref") / "summary.json");
  const double a = summary_mean(s, "no-aa", "flicker_contrast"), b = summary_mean(s, "ssaa-4x4", "flicker_contrast"),
               t = summary_mean(s, "taa", "flicker_contrast");
  EXPECT_GT(a, b);
  EXPECT_GT(b, t);
  EXPECT_TRUE(std::isnan(summary_mean(s, "no-aa", "flicker_ratio")));
  // The same as with a reference: flicker_contrast is the test's alone.
  const nlohmann::json with_ref = read_json(run_dir() / "summary.json");
  EXPECT_NEAR(a, summary_mean(with_ref, "no-aa", "flicker_contrast"), 1e-9 * a);
  // check: the summary against itself passes; against a baseline 10 % steadier it fails.
  const auto same = check_summary(s, s, default_check_tolerances());
  EXPECT_FALSE(same.empty());
  for (const CheckRow& r : same) EXPECT_FALSE(r.regression) << r.variant << " " << r.metric << " " << r.note;
  nlohmann::json baseline = s;
  for (auto& v : baseline["variants"]) v["metrics"]["flicker_contrast"]["mean"] = v["metrics"]["flicker_contrast"]["mean"].get<double>() / 1.1;
  const auto rows = check_summary(s, baseline, default_check_tolerances());
  EXPECT_TRUE(std::any_of(rows.begin(), rows.end(),
                          [](const CheckRow& r) { return r.regression && r.metric == "flicker_contrast"; }));
}

// A killed measurement resumes to the same rows; a resume whose input files changed is refused.
TEST_F(Measure, ResumeRedoesOnlyWhatIsMissingAndRefusesChangedFiles) {
  MeasureOptions o = own_options("resume");
  o.motion = (run_dir() / "motion").string();
  ASSERT_EQ(measure(o), 0);
  // frames.csv without wall_ms (the time it took to read the files, which differs between runs).
  auto rows_without_timing = [&] {
    Rows rows = read_csv(scratch("resume") / "frames.csv");
    for (auto& [key, r] : rows) r.erase("wall_ms");
    return rows;
  };
  const Rows full = rows_without_timing();
  // Keep the header, the references and the first 10 frame records (as a killed run leaves them).
  {
    std::ifstream in(scratch("resume") / "records.jsonl");
    std::string line, kept;
    int frames = 0;
    while (std::getline(in, line)) {
      const bool frame = line.find("\"type\":\"frame\"") != std::string::npos;
      if (frame && ++frames > 10) continue;
      kept += line + "\n";
    }
    std::ofstream(scratch("resume") / "records.jsonl") << kept << "{\"type\":\"fra";  // and a torn line
  }
  o.resume = true;
  std::string log;
  ASSERT_EQ(measure(o, &log), 0) << log;
  EXPECT_NE(log.find("resume: 10 frame record(s) done"), std::string::npos) << log;
  EXPECT_EQ(rows_without_timing(), full);
  // Another file in place of one frame: the resume is refused, naming what differs.
  fs::copy_file(run_dir() / "no-aa" / "frame_0003.exr", scratch("frame_0003.exr"));
  fs::copy_file(run_dir() / "ssaa-4x4" / "frame_0003.exr", run_dir() / "no-aa" / "frame_0003.exr",
                fs::copy_options::overwrite_existing);
  const int rc = measure(o, &log);
  fs::copy_file(scratch("frame_0003.exr"), run_dir() / "no-aa" / "frame_0003.exr", fs::copy_options::overwrite_existing);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(log.find("inputs"), std::string::npos) << log;
}

// An experiment file can put glintlab's variants beside frames read from files, and a file without
// "scene" is a measurement of files alone.
TEST_F(Measure, ExperimentFilesTakeFrameSources) {
  nlohmann::json mixed = nlohmann::json::parse(kOrbit);
  mixed["variants"].push_back({{"name", "engine"}, {"frames", (run_dir() / "taa").string()}});
  mixed["output"] = {{"exr", false}, {"png", false}};
  std::ofstream(scratch("mixed.json")) << mixed.dump();
  RunOptions opt;
  opt.report = false;
  opt.experiment = scratch("mixed.json").string();
  opt.out_dir = scratch("mixed").string();
  opt.cache_dir = scratch("cache").string();
  opt.validation = true;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  const Rows rows = read_csv(scratch("mixed") / "frames.csv");
  for (int k = 0; k < 8; ++k)  // the frames of the taa variant, read back: the same numbers
    for (const char* m : {"deltaE2000", "flicker_ratio", "temporal_error_mc"})
      EXPECT_EQ(rows.at({"engine", k}).at(m), rows.at({"taa", k}).at(m)) << k << " " << m;
  const nlohmann::json s = read_json(scratch("mixed") / "summary.json");
  EXPECT_EQ(s["variants"][3]["source"], "frames");

  const nlohmann::json only = {
      {"name", "files-only"},
      {"reference", {{"frames", "run/reference"}}},
      {"variants", {{{"name", "no-aa"}, {"frames", "run/no-aa"}}, {{"name", "taa"}, {"frames", "run/taa"}}}},
      {"motion", {{"frames", "run/motion"}, {"convention", "pixels"}}},
      {"metrics", {"deltaE2000"}}};
  std::ofstream(scratch("only.json")) << only.dump();  // paths relative to the file
  opt.experiment = scratch("only.json").string();
  opt.out_dir = scratch("only").string();
  ASSERT_EQ(run_experiment(opt, log), 0) << log.str();
  const Rows got = read_csv(scratch("only") / "frames.csv"), run = read_csv(run_dir() / "frames.csv");
  for (int k = 1; k < 8; ++k)
    EXPECT_NEAR(cell(got, "taa", k, "flicker_ratio"), cell(run, "taa", k, "flicker_ratio"),
                1e-6 * cell(run, "taa", k, "flicker_ratio"));
  EXPECT_EQ(read_json(scratch("only") / "summary.json")["experiment"], "files-only");
}

// Bad input: a clear error before anything is measured, or a count and NaN metrics with exit 1.
TEST_F(Measure, BadInputIsAnErrorOrACount) {
  struct Case {
    const char* what;
    std::function<void(MeasureOptions&)> edit;
    const char* says;
  };
  const fs::path small = scratch("small");
  fs::create_directories(small);
  for (int k = 0; k < 8; ++k) {
    const std::string name = frame_name(k);
    metrics::write_exr_data((small / name).string(), Image(48, 27, 4, 0.5f));
  }
  const fs::path tiny = scratch("tiny");
  fs::create_directories(tiny);
  for (int k = 0; k < 8; ++k) metrics::write_exr_data((tiny / frame_name(k)).string(), Image(40, 12, 4, 0.5f));
  const fs::path gap = scratch("gap"), few = scratch("few");
  fs::create_directories(gap);
  fs::create_directories(few);
  for (int k = 0; k < 8; ++k) {
    const std::string name = frame_name(k);
    if (k != 4) fs::copy_file(run_dir() / "no-aa" / name, gap / name);
    if (k < 6) fs::copy_file(run_dir() / "no-aa" / name, few / name);
  }
  // A frame cut short in the middle of the sequence (its header intact), a frame given twice with two
  // paddings, one padded otherwise, and a sequence of one frame.
  const fs::path cut = scratch("cut"), twins = scratch("twins"), padded = scratch("padded"), one = scratch("one");
  for (const fs::path& d : {cut, twins, padded, one}) fs::create_directories(d);
  for (int k = 0; k < 8; ++k)
    for (const fs::path& d : {cut, twins, padded}) fs::copy_file(run_dir() / "no-aa" / frame_name(k), d / frame_name(k));
  fs::resize_file(cut / frame_name(5), fs::file_size(cut / frame_name(5)) / 2);
  fs::copy_file(run_dir() / "no-aa" / frame_name(1), twins / "frame_1.exr");
  fs::copy_file(run_dir() / "no-aa" / frame_name(7), padded / "frame_09.exr");
  fs::copy_file(run_dir() / "no-aa" / frame_name(4), one / frame_name(4));
  const std::vector<Case> cases = {
      {"colour read as motion (--motion-from a file without a vector layer)",
       [&](MeasureOptions& o) { o.motion_from = "reference"; }, "has no layer of pixels vectors"},
      {"a frame rate that makes time_s infinite", [&](MeasureOptions& o) { o.fps = 1e-320; }, "--fps: 9.99989e-321 is not allowed"},
      {"a frame rate above the range", [&](MeasureOptions& o) { o.fps = 1001; }, "in [0.001, 1000]"},
      {"a truncated frame mid-sequence", [&](MeasureOptions& o) { o.tests[1].seq = cut.string(); },
       "frame_0005.exr' is truncated or damaged"},
      {"one frame under two names", [&](MeasureOptions& o) { o.tests[0].seq = twins.string(); },
       "'frame_1.exr' and 'frame_0001.exr', both frame 1"},
      {"a frame padded otherwise", [&](MeasureOptions& o) { o.tests[0].seq = padded.string(); },
       "'frame_09.exr', whose number is padded otherwise"},
      {"a sequence of one frame", [&](MeasureOptions& o) { o.tests[0].seq = one.string(); },
       "has no frame 0 (it has 1 frame, 4)"},
      {"another size", [&](MeasureOptions& o) { o.tests[0].seq = small.string(); }, "48x27"},
      {"fewer frames", [&](MeasureOptions& o) { o.tests[0].seq = few.string(); }, "no frame 6"},
      {"a gap", [&](MeasureOptions& o) { o.tests[0].seq = gap.string(); }, "no frame 4"},
      {"a gap in the reference", [&](MeasureOptions& o) { o.reference = gap.string(); }, "gap: frame 4 missing"},
      {"no such layer", [&](MeasureOptions& o) { o.tests[0].seq += "/frame_####.exr:ViewLayer.Combined"; },
       "the file has: R, G, B, A"},
      {"vectors the convention cannot read",
       [&](MeasureOptions& o) { o.motion = (run_dir() / "motion").string(), o.motion_convention = "blender"; },
       "the file has: R, G, B, A"},
      {"an unknown convention", [&](MeasureOptions& o) { o.motion_convention = "maya"; }, "pixels"},
      {"no file matches", [&](MeasureOptions& o) { o.tests[0].seq = (run_dir() / "nope.%04d.exr").string(); },
       "no file matches"},
      {"a folder of several sequences", [&](MeasureOptions& o) { o.tests[0].seq = run_dir().string(); },
       "no numbered image files"},
      {"a range without frames", [&](MeasureOptions& o) { o.first = 100, o.last = 200; }, "none in 100:200"},
      {"a reserved name", [&](MeasureOptions& o) { o.tests[0].name = "reference"; }, "the run folder's own names"},
      {"a name with a path in it", [&](MeasureOptions& o) { o.tests[0].name = ".."; }, "not allowed"},
      {"two tests of one name", [&](MeasureOptions& o) { o.tests[1].name = "no-aa"; }, "two tests are named"},
      {"an unknown metric", [&](MeasureOptions& o) { o.metrics = {"mse"}; }, "neither a metric nor a group"},
      {"frames too small for optical flow",
       [&](MeasureOptions& o) { o.reference = tiny.string(), o.tests = {{"t", tiny.string(), ""}}; },
       "needs frames of at least 16 pixels on the short side"},
  };
  for (const Case& c : cases) {
    MeasureOptions o = own_options(std::string("bad-") + std::to_string(&c - cases.data()));
    c.edit(o);
    std::string log;
    EXPECT_EQ(measure(o, &log), 2) << c.what << ": " << log;
    EXPECT_NE(log.find(c.says), std::string::npos) << c.what << ": " << log;
    EXPECT_FALSE(fs::exists(o.out_dir)) << c.what << ": wrote " << o.out_dir;
  }

  // NaN, Inf and negative pixels in a test frame, NaN vectors: counted, the frame's metrics NaN, exit 1.
  const fs::path bad = scratch("bad-pixels"), badv = scratch("bad-vectors");
  fs::create_directories(bad);
  fs::create_directories(badv);
  for (int k = 0; k < 8; ++k) {
    const std::string name = frame_name(k);
    Image img = metrics::read_image((run_dir() / "no-aa" / name).string());
    Image mv = metrics::read_image((run_dir() / "motion" / name).string());
    if (k == 5) {
      img.at(3, 3, 0) = std::nanf(""), img.at(4, 3, 1) = INFINITY, img.at(5, 3, 2) = -1.0f;
      mv.at(7, 7, 0) = std::nanf("");
    }
    metrics::write_exr_data((bad / name).string(), img);
    metrics::write_exr_data((badv / name).string(), mv);
  }
  MeasureOptions o = own_options("bad-counted");
  o.tests[0].seq = bad.string();
  o.motion = badv.string();
  std::string log;
  EXPECT_EQ(measure(o, &log), 1) << log;
  const Rows rows = read_csv(scratch("bad-counted") / "frames.csv");
  EXPECT_EQ(cell(rows, "no-aa", 5, "nan_px"), 1);
  EXPECT_EQ(cell(rows, "no-aa", 5, "inf_px"), 1);
  EXPECT_EQ(cell(rows, "no-aa", 5, "negative_px"), 1);
  EXPECT_TRUE(std::isnan(cell(rows, "no-aa", 5, "deltaE2000")));
  EXPECT_TRUE(std::isnan(cell(rows, "no-aa", 5, "flicker_ratio")));
  EXPECT_FALSE(std::isnan(cell(rows, "no-aa", 4, "deltaE2000")));
  EXPECT_EQ(cell(rows, "taa", 5, "motion_nonfinite_px"), 1);
  EXPECT_FALSE(std::isnan(cell(rows, "taa", 5, "flicker_ratio")));
  const nlohmann::json s = read_json(scratch("bad-counted") / "summary.json");
  EXPECT_TRUE(s["variants"][0]["metrics"]["deltaE2000"]["mean"].is_null());
  EXPECT_FALSE(fs::exists(scratch("bad-counted") / ".glintlab.lock"));  // released and removed at exit 1 too
}

// A folder that holds another command's outputs is refused without --resume, both ways: `measure`
// would replace a run's records, frames.csv and summary.json and leave its images beside them.
TEST_F(Measure, RefusesAFolderOfAnotherCommand) {
  const fs::path ran = scratch("owned-by-run");
  fs::create_directories(ran);
  fs::copy_file(run_dir() / "records.jsonl", ran / "records.jsonl");
  const std::string journal = file_text(ran / "records.jsonl");
  MeasureOptions o = own_options("owned-by-run");
  o.motion = (run_dir() / "motion").string();
  std::string log;
  EXPECT_EQ(measure(o, &log), 2) << log;
  EXPECT_NE(log.find("holds the outputs of `run`"), std::string::npos) << log;
  EXPECT_TRUE(file_text(ran / "records.jsonl") == journal) << "the run's records.jsonl was replaced";
  EXPECT_FALSE(fs::exists(ran / "summary.json"));

  o.out_dir = scratch("owned-by-measure").string();
  ASSERT_EQ(measure(o, &log), 0) << log;
  EXPECT_FALSE(fs::exists(scratch("owned-by-measure") / ".glintlab.lock"));
  EXPECT_EQ(measure(o, &log), 0) << log;  // the same command again replaces its own outputs
  RunOptions opt;
  opt.report = false;
  opt.experiment = (*dir_ / "orbit.json").string();
  opt.out_dir = scratch("owned-by-measure").string();
  opt.cache_dir = (*dir_ / "cache").string();
  std::ostringstream run_log;
  EXPECT_EQ(run_experiment(opt, run_log), 2) << run_log.str();
  EXPECT_NE(run_log.str().find("holds the outputs of `measure`"), std::string::npos) << run_log.str();
}

// glintlab's own vector files (pixels, with the distance channels) are measured as read, without the
// conversion: that shortcut holds only while the conversion gives them back bit for bit, whatever the
// depth and the vectors of the frame before, NaN and signed zeros included; no other layout takes it.
TEST(MotionConvention, OwnVectorsAreTheFlickerMotionAsRead) {
  Image raw(37, 11, 4);
  for (size_t i = 0; i < raw.data.size(); ++i) raw.data[i] = float(std::sin(double(i) * 1.7)) * 40.0f;
  raw.data[5] = std::nanf(""), raw.data[9] = -0.0f, raw.data[14] = -std::numeric_limits<float>::infinity();
  raw.data[22] = 0.0f, raw.data[31] = -3.0f;  // no surface now; behind the camera before
  MotionChannels own;
  own.backward = {"R", "G"};
  own.distances = {"B", "A"};
  ASSERT_TRUE(is_flicker_motion(MotionConvention::Pixels, own));
  Image depth(37, 11, 1), forward(37, 11, 2);
  for (size_t i = 0; i < depth.data.size(); ++i) depth.data[i] = float(1 + i % 5);
  for (size_t i = 0; i < forward.data.size(); ++i) forward.data[i] = float(i % 7) - 3.0f;
  for (bool with : {false, true}) {
    const Image m = flicker_motion(convert_motion(MotionConvention::Pixels, raw, own), with ? &depth : nullptr,
                                   with ? &forward : nullptr);
    ASSERT_EQ(m.channels, 4);
    ASSERT_EQ(m.data.size(), raw.data.size());
    EXPECT_EQ(std::memcmp(m.data.data(), raw.data.data(), raw.data.size() * sizeof(float)), 0) << with;
  }
  MotionChannels no_distances = own, with_forward = own;
  no_distances.distances.clear();
  with_forward.forward = {"B", "A"};
  EXPECT_FALSE(is_flicker_motion(MotionConvention::Pixels, no_distances));
  EXPECT_FALSE(is_flicker_motion(MotionConvention::Pixels, with_forward));
  for (MotionConvention c : {MotionConvention::Blender, MotionConvention::Unreal, MotionConvention::Unity})
    EXPECT_FALSE(is_flicker_motion(c, own));
}

// The hash the journal records of every input file: XXH3-128 over the file's bytes in 1 MiB pieces,
// each length-prefixed (so journals written before the file was hashed in place still resume).
TEST(FileContentHash, IsTheBytesInMegabytePieces) {
  test::TempDir dir("file_hash");
  std::string bytes(size_t(5) << 19, '\0');  // 2.5 MiB
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = char((i * 2654435761u) >> 13);
  std::ofstream(dir.path() / "f.bin", std::ios::binary) << bytes;
  core::ContentHash h;
  for (size_t o = 0; o < bytes.size(); o += size_t(1) << 20)
    h.add(bytes.data() + o, std::min(size_t(1) << 20, bytes.size() - o));
  EXPECT_EQ(file_content_hash((dir.path() / "f.bin").string()), h.hex());
  std::ofstream(dir.path() / "empty.bin");
  EXPECT_EQ(file_content_hash((dir.path() / "empty.bin").string()), core::ContentHash().hex());
  bytes[bytes.size() / 2] ^= 1;  // one bit elsewhere: another hash
  std::ofstream(dir.path() / "g.bin", std::ios::binary) << bytes;
  EXPECT_NE(file_content_hash((dir.path() / "g.bin").string()), h.hex());
  EXPECT_THROW(file_content_hash((dir.path() / "missing.bin").string()), std::exception);
}

// The truth's halves must be two independent estimates of one image: the same folder or a
// byte-identical copy (a floor of exactly 0), or a half of other channels (a grey half averaged into an
// RGB truth), is exit 2 naming both, before anything is written.
TEST_F(Measure, IdenticalOrIncompatibleHalvesAreRefused) {
  const fs::path ref = run_dir() / "reference";
  const fs::path copy = scratch("halves-copy");
  fs::create_directories(copy);
  for (const auto& e : fs::directory_iterator(ref)) fs::copy_file(e.path(), copy / e.path().filename());
  for (const fs::path& b : {ref, copy}) {
    MeasureOptions o = own_options("halves-same");
    o.reference_b = b.string();
    std::string log;
    EXPECT_EQ(measure(o, &log), 2) << log;
    EXPECT_NE(log.find("same file or the same bytes"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "records.jsonl"));
  }
  // a grey half: the reference's luminance alone, as a Y-only EXR sequence
  const fs::path grey = scratch("halves-grey");
  fs::create_directories(grey);
  for (const auto& e : fs::directory_iterator(ref)) {
    const Image rgb = metrics::read_image(e.path().string());
    Image y(rgb.width, rgb.height, 1);
    for (size_t i = 0; i < size_t(rgb.width) * rgb.height; ++i) y.data[i] = rgb.data[i * rgb.channels + 1];
    write_channels(grey / e.path().filename(), y, {"Y"});
  }
  MeasureOptions o = own_options("halves-grey");
  o.reference_b = grey.string();
  std::string log;
  EXPECT_EQ(measure(o, &log), 2) << log;
  EXPECT_NE(log.find("other channels"), std::string::npos) << log;
}

// One Inf pixel in frame 1 of a test, or of a truth's half: frame 1's metrics are NaN, and so are frame
// 2's temporal metrics (they compare frame 2 with frame 1 along the motion), while its per-frame ones
// stay; frame 3 is clean again. The truth's noise floor takes neither frame in: the summary's stays finite.
TEST_F(Measure, ABadPixelVoidsTheTemporalMetricsOfTheNextFrameAndTheFloor) {
  auto copy_with_inf = [&](const fs::path& from, const std::string& to, float scale) {
    const fs::path dir = scratch(to);
    fs::create_directories(dir);
    for (int k = 0; k < 8; ++k) {
      Image img = metrics::read_image((from / frame_name(k)).string());
      for (float& x : img.data) x *= scale;
      if (k == 1) img.data[size_t(10 * img.width + 10) * img.channels] = std::numeric_limits<float>::infinity();
      write_channels(dir / frame_name(k), img, {"R", "G", "B"});
    }
    return dir;
  };
  MeasureOptions o = own_options("bad-pixel");
  o.tests = {{"inf", copy_with_inf(run_dir() / "no-aa", "bad-test", 1.0f).string(), ""},
             {"no-aa", (run_dir() / "no-aa").string(), ""}};
  o.reference_b = copy_with_inf(run_dir() / "reference", "bad-half-b", 1.01f).string();
  o.motion = (run_dir() / "motion").string();
  std::string log;
  EXPECT_EQ(measure(o, &log), 1) << log;  // the defects are counted: exit 1
  const Rows rows = read_csv(scratch("bad-pixel") / "frames.csv");
  for (const char* v : {"inf", "no-aa"}) {
    SCOPED_TRACE(v);
    EXPECT_TRUE(std::isnan(cell(rows, v, 1, "temporal_error_mc")));
    EXPECT_TRUE(std::isnan(cell(rows, v, 2, "temporal_error_mc")));
    EXPECT_TRUE(std::isnan(cell(rows, v, 2, "flicker_excess")));
    EXPECT_TRUE(std::isfinite(cell(rows, v, 3, "temporal_error_mc")));
    EXPECT_TRUE(std::isfinite(cell(rows, v, 3, "flicker_excess")));
  }
  EXPECT_TRUE(std::isfinite(cell(rows, "inf", 2, "deltaE2000")));  // frame 2's own metrics stand
  EXPECT_TRUE(std::isnan(cell(rows, "no-aa", 2, "floor_temporal_error_mc")));
  EXPECT_TRUE(std::isfinite(cell(rows, "no-aa", 3, "floor_temporal_error_mc")));
  const nlohmann::json s = read_json(scratch("bad-pixel") / "summary.json");
  ASSERT_TRUE(s["references"][0]["floor"]["temporal_error_mc"].is_number()) << s["references"][0].dump();
  EXPECT_TRUE(s["references"][0]["floor"]["flicker_excess"].is_number());
}

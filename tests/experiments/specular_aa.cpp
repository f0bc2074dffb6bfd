// Geometric specular anti-aliasing ("specular_aa") in whole runs on lavapipe: on a plane, where the
// normal does not turn, every method renders the frames of "none" bit for bit (and on waves it does
// not: the option acts); on small waves seen from afar, the case the methods are for, it takes away
// flicker that one sample per pixel adds.
#include "experiments/runner/runner.h"
#include "metrics/color/image_io.h"

#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

RunOptions options(const fs::path& dir) {
  RunOptions opt;
  opt.report = false;
  opt.experiment = (dir / "e.json").string();
  opt.out_dir = (dir / "out").string();
  opt.cache_dir = (dir / "cache").string();
  opt.validation = true;
  return opt;
}

nlohmann::json variants(bool taa) {
  nlohmann::json v = nlohmann::json::array();
  for (const char* m : {"none", "kaplanyan2016", "tokuyoshi2019", "tokuyoshi2021"}) {
    v.push_back({{"name", m}, {"material", {{"specular_aa", m}}}});
    if (taa) v.push_back({{"name", std::string(m) + "-taa"}, {"aa", "taa"}, {"material", {{"specular_aa", m}}}});
  }
  return v;
}

// Every frame of every variant against the same frame of "none" (or "none-taa").
int frames_equal_to_none(const fs::path& out, int frames, bool taa) {
  int equal = 0;
  for (const char* m : {"kaplanyan2016", "tokuyoshi2019", "tokuyoshi2021"})
    for (const std::string suffix : taa ? std::vector<std::string>{"", "-taa"} : std::vector<std::string>{""})
      for (int f = 0; f < frames; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d.exr", f);
        const Image a = metrics::read_image((out / ("none" + suffix) / name).string());
        const Image b = metrics::read_image((out / (m + suffix) / name).string());
        equal += a.data == b.data ? 1 : 0;
      }
  return equal;
}

}  // namespace

TEST(SpecularAARun, PlaneIsBitIdenticalToNoneAndWavesAreNot) {
  for (const char* mesh : {"plane", "wavy"}) {
    const test::TempDir dir(std::string("specaa_") + mesh);
    const nlohmann::json mesh_json =
        mesh == std::string("plane")
            ? nlohmann::json{{"type", "plane"}, {"size", 20}, {"tessellation", 8}}
            : nlohmann::json{{"type", "wavy"}, {"size", 20}, {"tessellation", 256}, {"amplitude", 0.04}, {"wavelength", 0.9}};
    nlohmann::json j = {
        {"name", "specaa"},
        {"resolution", {48, 28}},
        {"scene", {{"mesh", mesh_json}, {"sky", {{"sun_elevation_deg", 30}, {"sun_azimuth_deg", 0}}}}},
        {"camera_path",
         {{"type", "orbit"}, {"fps", 30}, {"frames", 3}, {"center", {0, 0, 0}}, {"radius", 6}, {"height", 3},
          {"start_deg", 180}, {"end_deg", 182}, {"fov", 40}}},
        {"material",
         {{"preset", "thesis-hdri-match"}, {"glint_model", "zirr"}, {"sigmoid_b", 1000},
          {"glints", {{"alpha_g", {0.02, 0.02}}, {"light_cone", 0}}}}},
        {"variants", variants(true)},
        {"reference", {{"grid", 2}}},
        {"output", {{"exr", true}, {"png", false}, {"every", 1}}}};
    std::ofstream(dir.path() / "e.json") << j.dump();
    std::ostringstream log;
    ASSERT_EQ(run_experiment(options(dir.path()), log), 0) << log.str();
    const int equal = frames_equal_to_none(dir.path() / "out", 3, true);
    if (mesh == std::string("plane"))
      EXPECT_EQ(equal, 3 * 2 * 3) << "every method, alone and under TAA, every frame";
    else
      EXPECT_EQ(equal, 0) << "on waves the normal turns within a pixel: every method widens alpha_g";
  }
}

// The case of shaders/README.md's specular AA section at a few frames: 0.9-unit waves seen from 14
// units at 160x90, beckmann at alpha_g 0.02, no light cone, one sample per pixel.
TEST(SpecularAARun, SmallWavesFromAfarFlickerLessWithTokuyoshi2019) {
  const test::TempDir dir("specaa_waves");
  nlohmann::json j = {
      {"name", "specaa-waves"},
      {"resolution", {160, 90}},
      {"scene",
       {{"mesh", {{"type", "wavy"}, {"size", 60}, {"tessellation", 1024}, {"amplitude", 0.04}, {"wavelength", 0.9}}},
        {"sky", {{"turbidity", 3}, {"sky_intensity", 0.5}, {"sun_elevation_deg", 30}, {"sun_azimuth_deg", 0},
                 {"sun_intensity", 6}}}}},
      {"camera_path",
       {{"type", "keyframes"}, {"fps", 30}, {"frames", 6}, {"interpolation", "linear"},
        {"keyframes",
         {{{"time", 0}, {"position", {-11.489, 8, 0}}, {"target", {0, 0, 0}}, {"fov", 40}},
          {{"time", 0.5}, {"position", {-11.189, 8, 0.4}}, {"target", {0.3, 0, 0.4}}, {"fov", 40}}}}}},
      {"material",
       {{"preset", "thesis-hdri-match"}, {"noise_scale", 400}, {"glint_model", "beckmann"}, {"sigmoid_b", 1000},
        {"glints", {{"alpha_g", {0.02, 0.02}}, {"light_cone", 0}}}}},
      {"variants", {{{"name", "none"}}, {{"name", "tokuyoshi2019"}, {"material", {{"specular_aa", "tokuyoshi2019"}}}}}},
      {"reference", {{"grid", 12}}},
      {"metrics", {"deltaE2000"}},
      {"output", {{"exr", false}, {"png", false}}}};
  std::ofstream(dir.path() / "e.json") << j.dump();
  std::ostringstream log;
  ASSERT_EQ(run_experiment(options(dir.path()), log), 0) << log.str();
  const auto s = nlohmann::json::parse(std::ifstream(dir.path() / "out" / "summary.json"));
  const double none = s["variants"][0]["metrics"]["flicker_excess"]["mean"];
  const double aa = s["variants"][1]["metrics"]["flicker_excess"]["mean"];
  const double floor = s["references"][0]["floor"]["flicker_excess"];
  EXPECT_GT(none - aa, 3 * floor) << "beyond the truth's noise floor";
  EXPECT_LE(aa, none * 2.0 / 3.0) << "none " << none << ", tokuyoshi2019 " << aa;
}

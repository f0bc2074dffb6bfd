// Every material preset renders on every built-in mesh type, including a
// grazing view from below the horizon and a camera close to the surface,
// with zero NaN, Inf or negative pixels (run_experiment returns 1 if any
// frame has one) and zero validation messages.
#include "core/material/sand_material.h"
#include "experiments/runner/runner.h"

#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace glintlab;

TEST(Presets, EveryPresetRendersFiniteAndNonNegativeOnEveryMesh) {
  const glintlab::test::TempDir tmp("presets");
  const fs::path dir = tmp.path();
  nlohmann::json variants = nlohmann::json::array();
  for (const auto& p : core::SandParams::preset_names()) {
    variants.push_back({{"name", p}, {"material", {{"preset", p}}}});
    // Grains around a pixel wide and a visible glint gate: the stiff case.
    variants.push_back({{"name", p + "-fine"},
                        {"material", {{"preset", p}, {"noise_scale", 300}, {"glint_sigma", 1e-6},
                                      {"I_glints", {1e4, 1e4, 1e4}}, {"sigmoid_b", 4}}}});
  }
  for (const char* mesh : {"plane", "wavy", "sphere", "dunes"}) {
    nlohmann::json j = {
        {"resolution", {40, 24}},
        {"scene", {{"mesh", {{"type", mesh}, {"size", 4}, {"tessellation", 24}}}}},
        // Frame 0 close and high, frame 1 grazing, frame 2 from below the surface.
        {"camera_path",
         {{"type", "keyframes"}, {"fps", 1}, {"frames", 3}, {"interpolation", "linear"},
          {"keyframes",
           {{{"time", 0}, {"position", {0.3, 2.5, 0.4}}, {"target", {0, 0, 0}}, {"fov", 60}},
            {{"time", 1}, {"position", {0, 0.05, 6}}, {"target", {0, 0, -3}}, {"fov", 60}},
            {{"time", 2}, {"position", {0.5, -1.5, 3}}, {"target", {0, 0, 0}}, {"fov", 60}}}}}},
        {"variants", variants},
        {"output", {{"exr", false}, {"png", false}}}};
    fs::path file = dir / (std::string(mesh) + ".json");
    std::ofstream(file) << j.dump(2);
    RunOptions opt;
    opt.report = false;  // the report has its own test (report.cpp)
    opt.experiment = file.string();
    opt.out_dir = (dir / mesh).string();
    opt.measure = false;
    opt.validation = true;
    std::ostringstream log;
    EXPECT_EQ(run_experiment(opt, log), 0) << mesh << ":\n" << log.str();
  }
}

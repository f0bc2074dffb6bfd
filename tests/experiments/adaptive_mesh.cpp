// The adaptive grid in a run (scene.mesh.max_edge_px): it serves every frame
// of the camera path at the run's resolution, whatever part of the path the
// run renders, and the reference cache tells meshes apart.
#include "core/scene/camera_path.h"
#include "experiments/runner/plan.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

using namespace glintlab;

namespace {

nlohmann::json dunes_run(double max_edge_px, int frames, int width) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "scene": {"mesh": {"type": "dunes", "size": 40, "tessellation": 64, "amplitude": 2, "wavelength": 12}},
    "camera_path": {"type": "dolly", "fps": 10, "frames": 6, "from": [-30, 3, 0], "to": [-24, 3, 2],
                    "target": [0, 0, 0], "fov": 40},
    "variants": [{"name": "a"}]
  })");
  j["scene"]["mesh"]["max_edge_px"] = max_edge_px;
  j["frames"] = frames;
  j["resolution"] = {width, width / 2};
  return j;
}

}  // namespace

TEST(AdaptiveMesh, ServesEveryFrameOfThePathAtTheRunsResolution) {
  const ExperimentSpec spec = ExperimentSpec::from_json(dunes_run(8.0, 2, 320), "inline-test");
  const std::vector<core::MeshView> views = mesh_views(spec);
  ASSERT_EQ(views.size(), 6u) << "all frames of the path, not the two this run renders";
  for (int k = 0; k < 6; ++k) {
    const core::FrameCamera cam = spec.path.frame(k, 320, 160);
    EXPECT_EQ(views[size_t(k)].eye, cam.position);
    EXPECT_NEAR(views[size_t(k)].focal_px, 160.0 / (2.0 * std::tan(20.0 * 3.14159265358979 / 180.0)), 1e-3);
  }
  EXPECT_TRUE(mesh_views(ExperimentSpec::from_json(dunes_run(0.0, 2, 320), "inline-test")).empty());

  // The same mesh for a run of two frames and of all six; another at another resolution, and the
  // full grid without the key. The reference cache's scene key follows the mesh.
  const metrics::ColorManager cm;
  auto scene_of = [&](double px, int frames, int width) {
    const ExperimentSpec s = ExperimentSpec::from_json(dunes_run(px, frames, width), "inline-test");
    const SceneData d = build_scene(s, cm);
    return std::make_pair(d.mesh.indices.size() / 3, make_plan(s, s.frames, true, cm, d, "device").scene_key);
  };
  const auto two = scene_of(8.0, 2, 320), six = scene_of(8.0, 6, 320), small = scene_of(8.0, 2, 160),
             full = scene_of(0.0, 2, 320);
  EXPECT_EQ(two.first, six.first);
  EXPECT_EQ(full.first, 2u * 64u * 64u);
  EXPECT_LT(two.first, full.first);
  EXPECT_LT(small.first, two.first) << "fewer pixels per cell at the lower resolution";
  EXPECT_EQ(two.second, six.second);
  EXPECT_NE(two.second, small.second);
}

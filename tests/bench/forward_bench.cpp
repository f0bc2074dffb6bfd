// Forward-pass throughput on the current Vulkan device: ms/frame and Mpix/s of
// the sand material at 640x360 and 1280x720, for the full material and for
// the variants with features compiled out, measured in one run (so ratios
// between them are meaningful). Median of N timed frames after warm-up; GPU
// timestamps; variants timed round-robin.
// Usage: glintlab_bench [--device NAME|INDEX] [--frames N] [--size W H]
#include "core/scene/camera_path.h"
#include "core/scene/mesh.h"
#include "core/material/program.h"
#include "core/render/surface_pass.h"
#include "core/material/sand_material.h"
#include "core/vk/vk_context.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>

using namespace glintlab;

namespace {

struct Case {
  std::string name;
  core::SandParams params;
  core::SandFeatures needs;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string device;
  int frames = 10;
  std::vector<std::pair<int, int>> sizes = {{640, 360}, {1280, 720}};
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--device" && i + 1 < argc) device = argv[++i];
    else if (a == "--frames" && i + 1 < argc) frames = std::max(1, std::atoi(argv[++i]));
    else if (a == "--size" && i + 2 < argc) {
      sizes = {{std::atoi(argv[i + 1]), std::atoi(argv[i + 2])}};
      i += 2;
    } else {
      std::cerr << "usage: glintlab_bench [--device NAME|INDEX] [--frames N] [--size W H]\n";
      return 2;
    }
  }
  ExperimentSpec spec = ExperimentSpec::load(resolve_experiment_path("default"));
  metrics::ColorManager cm;
  core::Mesh mesh = core::build_mesh(spec.mesh);
  core::Environment env = prepare_environment(spec, cm);
  core::EnvironmentTexture tex = environment_texture(env);
  core::VkContext ctx(core::ContextOptions{device, false});
  core::SceneGpu scene(ctx, mesh, tex);
  const char* lp_threads = std::getenv("LP_NUM_THREADS");
  std::printf("device: %s (LP_NUM_THREADS=%s)\nscene: %s, path %s frame 0, material thesis-default, %d timed frames "
              "after 2 warm-up\n",
              ctx.info().name.c_str(), lp_threads ? lp_threads : "unset", spec.mesh.type.c_str(),
              spec.path_name.c_str(), frames);

  core::SandParams base = to_working_space(spec.variants.front().material, spec.working_space, cm);
  core::SandFeatures all = distance_range(spec, mesh);
  std::vector<Case> cases;
  cases.push_back({"full (close+far+transition)", base, {0.0, 1e30, "final"}});
  cases.push_back({"as the default scene needs", base, all});
  core::SandParams no_t = base;
  no_t.T = 0;
  cases.push_back({"T = 0 (no transmission)", no_t, {0.0, 1e30, "final"}});
  core::SandParams no_g = base;
  no_g.glint_model = core::GlintModel::None;
  cases.push_back({"no glints", no_g, {0.0, 1e30, "final"}});
  // With the thesis sigmoid (a = 2, b = 1.3) sig(0) = 0.07: the far field is
  // always blended in. A transition pushed out to b = 100 never reaches it
  // within 20 units, so the far branch and the blend compile out.
  core::SandParams near_only = base;
  near_only.sigmoid_b = 100;
  cases.push_back({"close only (b = 100, dist <= 20)", near_only, {0.0, 20.0, "final"}});
  cases.push_back({"far only (close never reached)", base, {1e6, 1e30, "final"}});
  core::SandParams minimal = no_t;
  minimal.glint_model = core::GlintModel::None;
  cases.push_back({"far only, T = 0, no glints", minimal, {1e6, 1e30, "final"}});

  for (auto [w, h] : sizes) {
    core::FrameCamera cam = spec.path.frame(0, w, h);
    core::FrameUniforms fu = frame_uniforms(cam, env, w, h, tex.mips_rgba.size());
    std::vector<core::SamplePush> one = {{cam.view_proj, {0, 0, 1, 0}}};
    std::printf("\n%dx%d (%.3f Mpix)\n", w, h, double(w) * h * 1e-6);
    std::printf("  %-34s %10s %10s %8s  %s\n", "variant", "ms/frame", "Mpix/s", "ratio", "defines");
    // All variants are built first and timed round-robin, so drift in the
    // machine's load spreads over every variant instead of biasing one.
    std::vector<std::unique_ptr<core::SurfaceRenderer>> passes;
    std::vector<std::string> defines;
    for (const Case& c : cases) {
      // The same factory as the runner's (core/material/program.h).
      core::SurfacePassOptions o;
      o.program = core::sand_program(c.params, c.needs, core::ProgramRole::Variant);
      o.sky = false;
      std::string defs;
      for (const auto& d : o.program.defines) defs += (defs.empty() ? "" : " ") + d;
      defines.push_back(defs);
      passes.push_back(std::make_unique<core::SurfaceRenderer>(ctx, scene, w, h, o));
      for (int i = 0; i < 2; ++i) passes.back()->render(fu, one);  // warm-up (JIT, caches)
    }
    std::vector<std::vector<double>> ms(cases.size());
    for (int i = 0; i < frames; ++i)
      for (size_t c = 0; c < cases.size(); ++c) ms[c].push_back(passes[c]->render(fu, one).timings[0].gpu_ms);
    double full_ms = median(ms[0]);
    for (size_t c = 0; c < cases.size(); ++c) {
      double m = median(ms[c]);
      std::printf("  %-34s %10.2f %10.2f %8.2f  %s\n", cases[c].name.c_str(), m, double(w) * h * 1e-6 / (m * 1e-3),
                  m / full_ms, defines[c].c_str());
    }
  }
  return 0;
}

// The sand material's parameters folded into the shader as constants
// (core::material_constants_define, what sand_program() does) render what the
// same program renders from its uniform block: the constants' mapping onto the
// fields of SandParams (std140 offsets) is right for every field a frame uses,
// and folding changes a pixel by no more than the compiler's constant folding.
#include "core/material/program.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace glintlab;

namespace {

const char* kScene = R"({
  "resolution": [64, 36],
  "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 24, "amplitude": 0.4, "wavelength": 5}},
  "camera_path": {"type": "static", "fps": 30, "frames": 1, "position": [0, 1.2, 3.5], "target": [0, 0, -2], "fov": 50},
  "material": {"preset": "thesis-hdri-match"},
  "variants": [{"name": "v"}]
})";

// Every parameter away from its default and from the others, so that two swapped fields show.
core::SandParams distinct_params(core::GlintModel model, uint32_t compat, bool energy_consistent) {
  core::SandParams p = core::SandParams::preset("thesis-hdri-match");
  for (int i = 0; i < 8; ++i) p.palette[i] = {0.2 + 0.09 * i, 0.7 - 0.05 * i, 0.3 + 0.04 * (i % 3)};
  p.SSS = 0.61;
  p.R_s = 0.23;
  p.T = 0.47;
  p.R_t = 0.31;
  p.glint_sigma = 0.003;
  p.P = 0.17;
  p.noise_scale = 350;
  p.I_glints = {7.0, 11.0, 5.0};
  p.scattering = 0.29;
  p.absorption = 0.53;
  p.oren_nayar_sigma = 0.37;
  p.sigmoid_a = 1.7;
  p.sigmoid_b = 3.1;
  p.ior = 1.61;
  p.glint_model = model;
  p.fresnel_half_vector = "light_view";
  p.appendix_compat = compat;
  p.energy_consistent = energy_consistent;
  p.glints.log_density = 6.3;
  p.glints.alpha_g = {0.21, 0.34};
  p.glints.relative_roughness = {0.12, 0.09};
  p.glints.size_variation = 0.4;
  p.glints.intensity = 2.5;
  p.glints.light_cone = 0.02;
  p.glints.color_saturation = 0.6;
  p.glints.half_vector_blend = true;
  return p;
}

}  // namespace

TEST(MaterialConstants, FoldedParametersRenderWhatTheUniformBlockRenders) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const ExperimentSpec spec = ExperimentSpec::from_json(nlohmann::json::parse(kScene), "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  const int w = spec.width, h = spec.height;
  const core::FrameUniforms fu = frame_uniforms(spec, data, 0);
  const std::vector<core::SamplePush> one = {{spec.path.frame(0, w, h).view_proj, {0.0f, 0.0f, 1.0f, 0.0f}}};
  // Close and far field with the transition inside the view (distances about 1.5 to 9).
  const core::SandFeatures needs = data.range;

  struct Case {
    core::GlintModel model;
    uint32_t compat;
    bool energy;
  };
  for (Case c : {Case{core::GlintModel::Kajs, 0u, false}, Case{core::GlintModel::Kajs, core::kSandCompatAll, true},
                 Case{core::GlintModel::Grains, 0u, false}, Case{core::GlintModel::Zirr, 0u, true},
                 Case{core::GlintModel::Beckmann, core::kSandCompatFresnelAbs, false}}) {
    SCOPED_TRACE(std::string(enum_name(core::kGlintModelNames, c.model)) + " compat " + std::to_string(c.compat));
    core::SurfacePassOptions folded;
    folded.program = core::sand_program(distinct_params(c.model, c.compat, c.energy), needs, core::ProgramRole::Variant);
    core::SurfacePassOptions from_block = folded;
    auto& d = from_block.program.defines;
    const auto n_before = d.size();
    d.erase(std::remove_if(d.begin(), d.end(), [](const std::string& s) { return s.rfind("SAND_PARAMS_WORDS=", 0) == 0; }),
            d.end());
    ASSERT_EQ(d.size() + 1, n_before) << "sand_program() adds the constants define once";
    const Image a = core::SurfaceRenderer(ctx, scene, w, h, folded).render(fu, one).images.at("color");
    const Image b = core::SurfaceRenderer(ctx, scene, w, h, from_block).render(fu, one).images.at("color");
    double worst = 0.0, sum = 0.0;
    for (size_t i = 0; i < a.data.size(); ++i) {
      ASSERT_TRUE(std::isfinite(a.data[i]) && std::isfinite(b.data[i])) << i;
      worst = std::max(worst, std::abs(double(a.data[i]) - b.data[i]) / (std::abs(double(b.data[i])) + 1e-3));
      sum += b.data[i];
    }
    EXPECT_GT(sum, 0.0);  // the frame shows the material
    EXPECT_LE(worst, 1e-4);
  }
}

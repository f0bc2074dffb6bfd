// The sand material's parameters and the frame's lighting folded into the
// shader as constants (core::material_constants_define and
// MaterialProgram::frame_lighting_constants, what sand_program() does) render
// what the same program renders from its uniform blocks: the constants'
// mapping onto the fields of SandParams (std140 offsets) and onto the sun and
// sky fields of the frame block is right for every field a frame uses, folding
// changes a pixel by no more than the compiler's constant folding, and a frame
// with other lighting is rendered with its own.
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
core::SandParams distinct_params(const std::string& model, uint32_t compat, bool energy_consistent) {
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
  auto own = [&p](const char* name, double v) {  // a model's own parameter, where it declares it
    if (const core::GlintModelDecl* d = p.glint_decl(); d && d->parameter(name)) p.glints.model[name] = v;
  };
  own("size_variation", 0.4);
  p.glints.intensity = 2.5;
  p.glints.light_cone = 0.02;
  own("color_saturation", 0.6);
  own("half_vector_blend", 1.0);
  return p;
}

// The scene of kScene on the shared device.
struct TestScene {
  core::VkContext& ctx = test::shared_context();
  const ExperimentSpec spec = ExperimentSpec::from_json(nlohmann::json::parse(kScene), "inline-test");
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene{ctx, data.mesh, data.env_texture};
  const int w = spec.width, h = spec.height;
  const std::vector<core::SamplePush> one = {{spec.path.frame(0, w, h).view_proj, {0.0f, 0.0f, 1.0f, 0.0f}}};
};

}  // namespace

TEST(MaterialConstants, FoldedParametersRenderWhatTheUniformBlockRenders) {
  TestScene t;
  test::ValidationGuard guard(t.ctx);
  const core::FrameUniforms fu = frame_uniforms(t.spec, t.data, 0);
  // Close and far field with the transition inside the view (distances about 1.5 to 9).
  const core::SandFeatures needs = t.data.range;

  struct Case {
    std::string model;
    uint32_t compat;
    bool energy;
  };
  for (Case c : {Case{core::kGlintModelKajs, 0u, false}, Case{core::kGlintModelKajs, core::kSandCompatAll, true},
                 Case{"grains", 0u, false}, Case{"zirr", 0u, true}, Case{"beckmann", core::kSandCompatFresnelAbs, false}}) {
    SCOPED_TRACE(c.model + " compat " + std::to_string(c.compat));
    core::SurfacePassOptions folded;
    folded.program = core::sand_program(distinct_params(c.model, c.compat, c.energy), needs, core::ProgramRole::Variant);
    core::SurfacePassOptions from_block = folded;
    auto& d = from_block.program.defines;
    const auto n_before = d.size();
    d.erase(std::remove_if(d.begin(), d.end(), [](const std::string& s) { return s.rfind("SAND_PARAMS_WORDS=", 0) == 0; }),
            d.end());
    ASSERT_EQ(d.size() + 1, n_before) << "sand_program() adds the constants define once";
    ASSERT_TRUE(folded.program.frame_lighting_constants);
    from_block.program.frame_lighting_constants = false;
    const Image a = core::SurfaceRenderer(t.ctx, t.scene, t.w, t.h, folded).render(fu, t.one).images.at("color");
    const Image b = core::SurfaceRenderer(t.ctx, t.scene, t.w, t.h, from_block).render(fu, t.one).images.at("color");
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

TEST(MaterialConstants, FoldedLightingFollowsTheFrame) {
  // One pass renders a frame, then the same view under another sun and sky:
  // it must give exactly what a fresh pass gives for the second lighting (the
  // pass recompiles when the lighting it folded in changes), which differs
  // from the first frame.
  TestScene t;
  test::ValidationGuard guard(t.ctx);
  const core::FrameUniforms first = frame_uniforms(t.spec, t.data, 0);
  core::FrameUniforms second = first;
  second.sun_dir = glm::vec4(glm::normalize(glm::vec3(-0.4f, 0.5f, 0.2f)), first.sun_dir.w);
  second.sun_L *= 0.5f;
  for (glm::vec4& c : second.env_sh) c *= glm::vec4(1.3f, 0.9f, 0.6f, 1.0f);
  core::SurfacePassOptions o;
  o.program = core::sand_program(core::SandParams::preset("thesis-hdri-match"), t.data.range, core::ProgramRole::Variant);
  ASSERT_TRUE(o.program.frame_lighting_constants);

  core::SurfaceRenderer reused(t.ctx, t.scene, t.w, t.h, o);
  const Image a = reused.render(first, t.one).images.at("color");
  const Image b = reused.render(second, t.one).images.at("color");
  const Image fresh = core::SurfaceRenderer(t.ctx, t.scene, t.w, t.h, o).render(second, t.one).images.at("color");
  ASSERT_EQ(b.data.size(), fresh.data.size());
  size_t differ_from_fresh = 0, surface = 0, relit = 0;
  for (size_t i = 0; i < b.data.size(); ++i) differ_from_fresh += b.data[i] != fresh.data[i];
  for (size_t px = 0; px < b.pixel_count(); ++px) {
    if (b.data[px * 4 + 3] <= 0.0f) continue;  // the sky: not lit by the sun or the SH term
    ++surface;
    relit += b.data[px * 4] != a.data[px * 4] && b.data[px * 4 + 2] != a.data[px * 4 + 2];
  }
  EXPECT_EQ(differ_from_fresh, 0u);
  EXPECT_GT(surface, b.pixel_count() / 4);
  EXPECT_EQ(relit, surface) << "every surface pixel must show the second lighting";
}

// A user's model file that writes the smooth Beckmann NDF out inline
// (tests/data/glint_models/beckmann_inline.glsl, gain k = 1) renders the
// frame the built-in "beckmann" renders, bit for bit; with k = 2 the glints
// change.
TEST(MaterialConstants, UserModelFileRendersWhatTheBuiltInRenders) {
  TestScene t;
  test::ValidationGuard guard(t.ctx);
  const core::FrameUniforms fu = frame_uniforms(t.spec, t.data, 0);
  auto render = [&](const core::SandParams& p) {
    core::SurfacePassOptions o;
    o.program = core::sand_program(p, t.data.range, core::ProgramRole::Variant);
    return core::SurfaceRenderer(t.ctx, t.scene, t.w, t.h, o).render(fu, t.one).images.at("color");
  };
  core::SandParams builtin = distinct_params("beckmann", 0u, true);
  core::SandParams user = builtin;
  const std::string file = std::string(GLINTLAB_TEST_DATA_DIR) + "/glint_models/beckmann_inline.glsl";
  user.glint_model = file;
  user.glint_file = std::make_shared<const core::GlintModelDecl>(core::glint_model_from_file(file));
  const Image a = render(builtin), b = render(user);
  ASSERT_EQ(a.data.size(), b.data.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.data.size(); ++i) differ += a.data[i] != b.data[i];
  EXPECT_EQ(differ, 0u);
  core::SandParams twice = user;
  twice.glints.model["k"] = 2.0;
  const Image c = render(twice);
  size_t brighter = 0;
  for (size_t i = 0; i < a.data.size(); ++i) brighter += c.data[i] > a.data[i];
  EXPECT_GT(brighter, 0u);
}

// The frame graph: declared targets become images, declarations become
// barriers (the validation layer, with synchronization validation, checks a
// graphics -> compute -> readback chain and its history across frames), a
// history target keeps its value across frames and drops it on reset, and bad
// graphs are refused with the pass and target named.
#include "core/render/frame_graph.h"
#include "core/render/surface_pass.h"
#include "core/scene/camera.h"
#include "core/scene/mesh.h"
#include "core/vk/pipeline.h"
#include "core/vk/shader_compiler.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

using namespace glintlab;

namespace {

// acc = src + previous acc (history), on the GPU (shaders/tests/accumulate.comp).
class AccumulatePass final : public core::Pass {
 public:
  AccumulatePass(const core::VkContext& ctx, std::string src) : ctx_(ctx), src_(std::move(src)) {
    std::vector<VkDescriptorSetLayoutBinding> b = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
    set_layout_ = core::make_set_layout(ctx, b);
    layout_ = core::make_pipeline_layout(ctx, set_layout_.get(), 16, VK_SHADER_STAGE_COMPUTE_BIT);
    auto cs = core::default_shader_compiler().compile("tests/accumulate.comp", core::ShaderStage::Compute);
    core::ShaderModule m = core::make_shader_module(ctx, cs.spirv);
    pipeline_ = core::make_compute_pipeline(ctx, layout_.get(), m.get());
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    VkSampler s;
    core::vk_check(vkCreateSampler(ctx.device(), &si, nullptr, &s), "vkCreateSampler");
    sampler_ = core::Sampler(ctx.device(), s);
    for (auto& set : sets_) set = core::make_descriptor_set(ctx, set_layout_.get(), b);
  }
  std::string name() const override { return "accumulate"; }
  void declare(core::PassIO& io) const override {
    io.read(src_);
    io.read_previous("acc");
    io.keep("acc", VK_FORMAT_R32G32B32A32_SFLOAT, core::TargetUse::Storage);
  }
  void setup(const core::TargetSet& t) override {
    for (int slot = 0; slot < 2; ++slot) {
      core::write_image_descriptor(ctx_, sets_[slot].set, 0, t.image(src_).view(), sampler_.get(),
                                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      core::write_image_descriptor(ctx_, sets_[slot].set, 1, t.slot("acc", 1 - slot).view(), sampler_.get(),
                                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      VkDescriptorImageInfo ii{VK_NULL_HANDLE, t.slot("acc", slot).view(), VK_IMAGE_LAYOUT_GENERAL};
      VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      w.dstSet = sets_[slot].set;
      w.dstBinding = 2;
      w.descriptorCount = 1;
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      w.pImageInfo = &ii;
      vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
    }
  }
  void record(VkCommandBuffer cmd, const core::FrameInputs&, const core::TargetSet& t) override {
    float push[4] = {float(t.width()), float(t.height()), t.history_valid("acc") ? 1.0f : 0.0f, 0.0f};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1,
                            &sets_[t.current_slot("acc")].set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, push);
    vkCmdDispatch(cmd, (uint32_t(t.width()) + 7) / 8, (uint32_t(t.height()) + 7) / 8, 1);
  }

 private:
  const core::VkContext& ctx_;
  std::string src_;
  core::DescriptorSetLayout set_layout_;
  core::PipelineLayout layout_;
  core::Pipeline pipeline_;
  core::Sampler sampler_;
  core::DescriptorSet sets_[2];
};

core::EnvironmentTexture black_env() {
  core::EnvironmentTexture env;
  env.width = env.height = 1;
  env.mips_rgba = {std::vector<float>(4, 0.0f)};
  return env;
}

core::Mesh plane() {
  core::MeshSpec spec;
  spec.type = "plane";
  spec.size = 100.0f;
  spec.tessellation = 2;
  return core::build_mesh(spec);
}

// A camera looking straight down at the plane, so every pixel is covered.
core::FrameInputs inputs(int w, int h) {
  core::CameraState cam;
  cam.position = {0.0f, 5.0f, 0.001f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.fov_y_deg = 60.0f;
  glm::mat4 vp = core::projection(cam, w, h) * core::view_matrix(cam);
  core::FrameInputs in;
  in.uniforms.view_proj = in.uniforms.prev_view_proj = vp;
  in.uniforms.inv_view_proj = glm::inverse(vp);
  in.uniforms.camera_pos = glm::vec4(cam.position, 0.0f);
  in.uniforms.resolution = glm::vec4(float(w), float(h), 1.0f / float(w), 1.0f / float(h));
  in.samples = {core::SamplePush{vp, {0, 0, 1, 0}}};
  return in;
}

}  // namespace

TEST(FrameGraph, GraphicsToComputeChainWithHistoryIsSynchronisedAndKeepsHistory) {
  core::VkContext& ctx = test::shared_context();
  ASSERT_TRUE(ctx.validation_enabled());
  test::ValidationGuard guard(ctx);
  const int w = 37, h = 23;
  core::Mesh mesh = plane();
  core::SceneGpu scene(ctx, mesh, black_env());
  core::FrameGraph g(ctx, w, h);
  core::SurfacePassOptions o;
  o.program.fragment = "tests/fragcoord.frag";  // colour = (x, y, 1000 y + x, 1) at pixel (x, y)
  o.sky = false;
  g.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  g.add(std::make_unique<AccumulatePass>(ctx, "color"));
  g.build({"acc", "color"});
  EXPECT_EQ(g.pass_names(), (std::vector<std::string>{"surface", "accumulate"}));
  const core::FrameInputs in = inputs(w, h);
  auto expect_acc = [&](const core::FrameResult& r, float n) {
    const Image& acc = r.images.at("acc");
    const Image& color = r.images.at("color");
    ASSERT_EQ(acc.width, w);
    int bad = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        bad += color.at(x, y, 0) != float(x) || color.at(x, y, 1) != float(y);
        bad += acc.at(x, y, 0) != n * float(x) || acc.at(x, y, 2) != n * float(1000 * y + x);
      }
    EXPECT_EQ(bad, 0) << "after " << n << " frame(s)";
  };
  expect_acc(g.execute(in), 1.0f);  // no history yet
  expect_acc(g.execute(in), 2.0f);  // history kept across frames
  core::FrameResult third = g.execute(in);
  expect_acc(third, 3.0f);
  ASSERT_EQ(third.timings.size(), 2u);
  EXPECT_GT(third.timings[0].gpu_ms, 0.0);
  g.reset_history();
  expect_acc(g.execute(in), 1.0f);  // dropped on reset
  expect_acc(g.execute(in), 2.0f);
  core::FrameInputs cut = in;
  cut.camera_cut = true;
  expect_acc(g.execute(cut), 1.0f);  // and at a camera cut
}

TEST(FrameGraph, BadGraphsAreRefusedNamingPassAndTarget) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  core::Mesh mesh = plane();
  core::SceneGpu scene(ctx, mesh, black_env());
  core::SurfacePassOptions o;
  o.program.fragment = "tests/fragcoord.frag";
  o.sky = false;
  {  // a read before any writer
    core::FrameGraph g(ctx, 8, 8);
    g.add(std::make_unique<AccumulatePass>(ctx, "color"));
    g.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
    try {
      g.build({});
      ADD_FAILURE() << "expected an error";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("\"accumulate\" reads \"color\" before its writer \"surface\""),
                std::string::npos) << e.what();
    }
  }
  {  // two writers of one target
    core::FrameGraph g(ctx, 8, 8);
    g.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
    g.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
    EXPECT_THROW(g.build({}), std::invalid_argument);
  }
  {  // nobody writes it
    core::FrameGraph g(ctx, 8, 8);
    g.add(std::make_unique<AccumulatePass>(ctx, "nothing"));
    EXPECT_THROW(g.build({}), std::invalid_argument);
  }
  {  // reading back an undeclared target
    core::FrameGraph g(ctx, 8, 8);
    g.add(std::make_unique<core::SurfacePass>(ctx, scene, o));
    EXPECT_THROW(g.build({"motion"}), std::invalid_argument);
  }
}

// The Vulkan foundation on the real device: context, validation counting,
// run-time GLSL compilation (includes, defines, errors, cache), the compute
// harness and exact readback.
#include "core/vk/compute_harness.h"
#include "core/util/content_hash.h"
#include "core/vk/gpu_resources.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/vk_context.h"
#include "tests/support/vk_test_util.h"

#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <filesystem>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

namespace fs = std::filesystem;
using namespace glintlab;

TEST(VkContext, DefaultDeviceIsLavapipeAndValidationIsOn) {
  core::VkContext& ctx = test::shared_context();
  EXPECT_TRUE(ctx.validation_enabled());
  // CI machines have no GPU: the default must be the CPU device.
  auto devices = core::VkContext::list_devices();
  ASSERT_FALSE(devices.empty());
  bool has_cpu = false;
  for (auto& d : devices) has_cpu |= d.type == "cpu";
  if (has_cpu) {
    EXPECT_EQ(ctx.info().type, "cpu") << ctx.info().name;
  }
  EXPECT_TRUE(ctx.timestamps_supported());
}

TEST(VkContext, UnknownDeviceNameIsAClearError) {
  try {
    core::VkContext ctx(core::ContextOptions{"no-such-gpu-xyz", false});
    FAIL() << "expected an error";
  } catch (const core::VulkanError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("no-such-gpu-xyz"), std::string::npos) << m;
    EXPECT_NE(m.find("available"), std::string::npos) << m;
  }
  EXPECT_THROW(core::VkContext(core::ContextOptions{"99", false}), core::VulkanError);
}

TEST(ShaderCompiler, DefinesReachTheShaderAndHarnessComputes) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  std::vector<float> in(1000);
  for (size_t i = 0; i < in.size(); ++i) in[i] = float(i) * 0.25f - 7.0f;
  auto out = core::run_compute(ctx, "tests/harness_selftest.comp", {"SCALE=3.0"}, in, in.size(), uint32_t(in.size()));
  for (size_t i = 0; i < in.size(); ++i) ASSERT_EQ(out[i], in[i] * 3.0f + float(i)) << i;
  // The bound is honoured: invocations past `count` write nothing.
  auto partial = core::run_compute(ctx, "tests/harness_selftest.comp", {}, in, in.size(), 100);
  EXPECT_EQ(partial[99], in[99] + 99.0f);
  EXPECT_EQ(partial[100], 0.0f);
}

TEST(ShaderCompiler, ErrorsNameFileAndLine) {
  const glintlab::test::TempDir tmp("shader_err");
  const fs::path dir = tmp.path();
  fs::create_directories(dir / "inc");
  std::ofstream(dir / "inc" / "bad.glsl") << "// line 1\nfloat f() {\n  return undefined_symbol;\n}\n";
  std::ofstream(dir / "main.comp") << "#version 450\n#include \"inc/bad.glsl\"\nlayout(local_size_x=1) in;\nvoid main() {}\n";
  core::ShaderCompiler sc(dir.string(), "-");
  try {
    sc.compile("main.comp", core::ShaderStage::Compute);
    FAIL() << "expected a compile error";
  } catch (const core::ShaderCompileError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("bad.glsl:3"), std::string::npos) << m;
    EXPECT_NE(m.find("undefined_symbol"), std::string::npos) << m;
  }
  EXPECT_THROW(sc.compile("missing.comp", core::ShaderStage::Compute), core::ShaderCompileError);
  EXPECT_THROW(sc.compile("main.comp", core::ShaderStage::Compute, {"1BAD"}), core::ShaderCompileError);
}

TEST(ShaderCompiler, CacheIsKeyedOnIncludesAndRebuildsCorruptEntries) {
  const glintlab::test::TempDir tmp("shader_cache");
  const fs::path dir = tmp.path();
  fs::create_directories(dir / "src");
  auto write_inc = [&](const char* value) {
    std::ofstream(dir / "src" / "value.glsl") << "const float VALUE = " << value << ";\n";
  };
  write_inc("1.0");
  std::ofstream(dir / "src" / "k.comp")
      << "#version 450\n#include \"value.glsl\"\nlayout(local_size_x=1) in;\n"
         "layout(std430, binding=0) buffer B { float b[]; };\nvoid main() { b[0] = VALUE; }\n";
  core::ShaderCompiler sc((dir / "src").string(), (dir / "cache").string());
  auto a = sc.compile("k.comp", core::ShaderStage::Compute);
  EXPECT_FALSE(a.from_cache);
  auto b = sc.compile("k.comp", core::ShaderStage::Compute);
  EXPECT_TRUE(b.from_cache);
  EXPECT_EQ(a.spirv, b.spirv);
  write_inc("2.0");  // an include changes: new hash, fresh compile
  auto c = sc.compile("k.comp", core::ShaderStage::Compute);
  EXPECT_NE(c.source_hash, a.source_hash);
  EXPECT_FALSE(c.from_cache);
  // Corrupt the cached entry: it is detected and rebuilt.
  std::ofstream(dir / "cache" / (c.source_hash + ".spv"), std::ios::binary) << "garbage!";
  auto d = sc.compile("k.comp", core::ShaderStage::Compute);
  EXPECT_FALSE(d.from_cache);
  EXPECT_EQ(d.spirv, c.spirv);
}

TEST(ContentHash, BoundariesMatter) {
  core::ContentHash a, b;
  a.add(std::string_view("ab")).add(std::string_view("c"));
  b.add(std::string_view("a")).add(std::string_view("bc"));
  EXPECT_NE(a.hex(), b.hex());
  EXPECT_EQ(core::hash_hex("x"), core::hash_hex("x"));
  EXPECT_EQ(core::hash_hex("x").size(), 32u);
}

TEST(Readback, HalfFloatTargetsAreWidenedExactly) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  // RGBA16F, odd size: cleared to values that are exact in half precision
  // (including a subnormal and a negative), read back through the padded pitch.
  core::Image2D img(ctx, 37, 11, VK_FORMAT_R16G16B16A16_SFLOAT,
                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  const float v[4] = {0.5f, -3.25f, 65504.0f, 5.9604645e-08f};
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    core::transition(cmd, img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_WRITE_BIT);
    VkClearColorValue c;
    std::memcpy(c.float32, v, sizeof v);
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, img.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &c, 1, &range);
  });
  EXPECT_EQ(core::padded_row_pitch(37, VK_FORMAT_R16G16B16A16_SFLOAT), 512u);  // 296 bytes padded to 256
  auto px = core::read_back(ctx, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  ASSERT_EQ(px.size(), size_t(37) * 11 * 4);
  for (size_t i = 0; i < px.size(); ++i) ASSERT_EQ(px[i], v[i % 4]) << i;
}

TEST(Readback, Rgba32fPixelsComeBackInPlaceWithAndWithoutRowPadding) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  // Width 16: rows of 256 bytes, copied in one piece; width 17: rows padded
  // to 512 bytes in the staging buffer, copied row by row. Every value is
  // distinct (and some are negative or not finite), so a row or pixel read
  // from the wrong place, or a value not copied, is seen.
  for (uint32_t w : {16u, 17u}) {
    const uint32_t h = 5;
    EXPECT_EQ(core::padded_row_pitch(w, VK_FORMAT_R32G32B32A32_SFLOAT) == VkDeviceSize(w) * 16, w == 16u) << w;
    core::Image2D img(ctx, w, h, VK_FORMAT_R32G32B32A32_SFLOAT,
                      VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    std::vector<float> px(size_t(w) * h * 4);
    for (size_t i = 0; i < px.size(); ++i) px[i] = (i % 7 == 3 ? -1.0f : 1.0f) * (float(i) + 0.25f);
    px[5] = std::numeric_limits<float>::infinity();
    px[px.size() - 2] = -0.0f;
    core::upload_rgba32f_mips(ctx, img, {px});
    const auto back = core::read_back(ctx, img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    ASSERT_EQ(back.size(), px.size()) << w;
    EXPECT_EQ(std::memcmp(back.data(), px.data(), px.size() * sizeof(float)), 0) << w;
  }
}

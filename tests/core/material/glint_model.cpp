// Every glint model in the C++ name table has the GLSL constant with the same
// value, so a model added on one side only cannot pack as another.
#include "core/material/glint_model.h"
#include "core/material/sand_material.h"
#include "core/vk/compute_harness.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <cctype>

using namespace glintlab;

TEST(GlintModel, EveryNamedModelHasItsGlslConstant) {
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  for (const auto& [model, name] : core::kGlintModelNames) {
    std::string upper = name;
    for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
    std::vector<float> out = core::run_compute(ctx, "tests/constant.comp", {"CONSTANT=SAND_GLINT_" + upper}, {}, 1, 1);
    EXPECT_EQ(out[0], float(uint32_t(model))) << name;
  }
}

TEST(GlintModel, NamesRoundTripAndUnknownNamesAreRejected) {
  for (const auto& [model, name] : core::kGlintModelNames) {
    EXPECT_EQ(enum_from_name(core::kGlintModelNames, name), model);
    core::SandParams p;
    p.glint_model = model;
    EXPECT_EQ(p.pack().glint_model, uint32_t(model)) << name;
  }
  EXPECT_FALSE(enum_from_name(core::kGlintModelNames, "kajs2"));
}

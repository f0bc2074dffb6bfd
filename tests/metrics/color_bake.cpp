// The bake of the shipped OCIO config compiled into the program (metrics/color/color_bake.h) against
// OpenColorIO itself: the same names and, for every baked conversion, the same colours to the bit on
// ordinary, extreme and non-finite values; a bake that is not provably the config's is not used.
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/util/ocio_plugin.h"
#include "metrics/color/color_bake.h"
#include "metrics/color/color_manager.h"

namespace fs = std::filesystem;
using glintlab::Image;
using namespace glintlab::metrics;

namespace {

// Values a conversion meets and the ones that test its order of operations: random colours over many
// octaves of both signs, then zeros of both signs, denormals, the largest floats, infinities and NaN.
Image test_values(int channels, std::uint32_t seed) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, 1e-42f, -1e-42f, std::numeric_limits<float>::min(),
                            std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), inf, -inf, nan,
                            0.18f, 65504.0f, 1e30f, -3e-39f};
  const int w = 257, h = 64;
  Image img(w, h, channels);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> mant(-1.0f, 1.0f);
  std::uniform_int_distribution<int> octave(-30, 30), pick(0, int(std::size(specials)) - 1);
  for (std::size_t i = 0; i < img.data.size(); ++i) {
    const bool special = (i / std::size_t(channels)) % 5 == 0;
    img.data[i] = special ? specials[pick(rng)] : std::ldexp(mant(rng), octave(rng));
  }
  return img;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(ColorBake, ConversionsEqualOpenColorIOToTheBit) {
  const BakedConfig* bake = bake_for(GLINTLAB_OCIO_CONFIG);
  ASSERT_TRUE(bake) << "the compiled bake is not that of " << GLINTLAB_OCIO_CONFIG;
  // What every metric needs from the linear spaces is baked (a matrix in OpenColorIO too).
  for (const char* from : {"lin_rec709", "ACEScg", "ACES2065-1"}) {
    EXPECT_TRUE(bake->conversion(from, kXyzD65Space)) << from;
    EXPECT_TRUE(bake->conversion(kXyzD65Space, from)) << from;
  }
  std::unique_ptr<glintlab::ocio::Config> config = glintlab::ocio::api().load(GLINTLAB_OCIO_CONFIG);
  int matrices = 0;
  for (std::size_t k = 0; k < bake->conversion_count; ++k) {
    const BakedConversion& c = bake->conversions[k];
    std::vector<glintlab::ocio::MatrixStep> steps;  // OpenColorIO says the same steps now
    ASSERT_TRUE(config->matrix_steps(c.from, c.to, steps)) << c.from << " -> " << c.to;
    ASSERT_EQ(steps.size(), c.step_count) << c.from << " -> " << c.to;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      EXPECT_EQ(steps[i].m, c.steps[i].m) << c.from << " -> " << c.to;
      EXPECT_EQ(steps[i].offset, c.steps[i].offset) << c.from << " -> " << c.to;
    }
    matrices += c.step_count > 0;
    for (int channels : {3, 4}) {
      const Image in = test_values(channels, std::uint32_t(k * 7 + std::size_t(channels)));
      Image ours = in, theirs = in;
      baked_processor(c)->apply_rgb(ours);
      config->processor(c.from, c.to)->apply_rgb(theirs);
      std::size_t differ = 0, first = 0;
      for (std::size_t i = 0; i < in.data.size(); ++i)
        if (!same_bits(ours.data[i], theirs.data[i]) && !(std::isnan(ours.data[i]) && std::isnan(theirs.data[i])))
          if (differ++ == 0) first = i;
      EXPECT_EQ(differ, 0u) << c.from << " -> " << c.to << ", " << channels << " channels: first at value " << first
                            << " (" << in.data[first] << "): " << ours.data[first] << " against OpenColorIO's "
                            << theirs.data[first];
    }
  }
  EXPECT_GE(matrices, 6);
  // and no conversion between two linear spaces is left out of the bake
  for (const std::string& from : config->spaces())
    for (const std::string& to : config->spaces()) {
      std::vector<glintlab::ocio::MatrixStep> steps;
      if (from != to && config->matrix_steps(from, to, steps)) EXPECT_TRUE(bake->conversion(from, to)) << from << " " << to;
    }
}

TEST(ColorBake, NamesResolveAsOpenColorIOResolvesThem) {
  const BakedConfig* bake = bake_for(GLINTLAB_OCIO_CONFIG);
  ASSERT_TRUE(bake);
  std::unique_ptr<glintlab::ocio::Config> config = glintlab::ocio::api().load(GLINTLAB_OCIO_CONFIG);
  const ColorManager baked(GLINTLAB_OCIO_CONFIG);
  std::size_t known = 0;
  for (const auto& [name, canonical] : config->names()) {  // every name OpenColorIO knows, in any case
    std::string upper = name, low = bake_key(name);
    for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
    for (const std::string& n : {name, upper, low}) {
      ASSERT_TRUE(bake->canonical(n)) << n;
      EXPECT_EQ(bake->canonical(n), config->canonical_name(n)) << n;
      EXPECT_EQ(baked.canonical_name(n), config->canonical_name(n)) << n;
    }
    ++known;
  }
  EXPECT_EQ(known >= bake->name_count, true);
  EXPECT_FALSE(bake->canonical("ProPhotoRGB-nope"));
  EXPECT_FALSE(baked.has_space("ProPhotoRGB-nope"));
  EXPECT_THROW((void)baked.canonical_name("ProPhotoRGB-nope"), std::invalid_argument);
}

// The bake is used only for the bytes it was made from and without OCIO_* variables; where it is not
// used, OpenColorIO answers the same.
TEST(ColorBake, OnlyTheConfigsOwnBakeIsUsed) {
  const glintlab::test::TempDir tmp("bake");
  const fs::path config = tmp.path() / "copy.ocio";
  fs::copy_file(GLINTLAB_OCIO_CONFIG, config);
  EXPECT_EQ(bake_for(config.string()), &compiled_bake());  // the same bytes elsewhere
  ::setenv("OCIO_INACTIVE_COLORSPACES", "ACEScg", 1);
  EXPECT_FALSE(bake_for(config.string()));
  ::unsetenv("OCIO_INACTIVE_COLORSPACES");
  std::ofstream(config, std::ios::app) << "# one more line\n";
  EXPECT_FALSE(bake_for(config.string()));
  EXPECT_FALSE(bake_for((tmp.path() / "missing.ocio").string()));
  Image a(1, 1, 3), b(1, 1, 3);
  a.data = b.data = {0.25f, 0.5f, 2.0f};
  ColorManager(config.string()).convert(a, "linear", "XYZ");      // through OpenColorIO: the bake is not its
  ColorManager(GLINTLAB_OCIO_CONFIG).convert(b, "linear", "XYZ");  // through the bake
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(a.data[c], b.data[c])) << c;
}

// The glint model registry (core/material/glint_model.h): the built-in
// models are the files of shaders/glint/models/, each declared in its own
// comment lines; their GPU ids agree with the GLSL; declarations are
// validated naming file and line; and no second list of model names exists
// in the product's sources.
#include "core/material/glint_model.h"
#include "core/material/sand_material.h"
#include "core/util/json_check.h"
#include "core/vk/compute_harness.h"
#include "tests/support/project_sources.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>

using namespace glintlab;
namespace fs = std::filesystem;

TEST(GlintModel, BuiltInModelsAreTheFilesOfTheModelFolder) {
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(fs::path(GLINTLAB_SHADER_DIR) / "glint" / "models"))
    if (e.path().extension() == ".glsl") files.insert(e.path().stem().string());
  std::set<std::string> registered;
  for (const auto& m : core::builtin_glint_models()) {
    registered.insert(m.name);
    EXPECT_TRUE(m.builtin);
    EXPECT_EQ(m.file, "glint/models/" + m.name + ".glsl");
    EXPECT_FALSE(m.checks.empty()) << m.name;
    EXPECT_EQ(m.content_hash.size(), 32u) << m.name;
  }
  EXPECT_EQ(registered, files);
  auto names = core::glint_model_names();
  EXPECT_EQ(names.front(), "kajs");
  EXPECT_EQ(names.back(), "none");
  EXPECT_EQ(names.size(), files.size() + 2);
}

TEST(GlintModel, GpuIdsAgreeWithTheGlslConstants) {
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  for (const char* name : {"KAJS", "NONE"}) {
    std::vector<float> out = core::run_compute(ctx, "tests/constant.comp", {std::string("CONSTANT=SAND_GLINT_") + name}, {}, 1, 1);
    EXPECT_EQ(out[0], float(core::glint_model_gpu_id(name[0] == 'K' ? "kajs" : "none"))) << name;
  }
  std::set<uint32_t> ids;
  for (const auto& name : core::glint_model_names()) {
    core::SandParams p;
    p.glint_model = name;
    EXPECT_EQ(p.pack().glint_model, core::glint_model_gpu_id(name)) << name;
    ids.insert(core::glint_model_gpu_id(name));
  }
  EXPECT_EQ(ids.size(), core::glint_model_names().size());  // distinct
}

TEST(GlintModel, DeclarationsAreParsedAndMalformedOnesNamed) {
  auto d = core::parse_glint_model("m", "m.glsl",
                                   "// a model\n"
                                   "// glint_model truth=grains limit=beckmann checks=finite,unbiased\n"
                                   "// glint_parameter k default=2 range=0,4\n"
                                   "// glint_parameter on default=true type=bool\n"
                                   "vec3 glint_D(GlintQuery q) { return vec3(q.k); }\n");
  EXPECT_EQ(d.truth, "grains");
  EXPECT_EQ(d.checks, (std::vector<std::string>{"finite", "unbiased"}));
  ASSERT_EQ(d.parameters.size(), 2u);
  EXPECT_EQ(d.parameters[0].name, "k");
  EXPECT_EQ(d.parameters[0].def, 2.0);
  EXPECT_EQ(d.parameters[0].hi, 4.0);
  EXPECT_TRUE(d.parameters[1].is_bool);
  EXPECT_EQ(d.parameters[1].def, 1.0);
  // the smooth limit GGX: the far field and the checks use GGX with alpha_g
  auto g = core::parse_glint_model("g", "g.glsl", "// glint_model limit=ggx\n");
  EXPECT_EQ(g.limit, "ggx");
  EXPECT_EQ(g.truth, "self");
  g.file = "g.glsl";
  auto defs = core::glint_model_defines(g);
  EXPECT_NE(std::find(defs.begin(), defs.end(), "GLINT_LIMIT_GGX"), defs.end());
  defs = core::glint_model_defines(d);
  EXPECT_EQ(std::find(defs.begin(), defs.end(), "GLINT_LIMIT_GGX"), defs.end());
  auto expect_error = [](const std::string& text, const std::string& must_contain) {
    try {
      core::parse_glint_model("m", "m.glsl", text);
      ADD_FAILURE() << "accepted " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(must_contain), std::string::npos) << e.what();
    }
  };
  const std::string head = "// glint_model truth=self\n";
  expect_error("vec3 glint_D(GlintQuery q) { return vec3(0.0); }\n", "m.glsl: no glint_model declaration");
  expect_error("// glint_model truth=self checks=finite,fast\n", "m.glsl:1: unknown check \"fast\"");
  expect_error("// glint_model limit=phong\n", "m.glsl:1: unknown or empty field \"limit=phong\"");
  expect_error(head + "// glint_parameter k default=5 range=0,4\n", "m.glsl:2: default of k");
  expect_error(head + "// glint_parameter k default=1\n", "m.glsl:2: parameter k has no range");
  expect_error(head + "// glint_parameter k range=0,1\n", "m.glsl:2: parameter k has no default");
  expect_error(head + "// glint_parameter 2k default=1 range=0,1\n", "m.glsl:2: a parameter needs a GLSL identifier");
  expect_error(head + "// glint_parameter k default=1 range=1,0\n", "m.glsl:2: range of k");
  expect_error(head + "// glint_parameter b default=yes type=bool\n", "m.glsl:2: default of bool b");
  expect_error(head + "// glint_parameter k default=1 range=0,1\n// glint_parameter k default=1 range=0,1\n",
               "m.glsl:3: parameter k declared twice");
  // names the struct or the material cannot take: GLSL's words, GlintQuery's fields, the common glints
  // keys, macros (upper case); exit 2 at the declaration's line, not a compile error in query.glsl
  for (const char* n : {"float", "in", "sample", "filter", "uv", "density", "rough", "SAND_GLINTS", "log_density",
                        "vec3", "gl_foo", "Size"})
    expect_error(head + "// glint_parameter " + std::string(n) + " default=1 range=0,2\n", "m.glsl:2: parameter name");
  // a default or range beyond a float (1e300 reached the GPU as inf)
  expect_error(head + "// glint_parameter k default=1e300 range=0,1e301\n", "m.glsl:2: range of k");
  // a byte-order mark does not hide the declaration
  const auto bom = core::parse_glint_model("m", "m.glsl", "\xEF\xBB\xBF" + head + "// glint_parameter k default=1 range=0,2\n");
  EXPECT_EQ(bom.parameters.size(), 1u);
  // checks the published method fails, and a data table
  auto f = core::parse_glint_model("f", "f.glsl",
                                   "// glint_model checks=finite,deterministic fails=unbiased,limit\n"
                                   "// glint_table size=4096\n");
  EXPECT_EQ(f.fails, (std::vector<std::string>{"unbiased", "limit"}));
  EXPECT_EQ(f.table_size, 4096u);
  f.file = "f.glsl";
  defs = core::glint_model_defines(f);
  EXPECT_NE(std::find(defs.begin(), defs.end(), "GLINT_TABLE_SIZE=4096u"), defs.end());
  EXPECT_EQ(d.table_size, 0u);
  expect_error("// glint_model checks=finite fails=finite\n", "m.glsl: check \"finite\" is both in checks= and in fails=");
  expect_error("// glint_model fails=slow\n", "m.glsl:1: unknown check \"slow\"");
  expect_error(head + "// glint_table size=0\n", "m.glsl:2: the table size must be a whole number");
  expect_error(head + "// glint_table size=2097153\n", "m.glsl:2: the table size must be a whole number");
  expect_error(head + "// glint_table size=10.5\n", "m.glsl:2: the table size");
  expect_error(head + "// glint_table rows=10\n", "m.glsl:2: the table size");
  expect_error(head + "// glint_table size=10\n// glint_table size=10\n", "m.glsl:3: a second glint_table line");
}

// Adding a built-in model is adding its file: no source of the product lists
// the built-in models' names (a list would be a second place to add one). The
// fp64 twins (core/testkit/) and the harnesses that compare them
// (shaders/tests/) implement particular built-in models and name them; tests
// and experiment files use models by name.
TEST(GlintModel, NoSecondListOfModelNames) {
  std::vector<std::string> names;
  for (const auto& m : core::builtin_glint_models()) names.push_back(m.name);
  ASSERT_GE(names.size(), 2u);
  const std::vector<test::SourceFile> sources =
      test::project_sources({"shaders/glint/models", "shaders/tests", "core/testkit"});
  for (const test::SourceFile& f : sources) {
    std::vector<std::string> found;
    for (const auto& n : names) {
      std::string upper = n;
      for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
      std::string cap = n;
      cap[0] = char(std::toupper(static_cast<unsigned char>(cap[0])));
      // as a string, a GLSL constant or an enum value
      std::regex pat("[\"']" + n + "[\"']|SAND_GLINT_" + upper + "\\b|GlintModel::" + cap + "\\b");
      if (std::regex_search(f.text, pat)) found.push_back(n);
    }
    EXPECT_LT(found.size(), 2u) << f.path << " names the models " << ::testing::PrintToString(found);
  }
  EXPECT_GT(sources.size(), 100u);
}

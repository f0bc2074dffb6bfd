// A temporal resolve is one file (core/render/taa_resolve.h, shaders/taa/interface.glsl): its
// declaration lines, the registry of shaders/taa/, a user's file from the experiment file with the
// guarantees of a user's glint model, and `glintlab taa-test` on resolves that pass and fail it.
#include "core/render/taa_resolve.h"
#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"
#include "experiments/runner/runner.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/taa_test/taa_test.h"
#include "tests/support/project_sources.h"
#include "tests/support/temp_dir.h"
#include "tests/support/user_file_run.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

const fs::path kResolves = fs::path(GLINTLAB_TEST_DATA_DIR) / "taa_resolves";

RunOptions options(const fs::path& exp, const fs::path& out) { return test::user_file_run_options(exp, out); }
void write(const fs::path& p, const std::string& text) { test::write_text(p, text); }
std::string read(const fs::path& p) { return test::read_text(p); }

void expect_error(const std::string& text, const std::string& want) {
  try {
    core::parse_taa_resolve("r", "r.glsl", text);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
  }
}

// A tiny run of a variant with the user's resolve `taa` ("taa" object).
nlohmann::json user_experiment(const nlohmann::json& taa) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "name": "user-resolve",
    "resolution": [32, 18],
    "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 8, "amplitude": 0.4, "wavelength": 5}},
    "camera_path": {"type": "orbit", "fps": 30, "frames": 3, "center": [0, 0, 0], "radius": 3.6,
                    "height": 1.7, "start_deg": 180, "end_deg": 184, "fov": 40},
    "material": {"preset": "thesis-default", "sigmoid_b": 100},
    "variants": [{"name": "user", "aa": "taa"}],
    "reference": {"grid": 2},
    "metrics": ["deltaE2000"],
    "output": {"exr": false, "png": false}
  })");
  j["variants"][0]["taa"] = taa;
  return j;
}

int run(const RunOptions& o, std::ostringstream& log) {
  try {
    return run_experiment(o, log);
  } catch (const core::ShaderCompileError& e) {
    log << e.what();
    return 3;  // what run_guarded maps it to
  }
}

}  // namespace

TEST(TaaResolve, DeclarationsAreParsedAndMalformedOnesNamed) {
  const core::TaaResolveDecl d = core::parse_taa_resolve(
      "r", "r.glsl",
      "// taa_resolve checks=finite,cut fails=ghosting\n"
      "// taa_parameter alpha default=0.2 range=0.01,1\n"
      "// taa_parameter sharpen default=true\n"
      "// taa_parameter amount default=0.5 range=0,1 requires=sharpen\n"
      "// taa_option kernel=box|tent|gauss default=tent requires=sharpen\n");
  EXPECT_EQ(d.checks, (std::vector<std::string>{"finite", "cut"}));
  EXPECT_EQ(d.fails, (std::vector<std::string>{"ghosting"}));
  ASSERT_EQ(d.parameters.size(), 3u);
  EXPECT_DOUBLE_EQ(d.parameters[0].def, 0.2);
  EXPECT_TRUE(d.parameters[1].is_bool);
  EXPECT_EQ(d.parameters[2].requires_bool, "sharpen");
  ASSERT_EQ(d.options.size(), 1u);
  EXPECT_EQ(d.options[0].def, 1u);
  core::TaaSettings s(d);
  EXPECT_EQ(s.option("kernel"), "tent");
  EXPECT_THROW(s.set("alpha", 2.0), std::invalid_argument);
  EXPECT_THROW(s.set("kernel", "lanczos"), std::invalid_argument);
  EXPECT_THROW(s.set("nope", 1.0), std::invalid_argument);
  const std::vector<std::string> defs = s.set("sharpen", false).defines();
  for (const char* want : {"TAA_ON_sharpen=0", "TAA_ON_alpha=1", "TAA_kernel=1", "TAA_kernel_gauss=2"})
    EXPECT_NE(std::find(defs.begin(), defs.end(), want), defs.end()) << want;

  expect_error("// taa_parameter a default=1 range=0,2\n", "no taa_resolve declaration line");
  expect_error("// taa_resolve checks=finite,sharp\n", "unknown check \"sharp\"");
  expect_error("// taa_resolve checks=cut fails=cut\n", "both in checks= and in fails=");
  expect_error("// taa_resolve checks=cut\n// taa_parameter a default=3 range=0,2\n", "r.glsl:2: default of a");
  expect_error("// taa_resolve checks=cut\n// taa_parameter pixel default=1 range=0,2\n", "\"pixel\" is taken");
  expect_error("// taa_resolve checks=cut\n// taa_parameter Alpha default=1 range=0,2\n", "lower_snake_case");
  expect_error("// taa_resolve checks=cut\n// taa_option k=a default=a\n", "at least two choices");
  expect_error("// taa_resolve checks=cut\n// taa_option k=a|B default=a\n", "choice \"B\"");
  expect_error("// taa_resolve checks=cut\n// taa_option k=a|b default=c\n", "default of option k");
  expect_error("// taa_resolve checks=cut\n// taa_option k=a|b default=a\n// taa_parameter k default=1 range=0,2\n",
               "declared twice");
  expect_error("// taa_resolve checks=cut\n// taa_parameter a default=1 range=0,2 requires=b\n",
               "requires=b, which is no other bool parameter");
  expect_error("// taa_resolve checks=cut\n// taa_option x=y_z|w default=w\n// taa_option x_y=z|q default=q\n",
               "gives the macro TAA_x_y_z a second time");
}

// Adding a built-in resolve is adding its file, and adding a design choice is adding its declaration:
// no source of the product lists the resolves' names, or the options of one of them (the stress suite
// and the tests set options by name, as experiment files do).
TEST(TaaResolve, NoSecondListOfResolvesOrTheirOptions) {
  const auto& resolves = core::builtin_taa_resolves();
  ASSERT_FALSE(resolves.empty());
  ASSERT_NE(core::find_builtin_taa_resolve(core::kTaaDefaultResolve), nullptr);
  std::set<std::string> names;                   // every parameter and option
  std::vector<std::vector<std::string>> choices;  // each option's choices but "none"
  for (const auto& r : resolves) {
    for (const auto& p : r.parameters) names.insert(p.name);
    for (const auto& o : r.options) {
      names.insert(o.name);
      choices.emplace_back();
      for (const auto& c : o.choices)
        if (c != "none") choices.back().push_back(c);
    }
  }
  ASSERT_GE(names.size(), 15u);
  const std::vector<test::SourceFile> sources = test::project_sources({"shaders/taa", "shaders/tests", "experiments/stress"});
  for (const test::SourceFile& f : sources) {
    auto quoted = [&](const std::string& n) { return std::regex_search(f.text, std::regex("[\"']" + n + "[\"']")); };
    std::vector<std::string> found;
    for (const auto& n : names)
      if (quoted(n)) found.push_back(n);
    EXPECT_LT(found.size(), 3u) << f.path << " names the options " << ::testing::PrintToString(found);
    for (const auto& list : choices) {
      std::vector<std::string> listed;
      for (const auto& c : list)
        if (quoted(c)) listed.push_back(c);
      EXPECT_LT(listed.size(), 2u) << f.path << " names the choices " << ::testing::PrintToString(listed);
    }
  }
  EXPECT_GT(sources.size(), 100u);
}

// The old experiment files' "taa" object is falcor's parameters and options; the new forms name a
// built-in resolve or a file, with "parameters".
TEST(TaaResolve, TheThreeFormsOfTheTaaObject) {
  auto spec_of = [](const nlohmann::json& taa) {
    nlohmann::json j = user_experiment(taa);
    return ExperimentSpec::from_json(j, "inline-test").variants[0].taa;
  };
  const core::TaaSettings flat = spec_of({{"clamp", "minmax"}, {"alpha", 0.2}, {"jitter", "r2"}});
  const core::TaaSettings named = spec_of({{"name", "falcor"}, {"jitter", "r2"},
                                           {"parameters", {{"clamp", "minmax"}, {"alpha", 0.2}}}});
  EXPECT_EQ(flat.resolve->name, "falcor");
  EXPECT_EQ(flat.values, named.values);
  EXPECT_EQ(flat.choices, named.choices);
  EXPECT_EQ(flat.to_json(), named.to_json());
  EXPECT_EQ(flat.to_json()["clamp"], "minmax");
  EXPECT_EQ(flat.to_json()["jitter"], "r2");
  const core::TaaSettings file = spec_of({{"file", (kResolves / "minmax_bilinear.glsl").string()},
                                          {"parameters", {{"alpha", 0.5}}}});
  EXPECT_FALSE(file.resolve->builtin);
  EXPECT_DOUBLE_EQ(file.value("alpha"), 0.5);
  EXPECT_EQ(file.jitter, core::JitterSequence::Halton16) << "the default jitter of every resolve";
  EXPECT_EQ(file.to_json()["hash"], file.resolve->content_hash);
  const core::TaaUses u = file.uses();
  EXPECT_TRUE(u.motion);
  EXPECT_FALSE(u.glint || u.state || u.state2 || u.history2) << "binds only what the file reads";
  auto rejected = [&](const nlohmann::json& taa, const std::string& want) {
    try {
      spec_of(taa);
      ADD_FAILURE() << "accepted " << taa.dump();
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
  };
  rejected({{"name", "falcor"}, {"alpha", 0.2}}, "variants[0].taa.alpha");  // parameters go in "parameters"
  rejected({{"name", "nope"}}, "falcor");
  rejected({{"name", "falcor"}, {"file", "x.glsl"}}, "not both");
  rejected({{"file", (kResolves / "minmax_bilinear.glsl").string()}, {"parameters", {{"alpha", 2}}}},
           "variants[0].taa.parameters.alpha");
  rejected({{"file", "missing.glsl"}}, "missing.glsl");
}

// The guarantees of a user's glint model, for a user's resolve: parameters checked before any output
// (exit 2), a compile error exits 3 naming the file and line before any output, resources of its own
// refused before the driver sees them, its hash among the run's inputs (a changed file refuses
// --resume), and NaN output counted as a defect of the run (exit 1).
TEST(UserTaaResolve, GuaranteesOfAUsersFile) {
  test::TempDir dir("user_taa_resolve");
  fs::copy_file(kResolves / "minmax_bilinear.glsl", dir.path() / "r.glsl");
  const fs::path e = dir.path() / "e.json", out = dir.path() / "out";
  {
    write(e, user_experiment({{"file", "r.glsl"}, {"parameters", {{"alpha", 5}}}}).dump());
    std::ostringstream log;
    EXPECT_EQ(run(options(e, out), log), 2) << log.str();
    EXPECT_NE(log.str().find("parameters.alpha"), std::string::npos) << log.str();
    EXPECT_FALSE(fs::exists(out / "records.jsonl"));
  }
  {
    write(dir.path() / "bad.glsl", read(kResolves / "minmax_bilinear.glsl") + "vec3 broken() { return vec3(1.0) }\n");
    write(e, user_experiment({{"file", "bad.glsl"}}).dump());
    std::ostringstream log;
    EXPECT_EQ(run(options(e, out), log), 3) << log.str();
    EXPECT_NE(log.str().find("bad.glsl:18"), std::string::npos) << log.str();
    EXPECT_FALSE(fs::exists(out)) << "nothing written before the file compiles";
  }
  for (const char* body : {"layout(set = 0, binding = 9) uniform sampler2D evil;\n", "#define B buffer\nB Evil { float x[]; };\n"}) {
    write(dir.path() / "res.glsl", std::string("// taa_resolve checks=finite\n") + body +
                                       "TaaResult taa_resolve(TaaPixel p) { return taa_result(taa_current(ivec2(0))); }\n");
    write(e, user_experiment({{"file", "res.glsl"}}).dump());
    std::ostringstream log;
    EXPECT_EQ(run(options(e, out), log), 2) << log.str();
    EXPECT_NE(log.str().find("res.glsl:2"), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("a TAA resolve may not use"), std::string::npos) << log.str();
  }
  {
    write(e, user_experiment({{"file", "r.glsl"}}).dump());
    RunOptions o = options(e, out);
    o.max_frames = 2;
    std::ostringstream first, same, changed;
    ASSERT_EQ(run(o, first), 0) << first.str();
    EXPECT_NE(read(out / "records.jsonl").find("taa_resolve "), std::string::npos) << "the file is a run input";
    o.resume = true;
    EXPECT_EQ(run(o, same), 0) << same.str();
    write(dir.path() / "r.glsl", read(dir.path() / "r.glsl") + "// changed\n");
    EXPECT_EQ(run(o, changed), 2) << changed.str();
    EXPECT_NE(changed.str().find("--resume"), std::string::npos) << changed.str();
  }
  {
    fs::copy_file(kResolves / "nan_pixels.glsl", dir.path() / "nan.glsl");
    write(e, user_experiment({{"file", "nan.glsl"}}).dump());
    std::ostringstream log;
    EXPECT_EQ(run(options(e, dir.path() / "out-nan"), log), 1) << log.str();
    EXPECT_NE(log.str().find("NaN"), std::string::npos) << log.str();
  }
}

// The suite passes Falcor's resolve on what its design meets and reports converges as its declared
// failure; it fails a resolve that shows the history unchanged (ghosting, cut) and one with NaN pixels
// (finite); the README's example resolve passes what it declares.
TEST(TaaTest, PassesFalcorAndFailsBrokenResolves) {
  core::VkContext& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  test::TempDir dir("taa_test");
  auto suite = [&](const core::TaaSettings& s, const std::string& sub) {
    fs::create_directories(dir.path() / sub);
    return run_taa_test(ctx, s, (dir.path() / sub).string(), "");
  };
  const ConformanceReport falcor = suite(taa_test_settings("falcor", {}), "falcor");
  EXPECT_TRUE(falcor.all_pass()) << falcor.text();
  for (const char* c : {"finite", "deterministic", "ghosting", "cut", "pan", "flicker"})
    EXPECT_TRUE(falcor.check(c)->applies && falcor.check(c)->pass) << c << "\n" << falcor.text();
  EXPECT_TRUE(falcor.check("converges")->expected_failure && !falcor.check("converges")->pass) << falcor.text();

  // the accumulating resolve without rectification converges as supersampling with as many samples
  const ConformanceReport acc =
      suite(taa_test_settings("falcor", {"accumulate=true", "clamp=none", "feedback=fixed", "alpha=0.015625"}), "acc");
  EXPECT_TRUE(acc.check("converges")->pass) << acc.text();
  EXPECT_FALSE(acc.all_pass()) << "it passes converges where Falcor declares it fails\n" << acc.text();

  const ConformanceReport frozen = suite(taa_test_settings((kResolves / "history_only.glsl").string(), {}), "frozen");
  EXPECT_FALSE(frozen.all_pass());
  EXPECT_FALSE(frozen.check("ghosting")->pass) << frozen.text();
  EXPECT_FALSE(frozen.check("cut")->pass) << frozen.text();

  const ConformanceReport nan = suite(taa_test_settings((kResolves / "nan_pixels.glsl").string(), {}), "nan");
  EXPECT_FALSE(nan.all_pass());
  EXPECT_FALSE(nan.check("finite")->pass) << nan.text();

  const ConformanceReport readme = suite(taa_test_settings((kResolves / "minmax_bilinear.glsl").string(), {}), "readme");
  EXPECT_TRUE(readme.all_pass()) << readme.text();
  EXPECT_THROW(taa_test_settings("falcor", {"clamp=sometimes"}), ConfigError);
  EXPECT_THROW(taa_test_settings("nope", {}), ConfigError);
}

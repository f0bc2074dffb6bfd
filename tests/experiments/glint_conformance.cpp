// The conformance suite (`glintlab glint-test`) on every built-in model and
// on user model files that must fail it, and a user's model file in an
// experiment: validated before any work, compile errors named by line, its
// content part of the run's inputs (a changed file refuses --resume).
#include "experiments/glint_test/glint_test.h"
#include "core/material/glint_table.h"
#include "core/util/json_check.h"
#include "core/util/strings.h"
#include "core/vk/shader_compiler.h"
#include "core/material/program.h"
#include "experiments/runner/runner.h"
#include "experiments/spec/experiment_spec.h"

#include "tests/support/temp_dir.h"
#include "tests/support/user_file_run.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

const fs::path kModels = fs::path(GLINTLAB_TEST_DATA_DIR) / "glint_models";

const GlintCheckResult& check(const GlintTestReport& r, const std::string& name) {
  for (const auto& c : r.checks)
    if (c.name == name) return c;
  throw std::runtime_error("no check " + name);
}

GlintTestReport conformance(const std::string& model, const std::vector<std::string>& params = {}) {
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const core::GlintModelDecl d = resolve_glint_model(model);
  return run_glint_test(ctx, d, glint_test_parameters(d, params));
}

}  // namespace

TEST(GlintTest, EveryBuiltInModelPassesEveryCheckItDeclares) {
  for (const auto& m : core::builtin_glint_models()) {
    GlintTestReport r = conformance(m.name);
    SCOPED_TRACE(r.text());
    EXPECT_TRUE(r.all_pass()) << m.name;
    size_t applying = 0;
    for (const auto& c : r.checks) {
      EXPECT_TRUE(std::isfinite(c.figure)) << m.name << " " << c.name;
      if (c.applies && !c.figure_only) {
        // a check in fails= is the published method's own defect: it must still fail
        EXPECT_NE(c.pass, c.expected_failure) << m.name << " " << c.name;
        ++applying;
      }
    }
    EXPECT_GE(applying, 3u) << m.name;  // finite, unbiased, deterministic at least
    if (std::getenv("GLINTLAB_PRINT_ERRORS")) std::printf("%s", r.text().c_str());
  }
}

TEST(GlintTest, TwiceBeckmannFailsUnbiasedAndNanAtGrazingFailsFinite) {
  // the inline Beckmann with k = 1 passes; with k = 2 it is 2 x Beckmann
  GlintTestReport one = conformance((kModels / "beckmann_inline.glsl").string());
  EXPECT_TRUE(one.all_pass()) << one.text();
  GlintTestReport two = conformance((kModels / "beckmann_inline.glsl").string(), {"k=2"});
  EXPECT_FALSE(two.all_pass());
  EXPECT_FALSE(check(two, "unbiased").pass) << two.text();
  EXPECT_TRUE(check(two, "finite").pass) << two.text();
  EXPECT_FALSE(check(two, "limit").pass) << two.text();

  GlintTestReport nan = conformance((kModels / "nan_grazing.glsl").string());
  EXPECT_FALSE(check(nan, "finite").pass) << nan.text();
  EXPECT_GT(check(nan, "finite").figure, 0.0);
  EXPECT_NE(check(nan, "finite").detail.find("NaN"), std::string::npos);
}

TEST(GlintTest, DeclaredFailuresAreRunAndExpectedToFail) {
  GlintTestReport biased = conformance((kModels / "biased_declared.glsl").string());
  EXPECT_TRUE(biased.all_pass()) << biased.text();
  EXPECT_TRUE(check(biased, "unbiased").applies);
  EXPECT_TRUE(check(biased, "unbiased").expected_failure);
  EXPECT_FALSE(check(biased, "unbiased").pass) << biased.text();
  EXPECT_GT(check(biased, "limit").figure, 40.0) << "1.5 x the limit is 50 % off";
  EXPECT_NE(biased.text().find("fails "), std::string::npos) << biased.text();
  // declaring a check it passes as failing fails the suite, naming the fix
  test::TempDir dir("declared_failure");
  std::string text = read_text_file(kModels / "biased_declared.glsl").value();
  const size_t at = text.find("checks=finite,deterministic fails=unbiased,limit");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 48, "checks=deterministic fails=unbiased,limit,finite");
  std::ofstream(dir / "wrong.glsl") << text;
  GlintTestReport wrong = conformance((dir / "wrong.glsl").string());
  EXPECT_FALSE(wrong.all_pass()) << wrong.text();
  EXPECT_TRUE(check(wrong, "finite").pass);
  EXPECT_NE(wrong.text().find("take it out of fails="), std::string::npos) << wrong.text();
}

TEST(GlintTest, AModelReadsTheDataTableItsFileGenerates) {
  const core::GlintModelDecl d = resolve_glint_model((kModels / "beckmann_table.glsl").string());
  ASSERT_EQ(d.table_size, 4096u);
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  auto table = core::glint_table(ctx, d);
  ASSERT_EQ(table->size(), 4096u);
  for (size_t i = 0; i < table->size(); ++i) ASSERT_EQ((*table)[i], float(i)) << i;
  EXPECT_EQ(core::glint_table(ctx, d).get(), table.get()) << "generated once per content";
  // glint_D reads entry i / i = 1: every figure is the built-in beckmann's, bit for bit
  GlintTestReport t = conformance(d.file), b = conformance("beckmann");
  EXPECT_TRUE(t.all_pass()) << t.text();
  for (const auto& c : b.checks) EXPECT_EQ(check(t, c.name).figure, c.figure) << c.name;
}

TEST(GlintTest, TheChecksCompareWithTheDeclaredSmoothLimit) {
  // GGX declared with its own limit passes; the same function declared with the Beckmann limit is biased
  GlintTestReport ggx = conformance((kModels / "ggx_inline.glsl").string());
  EXPECT_TRUE(ggx.all_pass()) << ggx.text();
  test::TempDir dir("ggx_as_beckmann");
  std::ifstream in(kModels / "ggx_inline.glsl");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const size_t at = text.find("limit=ggx");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 9, "limit=beckmann");
  std::ofstream(dir / "ggx_as_beckmann.glsl") << text;
  GlintTestReport wrong = conformance((dir / "ggx_as_beckmann.glsl").string());
  EXPECT_FALSE(check(wrong, "unbiased").pass) << wrong.text();
  EXPECT_TRUE(check(wrong, "finite").pass) << wrong.text();
}

TEST(GlintTest, LodCoherenceOfAFootprintIgnoringModelIsReported) {
  GlintTestReport point = conformance((kModels / "point_sample.glsl").string());
  const GlintCheckResult& lod = check(point, "LOD coherence");
  EXPECT_TRUE(lod.figure_only);
  // its value at the centre knows nothing of the four sub-footprints' cells
  EXPECT_LT(lod.figure, 0.5) << point.text();
  EXPECT_GT(lod.figure, -0.5) << point.text();
  // the smooth limit is the same everywhere: as coherent as the exact box filter
  GlintTestReport beck = conformance("beckmann");
  EXPECT_EQ(check(beck, "LOD coherence").figure, 1.0);
  EXPECT_EQ(check(beck, "shift coherence").figure, 1.0);
}

TEST(GlintTest, ParametersAndModelsAreValidated) {
  const core::GlintModelDecl zirr = resolve_glint_model("zirr");
  EXPECT_THROW(glint_test_parameters(zirr, {"size_variation=3"}), ConfigError);
  EXPECT_THROW(glint_test_parameters(zirr, {"k=1"}), ConfigError);
  EXPECT_THROW(glint_test_parameters(zirr, {"half_vector_blend=2"}), ConfigError);
  auto p = glint_test_parameters(zirr, {"size_variation=0.5"});
  EXPECT_EQ(p[size_t(zirr.parameter("size_variation") - zirr.parameters.data())], 0.5f);
  EXPECT_THROW(resolve_glint_model("zirr2"), ConfigError);
}

// ---------------------------------------------------------------- a user's model file in an experiment

namespace {

nlohmann::json user_experiment(const nlohmann::json& model) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "name": "user-model",
    "resolution": [32, 18],
    "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 8, "amplitude": 0.4, "wavelength": 5}},
    "camera_path": {"type": "orbit", "fps": 30, "frames": 2, "center": [0, 0, 0], "radius": 3.6,
                    "height": 1.7, "start_deg": 180, "end_deg": 182, "fov": 40},
    "material": {"preset": "thesis-default", "sigmoid_b": 100},
    "variants": [{"name": "user"}],
    "reference": {"grid": 2},
    "metrics": ["deltaE2000"],
    "output": {"exr": false, "png": false}
  })");
  j["variants"][0]["material"] = {{"glint_model", model}};
  return j;
}

RunOptions options(const fs::path& exp, const fs::path& out) { return test::user_file_run_options(exp, out); }
void write(const fs::path& p, const std::string& text) { test::write_text(p, text); }
std::string read(const fs::path& p) { return test::read_text(p); }

}  // namespace

TEST(UserGlintModel, OutOfRangeParameterIsRefusedBeforeAnyWork) {
  test::TempDir dir("user_glint_model");
  fs::copy_file(kModels / "beckmann_inline.glsl", dir.path() / "m.glsl");
  write(dir.path() / "e.json", user_experiment({{"file", "m.glsl"}, {"parameters", {{"k", 5}}}}).dump());
  std::ostringstream log;
  EXPECT_EQ(run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log), 2) << log.str();
  EXPECT_NE(log.str().find("parameters.k"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("[0, 2]"), std::string::npos) << log.str();
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "records.jsonl"));
  // an unknown parameter and a missing file are refused the same way
  write(dir.path() / "e.json", user_experiment({{"file", "m.glsl"}, {"parameters", {{"q", 1}}}}).dump());
  std::ostringstream log2;
  EXPECT_EQ(run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log2), 2) << log2.str();
  EXPECT_NE(log2.str().find("parameters.q"), std::string::npos) << log2.str();
  write(dir.path() / "e.json", user_experiment({{"file", "missing.glsl"}}).dump());
  std::ostringstream log3;
  EXPECT_EQ(run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log3), 2) << log3.str();
  EXPECT_NE(log3.str().find("missing.glsl"), std::string::npos) << log3.str();
}

TEST(UserGlintModel, SyntaxErrorExitsThreeNamingItsLine) {
  test::TempDir dir("user_glint_model");
  fs::copy_file(kModels / "syntax_error.glsl", dir.path() / "bad.glsl");
  write(dir.path() / "e.json", user_experiment({{"file", "bad.glsl"}}).dump());
  std::ostringstream log;
  int code = -1;
  try {
    code = run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log);
  } catch (const core::ShaderCompileError& e) {
    code = 3;  // what run_guarded maps it to
    log << e.what();
  }
  EXPECT_EQ(code, 3) << log.str();
  EXPECT_NE(log.str().find("bad.glsl:5"), std::string::npos) << log.str();
}

// A model file that includes itself, or two that include each other, without a guard: a compile error
// (exit 3) naming the file and line, not a preprocessor that recurses until memory runs out.
TEST(UserGlintModel, IncludeCyclesAreACompileErrorNotARunaway) {
  test::TempDir dir("user_glint_model");
  const std::string body = "#include \"glint/query.glsl\"\n#include \"common/beckmann.glsl\"\n"
                           "vec3 glint_D(GlintQuery q) { return vec3(beckmann_D(q.h, vec2(0.0), q.alpha_g)); }\n";
  write(dir.path() / "self.glsl", "// glint_model truth=grains limit=beckmann checks=finite\n#include \"self.glsl\"\n" + body);
  write(dir.path() / "a.glsl", "// glint_model truth=grains limit=beckmann checks=finite\n#include \"b.glsl\"\n" + body);
  write(dir.path() / "b.glsl", "#include \"a.glsl\"\n");
  for (const char* f : {"self.glsl", "a.glsl"}) {
    write(dir.path() / "e.json", user_experiment({{"file", f}}).dump());
    std::ostringstream log;
    int code = -1;
    try {
      code = run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log);
    } catch (const core::ShaderCompileError& e) {
      code = 3;
      log << e.what();
    }
    EXPECT_EQ(code, 3) << f << ": " << log.str();
    EXPECT_NE(log.str().find("includes nest deeper than 32"), std::string::npos) << log.str();
    EXPECT_NE(log.str().find(std::string(f == std::string("self.glsl") ? "self.glsl:2" : ".glsl:")), std::string::npos)
        << log.str();
  }
}

// A model that declares resources of its own (a descriptor set the pipeline does not have crashed the
// driver; a binding outside the layout read unbound memory), work-group memory, or discards, is refused
// before the driver sees it (exit 2, naming the file and line), a macro hiding the word included.
TEST(UserGlintModel, ResourcesOfItsOwnAreRefusedBeforeTheDriver) {
  test::TempDir dir("user_glint_model");
  const std::string head = "// glint_model truth=grains limit=beckmann checks=finite\n#include \"glint/query.glsl\"\n"
                           "#include \"common/beckmann.glsl\"\n";
  const std::string plain = "vec3 glint_D(GlintQuery q) { return vec3(beckmann_D(q.h, vec2(0.0), q.alpha_g)); }\n";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"layout(set = 3, binding = 0) buffer Evil { float x[]; };\n" + plain, "layout", ":4"},
      {"layout(set = 0, binding = 7) uniform sampler2D t;\n" + plain, "layout", ":4"},
      {"#define B buffer\nB Evil { float x[]; };\n" + plain, "buffer", ":4"},
      {"shared float s[64];\n" + plain, "shared", ":4"},
      {"vec3 glint_D(GlintQuery q) { if (q.h.z < 0.5) discard; return vec3(1.0); }\n", "discard", ":4"}};
  for (const auto& [body, word, line] : cases) {
    write(dir.path() / "m.glsl", head + body);
    write(dir.path() / "e.json", user_experiment({{"file", "m.glsl"}}).dump());
    std::ostringstream log;
    EXPECT_EQ(run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log), 2) << log.str();
    EXPECT_NE(log.str().find("m.glsl" + line), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("may not use \"" + word + "\""), std::string::npos) << log.str();
    EXPECT_FALSE(fs::exists(dir.path() / "out" / "records.jsonl"));
  }
}

TEST(UserGlintModel, ResumeAfterTheFileChangedIsRefused) {
  test::TempDir dir("user_glint_model");
  fs::copy_file(kModels / "beckmann_inline.glsl", dir.path() / "m.glsl");
  write(dir.path() / "e.json", user_experiment({{"file", "m.glsl"}, {"truth", "self"}}).dump());
  RunOptions o = options(dir.path() / "e.json", dir.path() / "out");
  o.max_frames = 1;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(o, log), 0) << log.str();
  const std::string header = read(dir.path() / "out" / "records.jsonl");
  EXPECT_NE(header.find("glint_model "), std::string::npos) << "the file's hash is one of the run's inputs";
  o.resume = true;
  std::ostringstream same;
  EXPECT_EQ(run_experiment(o, same), 0) << same.str();  // unchanged: resumes
  auto reference_key = [&] {
    const ExperimentSpec spec = ExperimentSpec::from_json(read_json_file((dir.path() / "e.json").string()),
                                                          (dir.path() / "e.json").string());
    return core::sand_program(spec.variants[0].material, {}, core::ProgramRole::Reference).cache_key();
  };
  const std::string key_before = reference_key();
  write(dir.path() / "m.glsl", read(dir.path() / "m.glsl") + "// changed\n");
  EXPECT_NE(reference_key(), key_before) << "the file's content is part of the reference cache key";
  std::ostringstream changed;
  EXPECT_EQ(run_experiment(o, changed), 2) << changed.str();
  EXPECT_NE(changed.str().find("--resume"), std::string::npos) << changed.str();
  // a file the model includes is one of the run's inputs too
  write(dir.path() / "inc.glsl", "float user_scale() { return 1.0; }\n");
  write(dir.path() / "m.glsl", "#include \"inc.glsl\"\n" + read(dir.path() / "m.glsl"));
  o.resume = false;
  std::ostringstream fresh;
  ASSERT_EQ(run_experiment(o, fresh), 0) << fresh.str();
  o.resume = true;
  write(dir.path() / "inc.glsl", "float user_scale() { return 2.0; }\n");
  std::ostringstream included;
  EXPECT_EQ(run_experiment(o, included), 2) << included.str();
  EXPECT_NE(included.str().find("glint_model"), std::string::npos) << included.str();
}

TEST(UserGlintModel, AModelWithADataTableRendersAsTheModelItComputes) {
  // the table holds i, glint_D reads entry i / i = 1: the frames equal the built-in beckmann's
  test::TempDir dir("user_glint_table");
  fs::copy_file(kModels / "beckmann_table.glsl", dir.path() / "t.glsl");
  nlohmann::json j = user_experiment({{"file", "t.glsl"}, {"truth", "self"}});
  j["variants"].push_back({{"name", "beckmann"}, {"material", {{"glint_model", "beckmann"}}}});
  write(dir.path() / "e.json", j.dump());
  RunOptions o = options(dir.path() / "e.json", dir.path() / "out");
  o.max_frames = 1;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(o, log), 0) << log.str();
  std::map<std::string, double> de;
  std::istringstream records(read(dir.path() / "out" / "records.jsonl"));
  for (std::string line; std::getline(records, line);) {
    const nlohmann::json r = nlohmann::json::parse(line);
    if (r.value("type", "") != "frame") continue;
    for (const auto& kv : r["metrics"])  // [name, value] pairs
      if (kv[0] == "deltaE2000") de[r["name"]] = kv[1].get<double>();
  }
  ASSERT_EQ(de.size(), 2u) << read(dir.path() / "out" / "records.jsonl");
  EXPECT_GT(de["beckmann"], 0.0);
  EXPECT_EQ(de["user"], de["beckmann"]);
  EXPECT_TRUE(fs::exists(dir.path() / "cache" / "glint-tables")) << "kept in the run's cache folder";
}

TEST(GlintModelRender, EveryBuiltInModelRendersFiniteAndNonNegativeAtTwoRoughnesses) {
  // one frame of every built-in model at a smooth and a rough global roughness, validation on: the
  // run scans every frame (truths included) and exits 1 on a NaN, Inf or negative pixel
  test::TempDir dir("every_model_render");
  nlohmann::json j = user_experiment({});
  j["variants"] = nlohmann::json::array();
  for (const auto& m : core::builtin_glint_models())
    for (double alpha : {0.05, 0.5})
      j["variants"].push_back({{"name", m.name + "-" + std::to_string(int(alpha * 100))},
                               {"material", {{"glint_model", m.name}, {"glints", {{"alpha_g", {alpha, alpha}}}}}}});
  j["material"]["glints"] = {{"log_density", 6}};
  write(dir.path() / "e.json", j.dump());
  RunOptions o = options(dir.path() / "e.json", dir.path() / "out");
  o.max_frames = 1;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(o, log), 0) << log.str();
  size_t frames = 0;
  std::istringstream records(read(dir.path() / "out" / "records.jsonl"));
  for (std::string line; std::getline(records, line);) {
    const nlohmann::json r = nlohmann::json::parse(line);
    if (r.value("type", "") != "frame") continue;
    ++frames;
    const auto& scan = r["scan"];  // pixels, nan, +inf, -inf, infinite, negative
    EXPECT_GT(scan[0].get<double>(), 0.0) << r["name"];
    for (int k = 1; k < 6; ++k) EXPECT_EQ(scan[k].get<double>(), 0.0) << r["name"] << " scan " << k;
  }
  EXPECT_EQ(frames, 2 * core::builtin_glint_models().size());
}

TEST(UserGlintModel, NegativeValuesAreDefectsOfTheRun) {
  test::TempDir dir("user_glint_model");
  fs::copy_file(kModels / "negative.glsl", dir.path() / "neg.glsl");
  write(dir.path() / "e.json", user_experiment({{"file", "neg.glsl"}}).dump());
  RunOptions o = options(dir.path() / "e.json", dir.path() / "out");
  o.max_frames = 1;
  std::ostringstream log;
  EXPECT_EQ(run_experiment(o, log), 1) << log.str();
  EXPECT_NE(log.str().find("negative pixels"), std::string::npos) << log.str();
}

// Every truth writes NAME, NAME-half-a and NAME-half-b: a user's model file named kajs-half-a.glsl (its own
// truth) beside the Kajs material must not write into the Kajs truth's half A; the later truth is numbered.
TEST(UserGlintModel, TruthsNeverShareAFolder) {
  test::TempDir dir("user_glint_model");
  fs::copy_file(kModels / "beckmann_inline.glsl", dir.path() / "kajs-half-a.glsl");
  nlohmann::json e = user_experiment({{"file", "kajs-half-a.glsl"}, {"truth", "self"}});
  e["variants"].push_back({{"name", "thesis"}, {"material", {{"glint_model", "kajs"}}}});
  e["output"] = {{"exr", true}, {"png", false}, {"halves", true}};
  write(dir.path() / "e.json", e.dump());
  std::ostringstream log;
  ASSERT_EQ(run_experiment(options(dir.path() / "e.json", dir.path() / "out"), log), 0) << log.str();
  const nlohmann::json s = nlohmann::json::parse(read(dir.path() / "out" / "summary.json"));
  std::set<std::string> folders;
  for (const auto& r : s["references"])
    for (const char* suffix : {"", "-half-a", "-half-b"})
      EXPECT_TRUE(folders.insert(r["name"].get<std::string>() + suffix).second) << r["name"] << suffix;
  EXPECT_EQ(s["references"].size(), 2u);
  EXPECT_TRUE(fs::exists(dir.path() / "out" / "reference-kajs-half-a"));  // the Kajs truth keeps its name
}

// The glint table cached on disk carries its checksum: an entry damaged on disk (every value x3) is
// generated again, with a note, and the model reads what it computes (the same figures as the first
// run), not the damaged values. Two fresh processes, so neither reads the other's memory.
TEST(UserGlintModel, ADamagedCachedTableIsGeneratedAgain) {
  test::TempDir dir("glint_table_cache");
  const std::string run = "XDG_CACHE_HOME=" + dir.path().string() + " " + GLINTLAB_CLI + " glint-test " +
                          (kModels / "beckmann_table.glsl").string() + " --json";
  ASSERT_EQ(std::system((run + " > " + (dir.path() / "first.json").string() + " 2>&1").c_str()), 0)
      << read(dir.path() / "first.json");
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(dir.path() / "glintlab" / "glint-tables")) entries.push_back(e.path());
  ASSERT_EQ(entries.size(), 1u);
  std::ifstream in(entries[0], std::ios::binary);
  std::string bytes(std::istreambuf_iterator<char>(in), {});
  ASSERT_GT(bytes.size(), 32u);
  for (size_t i = 0; i + 4 <= bytes.size() - 32; i += 4) {  // every value x3, the checksum kept
    float x;
    std::memcpy(&x, bytes.data() + i, 4);
    x *= 3;
    std::memcpy(bytes.data() + i, &x, 4);
  }
  std::ofstream(entries[0], std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  ASSERT_EQ(std::system((run + " > " + (dir.path() / "second.json").string() + " 2> " +
                         (dir.path() / "second.err").string()).c_str()), 0)
      << read(dir.path() / "second.err");
  EXPECT_NE(read(dir.path() / "second.err").find("does not match its checksum"), std::string::npos)
      << read(dir.path() / "second.err");
  auto checks = [&](const char* f) {
    const std::string t = read(dir.path() / f);
    return nlohmann::json::parse(t.substr(t.find('{')))["checks"];
  };
  EXPECT_EQ(checks("first.json"), checks("second.json"));
}

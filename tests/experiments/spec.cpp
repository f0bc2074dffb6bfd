// ExperimentSpec::from_json / load (experiments/spec/experiment_spec.h): malformed experiment files are
// rejected with a ConfigError that names the file and the key path; every shipped experiment loads;
// a minimal spec gets the documented defaults.
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "core/util/json_check.h"
#include "experiments/spec/experiment_spec.h"
#include "metrics/metric_registry.h"

namespace fs = std::filesystem;
using glintlab::ConfigError;
using glintlab::ExperimentSpec;
using nlohmann::json;

namespace {

const char* kFile = "experiments/data/under-test.json";

// The smallest valid experiment: everything else defaulted.
json minimal() {
  return json::parse(R"({
    "scene": {"mesh": {"type": "plane"}},
    "camera_path": {"type": "static", "fps": 30, "frames": 4,
                    "position": [0, 2, -4], "target": [0, 0, 0], "fov": 40},
    "variants": [{"name": "a"}]
  })");
}

// from_json(j) must throw a ConfigError whose message names the file and contains every `needle`
// (the key path, and where useful the offending value).
void expect_rejected(const json& j, const std::vector<std::string>& needles) {
  try {
    ExperimentSpec::from_json(j, kFile);
    ADD_FAILURE() << "accepted: " << j.dump();
  } catch (const ConfigError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(kFile), std::string::npos) << "message does not name the file: " << msg;
    for (const auto& n : needles) EXPECT_NE(msg.find(n), std::string::npos) << "missing \"" << n << "\" in: " << msg;
  }
}

// An experiment file with `text`, in its own TempDir.
struct TempFile {
  glintlab::test::TempDir dir{"spec"};
  fs::path path = dir / "experiment.json";
  explicit TempFile(const std::string& text) { std::ofstream(path) << text; }
};

}  // namespace

// "metrics" may name the groups flicker, glints and pooled: naming any measures flicker and those.
TEST(ExperimentSpec, MetricsListSelectsGroups) {
  json j = minimal();
  ExperimentSpec every = ExperimentSpec::from_json(j, kFile);
  EXPECT_TRUE(every.metric_options.glints && every.metric_options.pooled);
  j["metrics"] = {"deltaE2000", "flicker"};
  ExperimentSpec pair = ExperimentSpec::from_json(j, kFile);
  EXPECT_EQ(pair.metrics, std::vector<std::string>{"deltaE2000"});
  EXPECT_FALSE(pair.metric_options.glints);
  EXPECT_FALSE(pair.metric_options.pooled);
  j["metrics"] = {"pooled", "flip"};
  j["metric_options"] = {{"flip", "ldr"}};  // the options do not undo the selection
  ExperimentSpec pooled = ExperimentSpec::from_json(j, kFile);
  EXPECT_EQ(pooled.metrics, std::vector<std::string>{"flip"});
  EXPECT_FALSE(pooled.metric_options.glints);
  EXPECT_TRUE(pooled.metric_options.pooled);
  j.erase("metric_options");
  j["metrics"] = {"deltaE2000", "glint"};
  expect_rejected(j, {"metrics", "'glint'", "glints", "pooled", "deltaEITP"});
  j["metrics"] = {"flip", "flip"};
  expect_rejected(j, {"metrics", "'flip' is given twice"});
}

TEST(ExperimentSpec, MinimalSpecGetsDocumentedDefaults) {
  ExperimentSpec s = ExperimentSpec::from_json(minimal(), kFile);
  EXPECT_EQ(s.name, "under-test");  // file stem
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 360);
  EXPECT_EQ(s.frames, 4);  // all of the path's frames
  EXPECT_EQ(s.path_name, "inline");
  EXPECT_EQ(s.working_space, "lin_rec709");
  EXPECT_TRUE(s.reference.enabled);
  EXPECT_EQ(s.reference.grid, 16);
  EXPECT_EQ(s.metrics, glintlab::metrics::metric_names());
  EXPECT_TRUE(s.output.exr);
  EXPECT_TRUE(s.output.png);
  EXPECT_EQ(s.output.every, 1);
  ASSERT_EQ(s.variants.size(), 1u);
  const auto& v = s.variants[0];
  EXPECT_EQ(v.aa, glintlab::AaMethod::None);
  EXPECT_EQ(v.samples_per_pixel(), 1);
  EXPECT_EQ(v.debug, "final");
  // No material: the thesis-default preset (Appendix A values).
  const auto def = glintlab::core::SandParams::preset("thesis-default");
  EXPECT_EQ(v.material.SSS, def.SSS);
  EXPECT_EQ(v.material.noise_scale, def.noise_scale);
}

TEST(ExperimentSpec, VariantOverridesMergeOverExperimentMaterial) {
  json j = minimal();
  j["material"] = {{"preset", "thesis-hdri-match"}, {"noise_scale", 500}};
  j["variants"] = json::parse(R"([{"name": "base"}, {"name": "sss", "material": {"SSS": 0.25}},
                                  {"name": "ss", "aa": "ssaa", "ssaa_grid": 3}])");
  ExperimentSpec s = ExperimentSpec::from_json(j, kFile);
  ASSERT_EQ(s.variants.size(), 3u);
  const auto hdri = glintlab::core::SandParams::preset("thesis-hdri-match");
  EXPECT_EQ(s.variants[0].material.SSS, hdri.SSS);
  EXPECT_EQ(s.variants[0].material.noise_scale, 500);
  EXPECT_EQ(s.variants[1].material.SSS, 0.25);
  EXPECT_EQ(s.variants[1].material.noise_scale, 500);  // the experiment's override survives
  EXPECT_EQ(s.variants[1].material.R_s, hdri.R_s);     // the preset's value survives
  EXPECT_EQ(s.variants[2].samples_per_pixel(), 9);
  // nested objects merge key by key: a variant that sets one key of "glints" keeps the experiment's others
  j["material"]["glints"] = {{"log_density", 9}, {"alpha_g", {0.5, 0.5}}};
  j["material"]["glint_model"] = "zirr";
  j["variants"] = json::parse(R"([{"name": "z", "material": {"glints": {"size_variation": 0.5}}},
                                  {"name": "w", "material": {"glints": {"alpha_g": [0.2, 0.3]}}}])");
  s = ExperimentSpec::from_json(j, kFile);
  EXPECT_EQ(s.variants[0].material.glints.log_density, 9);
  EXPECT_EQ(s.variants[0].material.glints.alpha_g[0], 0.5);
  EXPECT_EQ(s.variants[0].material_json["glints"]["size_variation"], 0.5);
  EXPECT_EQ(s.variants[1].material.glints.log_density, 9);
  EXPECT_EQ(s.variants[1].material.glints.alpha_g[1], 0.3);  // an array is replaced whole
}

TEST(ExperimentSpec, RejectsUnknownTopLevelKey) {
  json j = minimal();
  j["resolutoin"] = {320, 180};
  expect_rejected(j, {"resolutoin", "unknown key"});
}

TEST(ExperimentSpec, RejectsUnknownMeshKey) {
  json j = minimal();
  j["scene"]["mesh"]["wobble"] = 3;
  expect_rejected(j, {"scene.mesh.wobble"});
}

TEST(ExperimentSpec, RejectsResolutionOfWrongType) {
  json j = minimal();
  j["resolution"] = "640x360";
  expect_rejected(j, {"resolution"});
  j["resolution"] = {640};
  expect_rejected(j, {"resolution"});
  j["resolution"] = {640.5, 360};
  expect_rejected(j, {"resolution"});
}

TEST(ExperimentSpec, RejectsResolutionOutOfRange) {
  json j = minimal();
  j["resolution"] = {0, 360};
  expect_rejected(j, {"resolution", "out of range"});
  j["resolution"] = {640, 16385};
  expect_rejected(j, {"resolution", "out of range"});
}

TEST(ExperimentSpec, RejectsMissingOrEmptyVariants) {
  json j = minimal();
  j.erase("variants");
  expect_rejected(j, {"variants", "missing"});
  j["variants"] = json::array();
  expect_rejected(j, {"variants"});
}

TEST(ExperimentSpec, RejectsDuplicateVariantNames) {
  json j = minimal();
  j["variants"] = json::parse(R"([{"name": "a"}, {"name": "b"}, {"name": "a", "aa": "ssaa"}])");
  expect_rejected(j, {"variants[2].name", "\"a\""});
}

TEST(ExperimentSpec, RejectsVariantNameWithSlash) {
  json j = minimal();
  j["variants"] = json::parse(R"([{"name": "ok"}, {"name": "a/b"}])");
  expect_rejected(j, {"variants[1].name"});
}

// A name becomes a folder of the run and a CSV row: nothing that leaves the run's folder, lands on
// its own files or splits a row gets through (before anything renders).
TEST(ExperimentSpec, RejectsVariantNamesThatAreNotPlainFolderNames) {
  for (const std::string& name : {std::string(".."), std::string("."), std::string("reference"),
                                  std::string("reference-grains"), std::string("motion"), std::string("figures"),
                                  std::string("summary.json"), std::string("a\nb"), std::string("a\0b", 3),
                                  std::string(300, 'x'), std::string("-x"), std::string(".hidden"),
                                  std::string("a b"), std::string("a,b")}) {
    json j = minimal();
    j["variants"] = json::array({{{"name", "ok"}}, {{"name", name}}});
    expect_rejected(j, {"variants[1].name", "1 to 100 of A-Z a-z 0-9"});
  }
  json j = minimal();
  j["variants"] = json::array({{{"name", "taa-clamp.none_x+2"}}});
  EXPECT_NO_THROW(ExperimentSpec::from_json(j, kFile));
}

TEST(ExperimentSpec, RejectsUnknownAaMethod) {
  json j = minimal();
  j["variants"][0]["aa"] = "fxaa";
  expect_rejected(j, {"variants[0].aa", "fxaa", "ssaa"});
}

TEST(ExperimentSpec, GlintAwareTaaKeysAreCheckedBeforeAnyWork) {
  json j = minimal();
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"reactive": 1.5}}])");
  expect_rejected(j, {"variants[0].taa.reactive", "out of range"});
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"glint_clamp": "minmax"}}])");
  expect_rejected(j, {"variants[0].taa.glint_clamp", "glint_layer"});
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"glint_layer": true, "glint_clamp": "clip"}}])");
  expect_rejected(j, {"variants[0].taa.glint_clamp", "clip", "minmax"});
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"glint_layer": true, "glint_alpha": 0}}])");
  expect_rejected(j, {"variants[0].taa.glint_alpha", "out of range"});
  j["variants"] = json::parse(
      R"([{"name": "t", "aa": "taa", "taa": {"glint_layer": true, "glint_alpha": 0.3, "glint_clamp": "minmax",
           "accumulate": true, "reactive": 0.5, "glint_lock": true}}])");
  const glintlab::core::TaaSettings t = ExperimentSpec::from_json(j, kFile).variants[0].taa;
  EXPECT_TRUE(t.on("glint_layer") && t.on("accumulate") && t.on("glint_lock"));
  EXPECT_EQ(t.option("glint_clamp"), "minmax");
  EXPECT_DOUBLE_EQ(t.value("glint_alpha"), 0.3);
  EXPECT_DOUBLE_EQ(t.value("reactive"), 0.5);
  const glintlab::core::TaaUses u = t.uses(), off = glintlab::core::TaaSettings{}.uses();
  EXPECT_TRUE(u.glint && u.state && u.history2 && !u.state2);
  EXPECT_FALSE(off.glint || off.state || off.state2 || off.history2) << "off by default";
  EXPECT_TRUE(off.motion);
}

// Falcor's TAA has no depth test, so neither has a "taa" object with no key set; its tolerance
// means nothing without it.
TEST(ExperimentSpec, TheDisocclusionTestIsOffByDefaultAndItsToleranceNeedsIt) {
  json j = minimal();
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {}}])");
  EXPECT_FALSE(ExperimentSpec::from_json(j, kFile).variants[0].taa.on("disocclusion"));
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"disocclusion_tolerance": 0.1}}])");
  expect_rejected(j, {"variants[0].taa.disocclusion_tolerance", "\"disocclusion\": true"});
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"disocclusion": true, "disocclusion_tolerance": 0}}])");
  expect_rejected(j, {"variants[0].taa.disocclusion_tolerance", "out of range"});
  j["variants"] = json::parse(R"([{"name": "t", "aa": "taa", "taa": {"disocclusion": true, "disocclusion_tolerance": 0.1}}])");
  const glintlab::core::TaaSettings t = ExperimentSpec::from_json(j, kFile).variants[0].taa;
  EXPECT_TRUE(t.on("disocclusion"));
  EXPECT_DOUBLE_EQ(t.value("disocclusion_tolerance"), 0.1);
}

TEST(ExperimentSpec, RejectsUnknownDebugOutput) {
  json j = minimal();
  j["variants"][0]["debug"] = "normals";
  expect_rejected(j, {"variants[0].debug", "normals", "sigmoid"});  // lists the allowed outputs
}

TEST(ExperimentSpec, RejectsUnknownMetric) {
  json j = minimal();
  j["metrics"] = {"psnr", "ssim"};
  expect_rejected(j, {"metrics", "ssim"});
}

TEST(ExperimentSpec, RejectsBadCameraPathName) {
  json j = minimal();
  j["camera_path"] = "no-such-path";
  expect_rejected(j, {"camera_path", "no-such-path"});
  j["camera_path"] = 7;
  expect_rejected(j, {"camera_path"});
}

TEST(ExperimentSpec, RejectsMoreFramesThanThePath) {
  json j = minimal();  // the inline path has 4 frames
  j["frames"] = 4;
  EXPECT_EQ(ExperimentSpec::from_json(j, kFile).frames, 4);
  j["frames"] = 5;
  expect_rejected(j, {"frames", "out of range"});
}

TEST(ExperimentSpec, RejectsMaterialOverrideOutOfRangeUnderVariant) {
  json j = minimal();
  j["variants"] = json::parse(R"([{"name": "a"}, {"name": "b", "material": {"SSS": 2}}])");
  expect_rejected(j, {"variants[1].material.SSS", "out of range"});
}

TEST(ExperimentSpec, LoadRejectsMalformedJsonNamingTheFile) {
  TempFile f(R"({"scene": {"mesh": {"type": "plane"}}, "variants": [ {"name": "a"} )");
  try {
    ExperimentSpec::load(f.path.string());
    ADD_FAILURE() << "malformed JSON accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(f.path.string()), std::string::npos) << e.what();
  }
}

// Found by the fuzzer (tests/fuzz/crashes/): a number beyond a double, and a
// camera-path name no file system accepts, are bad input like any other.
TEST(ExperimentSpec, FuzzFindingsAreConfigErrors) {
  for (const char* name : {"experiment-number-overflow.json", "experiment-camera-path-name-too-long.json"}) {
    const std::string path = std::string(GLINTLAB_SOURCE_DIR) + "/tests/fuzz/crashes/" + name;
    try {
      ExperimentSpec::load(path);
      ADD_FAILURE() << name << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(glintlab::resolve_experiment_path(std::string(300, 'x')), ConfigError);
}

TEST(ExperimentSpec, LoadErrorsNameTheLoadedFile) {
  json j = minimal();
  j["variants"][0]["aa"] = "fxaa";
  TempFile f(j.dump(2));
  try {
    ExperimentSpec::load(f.path.string());
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(f.path.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("variants[0].aa"), std::string::npos) << msg;
  }
}

// Keeps the shipped experiments valid: every *.json under experiments/ (recursively; camera paths
// in experiments/data/paths/ are not experiments) must load.
TEST(ExperimentSpec, EveryShippedExperimentLoads) {
  const fs::path root(GLINTLAB_EXPERIMENT_DIR);
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file() || e.path().extension() != ".json") continue;
    const fs::path rel = e.path().lexically_relative(root);
    if (!rel.empty() && *rel.begin() == "paths") continue;
    files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << "no experiments found under " << root;
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    try {
      ExperimentSpec s = ExperimentSpec::load(f.string());
      EXPECT_FALSE(s.variants.empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
  }
}

TEST(ExperimentSpec, MetricOptionsAreValidated) {
  json j = minimal();
  j["metric_options"] = {{"view", "sRGB"}};
  expect_rejected(j, {"metric_options.view", "DISPLAY/VIEW"});
  j["metric_options"] = {{"flip", "medium"}};
  expect_rejected(j, {"metric_options.flip", "\"hdr\""});
  j["metric_options"] = {{"itp_nits", -5}};
  expect_rejected(j, {"metric_options.itp_nits"});
  j["metric_options"] = {{"view", "sRGB/Standard"}, {"flip", "ldr"}, {"itp_nits", 203}};
  ExperimentSpec s = ExperimentSpec::from_json(j, kFile);
  EXPECT_EQ(s.metric_options.display_view, "sRGB/Standard");
  EXPECT_FALSE(s.metric_options.flip_hdr);
  EXPECT_EQ(s.metric_options.itp_luminance_nits, 203.0);
}

// "density_sweep": each named variant again at every value of a "glints" parameter; every derived
// material is validated before any work (a value outside the parameter's range, a parameter the
// model does not have, a variant that does not exist, values out of order).
TEST(ExperimentSpec, DensitySweepIsCheckedBeforeAnyWork) {
  json j = minimal();
  j["variants"] = json::parse(R"([{"name": "z", "material": {"glint_model": "zirr"}},
                                  {"name": "k", "material": {"glint_model": "kemppinen"}}])");
  j["density_sweep"] = json::parse(R"({"z": {"parameter": "log_density", "values": [5, 6.5, 8]},
                                       "k": {"parameter": "filter_width", "values": [0.3, 0.7]}})");
  const ExperimentSpec s = ExperimentSpec::from_json(j, kFile);
  ASSERT_EQ(s.density_sweep.methods.size(), 2u);
  EXPECT_EQ(s.density_sweep.methods[0].variant, "k");  // by name
  EXPECT_EQ(s.density_sweep.methods[0].parameter, "filter_width");
  EXPECT_EQ(s.density_sweep.methods[1].parameter, "log_density");
  EXPECT_EQ(s.density_sweep.methods[1].values, (std::vector<double>{5, 6.5, 8}));
  // the derived material keeps the variant's model and every other key, and sets only the parameter
  const json m = glintlab::density_sweep_material(s.variants[0], s.density_sweep.methods[1], 6.5);
  EXPECT_EQ(m["glint_model"], "zirr");
  EXPECT_EQ(m["glints"]["log_density"], 6.5);
  EXPECT_EQ(m.value("preset", ""), s.variants[0].material_json.value("preset", ""));
  // a [u, v] key gets the value on both axes
  glintlab::DensitySweepSpec::Method rr{"z", "relative_roughness", {0.05, 0.1}, json{{"size_variation", 0.5}}};
  const json mr = glintlab::density_sweep_material(s.variants[0], rr, 0.05);
  EXPECT_EQ(mr["glints"]["relative_roughness"], json::array({0.05, 0.05}));
  EXPECT_EQ(mr["glints"]["size_variation"], 0.5);  // the sweep's fixed keys

  auto bad = [&](const char* sweep, const std::vector<std::string>& needles) {
    json b = j;
    b["density_sweep"] = json::parse(sweep);
    expect_rejected(b, needles);
  };
  bad(R"({"z": {"parameter": "log_density", "values": [5, 99]}})", {"density_sweep.z.values", "log_density"});
  bad(R"({"nope": {"parameter": "log_density", "values": [5, 6]}})", {"density_sweep.nope", "no variant"});
  bad(R"({"z": {"parameter": "log_density", "values": [6, 5]}})", {"density_sweep.z.values", "increasing"});
  bad(R"({"z": {"parameter": "log_density", "values": [6]}})", {"density_sweep.z.values", "2 to 32"});
  bad(R"({"z": {"parameter": "log_density", "values": [5, "6"]}})", {"density_sweep.z.values"});
  bad(R"({})", {"density_sweep"});
  bad(R"({"z": [5, 6]})", {"density_sweep", "parameter"});
  bad(R"({"z": {"parameter": "no such key", "values": [5, 6]}})", {"density_sweep.z.parameter"});
  bad(R"({"z": {"parameter": "filter_width", "values": [0.5, 1]}})", {"density_sweep.z.values", "filter_width"});
  bad(R"({"z": {"parameter": "log_density", "values": [5, 6], "extra": 1}})", {"density_sweep.z", "extra"});
  bad(R"({"z": {"parameter": "log_density", "values": [5, 6], "glints": {"log_density": 6}}})",
      {"density_sweep.z.glints", "swept"});
  bad(R"({"z": {"parameter": "log_density", "values": [5, 6], "glints": {"size_variation": 9}}})",
      {"density_sweep.z.values", "size_variation"});
}

// Options that would do nothing are refused before any work, saying why: a floor target named by a
// pooled prefix without its block size, the truth's halves of a truth that has none (one sample, read
// from files, switched off, or an experiment of files only).
TEST(ExperimentSpec, OptionsThatWouldDoNothingAreRefused) {
  json j = minimal();
  j["reference"] = {{"grid", 4}, {"floor", {{"pooled_rms_", 0.1}}}};
  expect_rejected(j, {"reference.floor", "pooled_rms_", "not a metric with a noise floor", "pooled_rms_<block>"});
  j["reference"] = {{"grid", 4}, {"floor", {{"pooled_rms_8", 0.1}}}};
  EXPECT_NO_THROW(ExperimentSpec::from_json(j, kFile));
  j["reference"] = {{"grid", 1}};
  j["output"] = {{"halves", true}};
  expect_rejected(j, {"output.halves", "reference.grid 1"});
  j["reference"] = {{"grid", 2}};
  EXPECT_NO_THROW(ExperimentSpec::from_json(j, kFile));
  j["reference"] = {{"enabled", false}};
  expect_rejected(j, {"output.halves", "reference.enabled false"});
  json f = json::parse(R"({"variants": [{"name": "t", "frames": "t/"}], "reference": {"frames": "r/"},
                           "output": {"halves": true}})");
  expect_rejected(f, {"output.halves", "without \"scene\""});
}

// A copy of an experiment run from another folder (tune's trials) names its files by absolute paths,
// resolved as the spec resolves them: a model file beside the experiment, in its material and a
// variant's; the HDRI; a camera-path file; built-in names and absolute paths stay as they are.
TEST(ExperimentSpec, AbsolutePathsForACopyRunElsewhere) {
  TempFile t("{}");
  const fs::path dir = t.dir.path();
  std::ofstream(dir / "path.json") << "{}";
  json j = minimal();
  j["camera_path"] = "path.json";
  j["scene"]["sky"] = {{"hdri", "sky.exr"}};
  j["material"] = {{"glint_model", {{"file", "models/m.glsl"}}}};
  j["variants"] = json::parse(R"([{"name": "a", "material": {"glint_model": {"file": "/abs/n.glsl"}}},
                                  {"name": "b", "truth_material": {"glint_model": {"file": "../o.glsl"}}}])");
  const json a = glintlab::with_absolute_paths(j, t.path.string());
  const std::string d = fs::absolute(dir).lexically_normal().string();
  EXPECT_EQ(a["camera_path"], (fs::path(d) / "path.json").string());
  EXPECT_EQ(a["scene"]["sky"]["hdri"], (fs::path(d) / "sky.exr").string());
  EXPECT_EQ(a["material"]["glint_model"]["file"], (fs::path(d) / "models/m.glsl").string());
  EXPECT_EQ(a["variants"][0]["material"]["glint_model"]["file"], "/abs/n.glsl");
  EXPECT_EQ(a["variants"][1]["truth_material"]["glint_model"]["file"],
            (fs::path(d).parent_path() / "o.glsl").lexically_normal().string());
  j["camera_path"] = "orbit-close";  // a built-in name
  EXPECT_EQ(glintlab::with_absolute_paths(j, t.path.string())["camera_path"], "orbit-close");
}

// A model's own parameter where the material has another model: the refusal names the model that
// declares it.
TEST(ExperimentSpec, AnotherModelsParameterNamesThatModel) {
  json j = minimal();
  j["material"] = {{"glints", {{"size_variation", 0.5}}}};
  expect_rejected(j, {"material.glints.size_variation", "glint model kajs", "the glint model zirr"});
  j["material"]["glint_model"] = "zirr";
  EXPECT_NO_THROW(ExperimentSpec::from_json(j, kFile));
}

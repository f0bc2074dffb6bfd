// `glintlab stress --fast` through the code the command runs (run_stress,
// stress_json, print_stress_text), validation layers on: every case passes,
// the JSON has the documented schema, and the suite covers every group of
// extreme inputs experiments/stress/README.md lists.
#include "experiments/stress/stress.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <set>
#include <sstream>

using namespace glintlab;
using nlohmann::json;

namespace {

StressReport run_fast() {
  StressOptions o;
  o.fast = true;
  o.validation = true;
  std::ostringstream progress;
  return run_stress(o, progress);
}

bool has_name_containing(const std::vector<std::string>& names, const std::string& part) {
  return std::any_of(names.begin(), names.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

}  // namespace

// One run (every test is a process under ctest: the suite runs once).
TEST(Stress, FastSuitePassesWithValidationAndPrintsTheSchema) {
  const StressReport r = run_fast();
  ASSERT_FALSE(r.cases.empty());
  EXPECT_TRUE(r.validation);
  for (const auto& c : r.cases) {
    EXPECT_TRUE(c.pass) << c.name << ": " << c.detail;
    EXPECT_EQ(c.nonfinite, 0u) << c.name;
    EXPECT_EQ(c.negative, 0u) << c.name;
    EXPECT_GT(c.items, 0u) << c.name << " checked nothing";
    if (c.max_rel_error && c.bound) {
      EXPECT_LE(*c.max_rel_error, *c.bound) << c.name;
    }
    if (c.max_rel_error) {
      EXPECT_GT(c.compared, 0u) << c.name;
    }
  }
  EXPECT_TRUE(r.all_pass());
  EXPECT_LT(r.wall_s, 120.0) << "the fast subset should take well under 30 s on two cores";
  // the text output: one line per case and a summary with the wall time
  std::ostringstream text;
  print_stress_text(r, text);
  std::string t = text.str();
  EXPECT_EQ(size_t(std::count(t.begin(), t.end(), '\n')), r.cases.size() + 1) << t;
  EXPECT_NE(t.find("cases pass (fast subset); wall time"), std::string::npos) << t;
  // it ran exactly the fast subset, in order
  const auto fast = stress_case_names(true);
  ASSERT_EQ(r.cases.size(), fast.size());
  for (size_t i = 0; i < fast.size(); ++i) EXPECT_EQ(r.cases[i].name, fast[i]);

  // --json: exactly {"cases": [...]} with the documented keys per case
  json j = json::parse(stress_json(r).dump());  // what --json prints, parsed back
  ASSERT_TRUE(j.is_object());
  ASSERT_EQ(j.size(), 1u) << "only \"cases\" at the top level";
  ASSERT_TRUE(j.contains("cases") && j["cases"].is_array());
  ASSERT_EQ(j["cases"].size(), r.cases.size());
  std::set<std::string> names;
  for (const auto& c : j["cases"]) {
    ASSERT_TRUE(c.is_object());
    ASSERT_TRUE(c.contains("name") && c["name"].is_string()) << c.dump();
    EXPECT_TRUE(names.insert(c["name"].get<std::string>()).second) << "duplicate " << c["name"];
    ASSERT_TRUE(c.contains("nonfinite") && c["nonfinite"].is_number_unsigned()) << c.dump();
    ASSERT_TRUE(c.contains("negative") && c["negative"].is_number_unsigned()) << c.dump();
    ASSERT_TRUE(c.contains("max_rel_error") && (c["max_rel_error"].is_null() || c["max_rel_error"].is_number()))
        << c.dump();
    ASSERT_TRUE(c.contains("pass") && c["pass"].is_boolean()) << c.dump();
    // the added keys
    EXPECT_TRUE(c["bound"].is_null() || c["bound"].is_number()) << c.dump();
    EXPECT_TRUE(c["detail"].is_string()) << c.dump();
    EXPECT_TRUE(c["category"].is_string()) << c.dump();
  }
}

TEST(Stress, SuiteCoversTheIssue) {
  const auto full = stress_case_names(false), fast = stress_case_names(true);
  EXPECT_GE(full.size(), 40u);
  EXPECT_LT(fast.size(), full.size());
  EXPECT_EQ(std::set<std::string>(full.begin(), full.end()).size(), full.size()) << "case names are unique";
  for (const auto& n : fast) EXPECT_NE(std::find(full.begin(), full.end(), n), full.end()) << n;
  for (const char* part :
       {"grazing-view", "behind-surface", "camera-inside", "backlit", "normal-minus-z", "normal-plus-z",
        "object-coords-1e6", "noise-scale-1e6", "footprint-1e-9-to-1e3", "footprint-degenerate", "roughness-0-and-1",
        "glint-sigma-1e-6-to-1", "T1", "porosity", "sigmoid-a1e3-dist1e6", "binomial-n1e12", "sun-1e6",
        "palette-black", "palette-white", "zirr-density-1e-3-to-1e12", "huge-history", "motion-offscreen",
        "rgba16f", "resolution-1x1", "resolution-4096x16", "energy-zirr-vs-beckmann", "oren-nayar"})
    EXPECT_TRUE(has_name_containing(full, part)) << "no case for " << part;
  for (const char* model : {"kajs", "grains", "zirr", "beckmann"})
    EXPECT_TRUE(has_name_containing(full, std::string("grazing-view.") + model)) << model;
}

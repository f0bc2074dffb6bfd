// The regression gate: the same summary passes its own baseline; a summary
// whose flicker ratio doubled (or whose error grew, or that lost a variant or
// gained a non-finite pixel) fails; tolerances are applied in each metric's
// own sense.
#include "experiments/cli/check.h"

#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace glintlab;
using nlohmann::json;

namespace {

json summary() {
  auto stat = [](double m) { return json{{"mean", m}, {"p95", m}, {"max", m}, {"n", 5}}; };
  json v1 = {{"name", "no-aa"},
             {"metrics",
              {{"deltaE2000", stat(0.5)}, {"flip", stat(0.05)}, {"flicker_ratio", stat(2.0)},
               {"temporal_error", stat(0.003)}, {"nonfinite_pixels", stat(0)}}}};
  json v2 = {{"name", "taa"},
             {"metrics", {{"deltaE2000", stat(0.4)}, {"flicker_ratio", stat(0.8)}, {"nonfinite_pixels", stat(0)}}}};
  return {{"schema", "glintlab-summary/1"}, {"experiment", "regression"}, {"variants", {v1, v2}}};
}

size_t regressions(const std::vector<CheckRow>& rows) {
  size_t n = 0;
  for (const auto& r : rows) n += r.regression;
  return n;
}

}  // namespace

TEST(Check, SameSummaryPassesAndDoubledFlickerFails) {
  const json base = summary();
  EXPECT_EQ(regressions(check_summary(base, base, default_check_tolerances())), 0u);

  json worse = base;
  worse["variants"][0]["metrics"]["flicker_ratio"]["mean"] = 4.0;  // 2x the flicker
  auto rows = check_summary(worse, base, default_check_tolerances());
  ASSERT_EQ(regressions(rows), 1u);
  for (const auto& r : rows) {
    if (r.regression) {
      EXPECT_EQ(r.variant + "/" + r.metric, "no-aa/flicker_ratio");
    }
  }

  // Over-smoothing moves the ratio away from 1 as well: 0.8 -> 0.4 is worse.
  json smoother = base;
  smoother["variants"][1]["metrics"]["flicker_ratio"]["mean"] = 0.4;
  EXPECT_EQ(regressions(check_summary(smoother, base, default_check_tolerances())), 1u);
  // ... and moving toward 1 is an improvement, not a regression.
  json better = base;
  better["variants"][0]["metrics"]["flicker_ratio"]["mean"] = 1.5;
  better["variants"][0]["metrics"]["deltaE2000"]["mean"] = 0.3;
  EXPECT_EQ(regressions(check_summary(better, base, default_check_tolerances())), 0u);
}

TEST(Check, TolerancesMissingVariantsAndNonFinitePixels) {
  const json base = summary();
  json slightly = base;
  slightly["variants"][0]["metrics"]["deltaE2000"]["mean"] = 0.505;  // +1 %: within the default 2 %
  EXPECT_EQ(regressions(check_summary(slightly, base, default_check_tolerances())), 0u);
  auto tight = default_check_tolerances();
  tight["deltaE2000"] = 0.005;
  EXPECT_EQ(regressions(check_summary(slightly, base, tight)), 1u);

  json lost = base;
  lost["variants"].erase(1);
  EXPECT_GE(regressions(check_summary(lost, base, default_check_tolerances())), 1u);

  json nan = base;
  nan["variants"][0]["metrics"]["flip"]["mean"] = nullptr;  // a NaN frame makes the mean null
  EXPECT_EQ(regressions(check_summary(nan, base, default_check_tolerances())), 1u);

  json broken = base;
  broken["variants"][1]["metrics"]["nonfinite_pixels"]["mean"] = 0.2;
  EXPECT_EQ(regressions(check_summary(broken, base, default_check_tolerances())), 1u);

  json other = base;
  other["experiment"] = "default";
  EXPECT_THROW(check_summary(other, base, default_check_tolerances()), std::invalid_argument);
}

TEST(Check, CommandLineExitCodes) {
  const glintlab::test::TempDir tmp("check");
  const auto dir = tmp.path();
  json worse = summary();
  worse["variants"][0]["metrics"]["flicker_ratio"]["mean"] = 4.0;
  std::ofstream(dir / "base.json") << summary().dump();
  std::ofstream(dir / "worse.json") << worse.dump();
  std::ostringstream out, err;
  EXPECT_EQ(run_check((dir / "base.json").string(), (dir / "base.json").string(), {}, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("no regression"), std::string::npos) << out.str();
  std::ostringstream out2, err2;
  EXPECT_EQ(run_check((dir / "worse.json").string(), (dir / "base.json").string(), {}, out2, err2), 1);
  EXPECT_NE(out2.str().find("REGRESSION"), std::string::npos) << out2.str();
  std::ostringstream out3, err3;  // a generous tolerance lets it pass
  EXPECT_EQ(run_check((dir / "worse.json").string(), (dir / "base.json").string(), {"flicker_ratio=1.0"}, out3, err3),
            0);
  std::ostringstream out4, err4;
  EXPECT_EQ(run_check((dir / "worse.json").string(), (dir / "base.json").string(), {"flicker_ratio"}, out4, err4), 2);
  EXPECT_EQ(run_check((dir / "nope.json").string(), (dir / "base.json").string(), {}, out4, err4), 2);
}

namespace {

struct CheckRun {
  int rc;
  std::string out, err;
};

// run_check on `s` (summary) against `b` (baseline), written to files named summary.json and base.json.
CheckRun check_files(const json& s, const json& b, const std::vector<std::string>& tolerances = {}) {
  const glintlab::test::TempDir tmp("check");
  std::ofstream(tmp / "summary.json") << s.dump();
  std::ofstream(tmp / "base.json") << b.dump();
  std::ostringstream out, err;
  const int rc = run_check((tmp / "summary.json").string(), (tmp / "base.json").string(), tolerances, out, err);
  return {rc, out.str(), err.str()};
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Bad input must be exit 2 with a message naming every part given.
void expect_refused(const CheckRun& r, const std::vector<std::string>& parts) {
  EXPECT_EQ(r.rc, 2) << r.out << r.err;
  for (const auto& p : parts) EXPECT_TRUE(has(r.err, p)) << "missing \"" << p << "\" in: " << r.err;
}

}  // namespace

// A baseline whose gated mean is null or "nan" cannot gate that metric: exit 2 naming the file, the
// variant and the metric, not a pass with one check fewer (on main both pass a ΔE00 of 1000, exit 0).
TEST(Check, BaselineMeanThatCannotGateIsBadInput) {
  json awful = summary();
  awful["variants"][0]["metrics"]["deltaE2000"]["mean"] = 1000.0;
  for (const json& bad_mean : {json(nullptr), json("nan")}) {
    json base = summary();
    base["variants"][0]["metrics"]["deltaE2000"]["mean"] = bad_mean;
    expect_refused(check_files(awful, base), {"base.json", "\"no-aa\"", "\"deltaE2000\"", "a finite number >= 0"});
  }
  json not_an_entry = summary();  // on main: read as "not in the baseline", exit 0
  not_an_entry["variants"][0]["metrics"]["deltaE2000"] = 0.5;
  expect_refused(check_files(awful, not_an_entry), {"base.json", "\"deltaE2000\"", "\"mean\""});
}

// Each metric's mean must be in its declared range, in either file: a ΔE00 of -5 or a FLIP of 2 is
// refused (on main a summary ΔE00 of -5 passes, exit 0, and so does a FLIP of 2 in the baseline
// against a summary of 2.01).
TEST(Check, MeansOutOfTheirMetricsRangeAreBadInput) {
  json negative = summary();
  negative["variants"][0]["metrics"]["deltaE2000"]["mean"] = -5.0;
  expect_refused(check_files(negative, summary()), {"summary.json", "\"no-aa\"", "\"deltaE2000\"", "-5",
                                                    "a finite number >= 0"});
  json flip2 = summary(), flip201 = summary();
  flip2["variants"][0]["metrics"]["flip"]["mean"] = 2.0;
  flip201["variants"][0]["metrics"]["flip"]["mean"] = 2.01;
  expect_refused(check_files(flip201, flip2), {"\"flip\"", "a number in [0, 1]"});
  // A string in the summary is malformed input (on main: a regression, exit 1), while null there is a
  // NaN frame of the run: a regression (exit 1), as before.
  json text = summary(), null = summary();
  text["variants"][1]["metrics"]["flicker_ratio"]["mean"] = "0.8";
  expect_refused(check_files(text, summary()), {"summary.json", "\"taa\"", "\"flicker_ratio\""});
  null["variants"][1]["metrics"]["flicker_ratio"]["mean"] = nullptr;
  EXPECT_EQ(check_files(null, summary()).rc, 1);
}

// A variant named twice is ambiguous in either file (on main the summary's last copy is compared and
// the first, with ΔE00 1000, ignored: exit 0).
TEST(Check, VariantNamedTwiceIsBadInput) {
  json twice = summary();
  json first = twice["variants"][0];
  first["metrics"]["deltaE2000"]["mean"] = 1000.0;
  twice["variants"].insert(twice["variants"].begin(), first);
  expect_refused(check_files(twice, summary()), {"summary.json", "\"no-aa\" is given twice"});
  expect_refused(check_files(summary(), twice), {"base.json", "\"no-aa\" is given twice"});
}

// Schema and experiment: both files must say they are glintlab summaries of the same, named
// experiment (on main any "schema" value and two files without "experiment" pass, exit 0).
TEST(Check, SchemaAndExperimentMustMatch) {
  json tune = summary();
  tune["schema"] = "glintlab-tune/1";
  expect_refused(check_files(tune, summary()), {"summary.json", "\"schema\"", "glintlab-summary/1"});
  json bytes = summary();  // not UTF-8 (only a caller's JSON can hold that): refused, not a JSON error
  bytes["schema"] = std::string("\xff\xfe");
  EXPECT_THROW(check_summary(bytes, summary(), default_check_tolerances()), std::invalid_argument);
  json anonymous = summary();
  anonymous.erase("experiment");
  expect_refused(check_files(anonymous, anonymous), {"summary.json", "\"experiment\""});
  json other = summary();
  other["experiment"] = "default";
  expect_refused(check_files(other, summary()), {"summary.json", "base.json", "\"default\"", "\"regression\""});
}

// --tolerance takes an exact, gateable metric name and a finite decimal >= 0 with nothing after it.
// On main the first four (and the two after) are ignored or read as 0.1: exit 0.
TEST(Check, ToleranceMustNameAKnownMetricAndAPlainNumber) {
  const json s = summary();
  for (const std::string bad : {"nosuch=0.1", "DeltaE2000=0.1", "deltaE2000=0.1junk", "deltaE2000=0.1=2",
                                "pooled_bias_8=0.1", "deltaE2000= 0.1", "deltaE2000=0x1p-3"}) {
    const CheckRun r = check_files(s, s, {bad});
    expect_refused(r, {"--tolerance \"" + bad + "\"", "allowed"});
  }
  for (const std::string bad : {"deltaE2000=inf", "deltaE2000=-1", "deltaE2000=", "=0.1", "deltaE2000"})
    expect_refused(check_files(s, s, {bad}), {"--tolerance"});
  expect_refused(check_files(s, s, {"flip=0.1", "flip=0.2"}), {"flip is given twice"});
  EXPECT_TRUE(has(check_files(s, s, {"nosuch=0.1"}).err, "deltaE2000"));  // the allowed names are listed

  json worse = s;  // a tolerance given properly is applied
  worse["variants"][0]["metrics"]["deltaE2000"]["mean"] = 0.6;  // +20 %
  EXPECT_EQ(check_files(worse, s).rc, 1);
  EXPECT_EQ(check_files(worse, s, {"deltaE2000=0.25"}).rc, 0);
  EXPECT_EQ(check_files(worse, s, {"deltaE2000=1e-1"}).rc, 1);
}

// The summary line counts the checks that ran and names each skipped metric with why and for which
// variants (on main it says only "no regression in 8 checks").
TEST(Check, SummaryLineCountsChecksAndNamesSkippedMetrics) {
  const CheckRun r = check_files(summary(), summary());
  EXPECT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(has(r.out, "no regression in 8 checks")) << r.out;
  EXPECT_TRUE(has(r.out, "skipped flip (not measured in the baseline for taa)")) << r.out;
  EXPECT_TRUE(has(r.out, "skipped temporal_score (not measured in the baseline for no-aa, taa)")) << r.out;
}

// The committed baseline passes its own validation: every gated metric of every variant is checked.
TEST(Check, CommittedBaselineGatesEverything) {
  const std::string base = std::string(GLINTLAB_SOURCE_DIR) + "/results/baselines/regression.json";
  std::ostringstream out, err;
  EXPECT_EQ(run_check(base, base, {}, out, err), 0) << err.str();
  EXPECT_TRUE(has(out.str(), "no regression in 30 checks")) << out.str();
  EXPECT_TRUE(has(out.str(), "; none skipped")) << out.str();
}

// The truth's noise floor (summary.json references[].floor): a change smaller than the noise the
// baseline's truth puts into a figure is not a regression, so the allowed worsening of a metric is at
// least its floor relative to the baseline's value, and the row says so; beyond the floor the gate
// still fails. A baseline without floors keeps the tolerances as given.
TEST(Check, TheAllowedWorseningIsAtLeastTheTruthsNoiseFloor) {
  json base = summary();
  base["variants"][0]["reference"] = "reference";
  base["references"] = {{{"name", "reference"}, {"floor", {{"deltaE2000", 0.05}}}}};  // 10 % of no-aa's 0.5
  json worse = base;
  worse["variants"][0]["metrics"]["deltaE2000"]["mean"] = 0.54;  // 8 % worse: above 2 %, within the floor
  auto rows = check_summary(worse, base, default_check_tolerances());
  EXPECT_EQ(regressions(rows), 0u);
  bool raised = false;
  for (const auto& r : rows)
    if (r.variant == "no-aa" && r.metric == "deltaE2000") {
      raised = true;
      EXPECT_DOUBLE_EQ(r.tolerance, 0.1);
      EXPECT_DOUBLE_EQ(r.floor, 0.1);
    }
  EXPECT_TRUE(raised);
  worse["variants"][0]["metrics"]["deltaE2000"]["mean"] = 0.56;  // 12 %: beyond the floor
  EXPECT_EQ(regressions(check_summary(worse, base, default_check_tolerances())), 1u);
  json no_floor = base;
  no_floor.erase("references");
  worse["variants"][0]["metrics"]["deltaE2000"]["mean"] = 0.54;
  EXPECT_EQ(regressions(check_summary(worse, no_floor, default_check_tolerances())), 1u);
}

// A baseline's floors widen what the gate allows, so a floor that could not be the truth's is bad input
// (naming the reference and the metric), not a gate that lets a x2-x5 regression pass: a floor above
// every error measured against that truth, a floor on a metric that has none, one outside the metric's
// range, two truths of one name, a floor that is not a number >= 0.
TEST(Check, FloorsInTheBaselineAreValidatedAsMeansAre) {
  json base = summary();
  base["variants"][0]["reference"] = "reference";
  base["variants"][1]["reference"] = "reference";
  base["references"] = {{{"name", "reference"}, {"floor", {{"deltaE2000", 0.05}}}}};
  json worse = base;
  worse["variants"][0]["metrics"]["deltaE2000"]["mean"] = 2.5;  // x5
  ASSERT_EQ(regressions(check_summary(worse, base, default_check_tolerances())), 1u);  // the valid floor
  auto refused = [&](const json& floor, const std::vector<std::string>& needles, json refs = nullptr) {
    json b = base;
    b["references"] = refs.is_null() ? json{{{"name", "reference"}, {"floor", floor}}} : refs;
    try {
      check_summary(worse, b, default_check_tolerances());
      ADD_FAILURE() << "accepted " << b["references"].dump();
    } catch (const std::invalid_argument& e) {
      for (const auto& n : needles) EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what();
    }
  };
  refused({{"deltaE2000", 1e300}}, {"reference \"reference\"", "deltaE2000", "larger than every mean"});
  refused({{"deltaE2000", 0.6}}, {"deltaE2000", "largest is 0.5"});
  refused({{"flicker_contrast", 0.1}}, {"flicker_contrast", "no noise floor"});
  refused({{"flip", 5}}, {"flip", "[0, 1]"});
  refused({{"deltaE2000", "0.1"}}, {"deltaE2000", "\"0.1\""});
  refused({{"deltaE2000", nullptr}}, {"deltaE2000", "null"});
  refused({{"deltaE2000", json::array({0.1})}}, {"deltaE2000"});
  refused({{"deltaE2000", -0.1}}, {"deltaE2000", "at least 0"});
  refused(nullptr, {"given twice"},
          json{{{"name", "reference"}, {"floor", {{"deltaE2000", 0.05}}}},
               {{"name", "reference"}, {"floor", {{"deltaE2000", 1e300}}}}});
}

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

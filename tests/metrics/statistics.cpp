// The statistics type behind every summary aggregate: its documented rules on
// NaN, +-Inf, empty and single inputs, and nearest-rank percentiles.
#include "metrics/stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using glintlab::metrics::Statistics;

namespace {
const double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

TEST(Statistics, EmptyIsNaNEverywhere) {
  Statistics s;
  EXPECT_EQ(s.count(), 0u);
  EXPECT_TRUE(std::isnan(s.mean()));
  EXPECT_TRUE(std::isnan(s.p95()));
  EXPECT_TRUE(std::isnan(s.max()));
}

TEST(Statistics, SingleValueIsEveryAggregate) {
  Statistics s;
  s.add(2.5);
  EXPECT_EQ(s.mean(), 2.5);
  EXPECT_EQ(s.p95(), 2.5);
  EXPECT_EQ(s.max(), 2.5);
  EXPECT_EQ(s.min(), 2.5);
}

TEST(Statistics, NaNPoisonsEveryAggregateAndIsCounted) {
  Statistics s;
  for (double x : {1.0, 2.0, kNaN, 4.0}) s.add(x);
  EXPECT_EQ(s.count(), 4u);
  EXPECT_EQ(s.nan_count(), 1u);
  EXPECT_TRUE(std::isnan(s.mean()));
  EXPECT_TRUE(std::isnan(s.p95()));
  EXPECT_TRUE(std::isnan(s.max()));
}

TEST(Statistics, InfinitiesTakePartAsNumbers) {
  Statistics s;
  for (double x : {1.0, kInf, 3.0}) s.add(x);
  EXPECT_EQ(s.inf_count(), 1u);
  EXPECT_EQ(s.mean(), kInf);
  EXPECT_EQ(s.max(), kInf);
  EXPECT_EQ(s.p95(), kInf);
  EXPECT_EQ(s.min(), 1.0);
  Statistics both;
  both.add(kInf);
  both.add(-kInf);
  EXPECT_TRUE(std::isnan(both.mean()));
  EXPECT_EQ(both.max(), kInf);
  Statistics neg;
  neg.add(-kInf);
  neg.add(0.0);
  EXPECT_EQ(neg.mean(), -kInf);
}

TEST(Statistics, NearestRankPercentile) {
  Statistics s;
  for (int i = 100; i >= 1; --i) s.add(double(i));  // order of arrival must not matter
  EXPECT_EQ(s.p95(), 95.0);
  EXPECT_EQ(s.percentile(0.5), 50.0);
  EXPECT_EQ(s.percentile(1.0), 100.0);
  EXPECT_EQ(s.percentile(0.001), 1.0);
  EXPECT_DOUBLE_EQ(s.mean(), 50.5);
  Statistics small;  // n < 20: p95 is the maximum
  for (double x : {3.0, 1.0, 2.0}) small.add(x);
  EXPECT_EQ(small.p95(), 3.0);
  EXPECT_THROW(small.percentile(0.0), std::invalid_argument);
}

// One schema defines every frames.csv column with its unit: the header and
// every row come from the same list, in the same order, and summary.json takes
// its units from it.
#include "experiments/runner/output_writers.h"
#include "experiments/runner/schema.h"

#include "tests/support/csv.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace glintlab;

namespace {

FrameRecord record(int variant, int frame) {
  FrameRecord r;
  r.variant = variant;
  r.name = variant == 0 ? "no-aa" : "taa";
  r.frame = frame;
  r.time_s = frame / 30.0;
  r.spp = 1;
  r.gpu_ms = 2.5;
  r.wall_ms = 4.0;
  r.passes = {{"surface", 2.0}};
  if (variant == 1) r.passes.push_back({"taa", 0.5});
  r.scan.pixels = 100;
  r.scan.negative = 3;
  r.metrics = {{"deltaE2000", 0.25}, {"flicker_ratio", frame == 0 ? NAN : 1.5}, {"flicker_valid_px", 97}};
  return r;
}

std::vector<std::string> split(const std::string& line) { return glintlab::test::split_csv_line(line); }

}  // namespace

TEST(Schema, HeaderAndRowsComeFromOneDefinition) {
  const FrameSchema schema({"deltaE2000", "flicker_ratio", "flicker_valid_px"}, {"surface", "taa"});
  std::vector<std::string> names;
  for (const Column& c : schema.columns()) names.push_back(c.name);
  const std::vector<std::string> expected = {"variant", "frame", "time_s", "spp", "gpu_ms", "wall_ms", "gpu_ms_surface",
                                             "gpu_ms_taa", "nan_px", "inf_px", "negative_px", "nonfinite_pixels",
                                             "negative_pixels", "deltaE2000", "flicker_ratio", "flicker_valid_px",
                                             "reference_cached"};
  EXPECT_EQ(names, expected);
  for (const Column& c : schema.columns()) {  // every number names its unit
    if (c.name != "variant" && c.name != "reference_cached") {
      EXPECT_FALSE(c.unit.empty()) << c.name;
    }
  }

  const auto row = schema.row(record(0, 0));
  ASSERT_EQ(row.size(), expected.size());
  EXPECT_EQ(row[0], "no-aa");
  EXPECT_EQ(row[6], "2");        // gpu_ms_surface
  EXPECT_EQ(row[7], "");         // a pass the variant does not have
  EXPECT_EQ(row[10], "3");       // negative_px
  EXPECT_EQ(row[13], "0.25");    // deltaE2000
  EXPECT_EQ(row[14], "");        // no flicker in a sequence's first frame
  EXPECT_EQ(row[15], "97");      // counts are integers

  // The CSV writer writes exactly the schema's header and rows, sorted by
  // variant then frame whatever the arrival order, atomically.
  const glintlab::test::TempDir tmp("schema");
  const auto dir = tmp.path();
  CsvWriter csv(dir / "frames.csv", schema);
  csv.frame(record(1, 1));
  csv.frame(record(0, 1));
  csv.frame(record(1, 0));
  csv.frame(record(0, 0));
  csv.finish();
  std::ifstream in(dir / "frames.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(split(line), expected);
  std::vector<std::pair<std::string, std::string>> order;
  while (std::getline(in, line)) {
    auto cells = split(line);
    ASSERT_EQ(cells.size(), expected.size()) << line;
    order.emplace_back(cells[0], cells[1]);
  }
  EXPECT_EQ(order, (std::vector<std::pair<std::string, std::string>>{{"no-aa", "0"}, {"no-aa", "1"}, {"taa", "0"},
                                                                      {"taa", "1"}}));
}

TEST(Schema, UnitsOfDerivedNames) {
  EXPECT_EQ(unit_of("deltaE2000_max"), unit_of("deltaE2000"));
  EXPECT_EQ(unit_of("gpu_ms_taa"), "ms (GPU timestamps)");
  EXPECT_EQ(unit_of("pooled_rms_16"), "Y (block means)");
  EXPECT_EQ(csv_number(INFINITY), "inf");
  EXPECT_EQ(csv_number(NAN), "");
}

// A truth with halves gives each frame's noise floor of the metrics that have one (half the metric of
// its half B against its half A) as floor_<metric> columns after the metrics; ratios and counts have none.
TEST(Schema, FloorColumnsCarryEachFramesTruthNoise) {
  const glintlab::metrics::NamedValues halves = {
      {"deltaE2000", 0.5}, {"flicker_ratio", 1.25}, {"temporal_error_mc", NAN}, {"flicker_valid_px", 97}};
  const glintlab::metrics::NamedValues floor = glintlab::metrics::noise_floor(halves);
  ASSERT_EQ(floor.size(), 2u);
  EXPECT_EQ(floor[0].first, "deltaE2000");
  EXPECT_EQ(floor[0].second, 0.25);
  EXPECT_EQ(floor[1].first, "temporal_error_mc");
  EXPECT_TRUE(std::isnan(floor[1].second));

  const FrameSchema schema({"deltaE2000", "flicker_ratio", "flicker_valid_px"}, {"surface"},
                           {"deltaE2000", "temporal_error_mc"});
  const auto& cols = schema.columns();
  ASSERT_GE(cols.size(), 2u);
  EXPECT_EQ(cols[cols.size() - 2].name, "floor_deltaE2000");
  EXPECT_EQ(cols.back().name, "floor_temporal_error_mc");
  EXPECT_EQ(cols.back().unit, unit_of("temporal_error_mc"));
  EXPECT_FALSE(cols.back().summarised);  // pooled in summary.json references[].floor, not as a variant's metric
  FrameRecord r = record(0, 1);
  r.floor = floor;
  const auto row = schema.row(r);
  EXPECT_EQ(row[row.size() - 2], "0.25");
  EXPECT_EQ(row.back(), "");  // undefined at a sequence's start, as the metric itself
  EXPECT_EQ(schema.row(record(0, 1)).back(), "");  // a record without floors (a truth read from files)

  // The journal keeps them.
  const FrameRecord back = glintlab::frame_record_from_json(glintlab::to_json(r));
  ASSERT_EQ(back.floor.size(), 2u);
  EXPECT_EQ(back.floor[0].second, 0.25);
  EXPECT_TRUE(std::isnan(back.floor[1].second));
}

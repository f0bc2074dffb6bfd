// The one definition of what a run writes per frame and per variant: every
// column of frames.csv, with its unit, in order; summary.json takes its keys
// and units from the same list (experiments/runner/output_writers.h). Adding a
// metric to metrics/frame_metrics.h adds its column here by name; its unit
// comes from the table in schema.cpp.
#pragma once

#include "experiments/runner/records.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace glintlab {

constexpr const char* kSummarySchema = "glintlab-summary/1";
// frames.csv's column of a metric's noise floor at that frame: "floor_deltaE2000", ...
inline const std::string kFloorPrefix = "floor_";

struct Column {
  std::string name;
  std::string unit;         // "" for labels and counts without unit
  bool summarised = false;  // aggregated per variant into summary.json "metrics"
  bool integer = false;     // a count or index: written without decimals
};

class FrameSchema {
 public:
  // metric_names: FrameMetrics::names() (empty when the run does not
  // measure); pass_names: every pass of any variant (gpu_ms_<pass> columns);
  // floor_names: the metrics whose truth's noise floor the records carry
  // (floor_<metric> columns, after the metrics; empty where no truth has halves).
  FrameSchema(const std::vector<std::string>& metric_names, const std::vector<std::string>& pass_names,
              const std::vector<std::string>& floor_names = {});

  const std::vector<Column>& columns() const { return columns_; }
  // The CSV cells of a record, in column order (empty cell = no value; NaN
  // is empty too, +-Inf are "inf"/"-inf").
  std::vector<std::string> row(const FrameRecord& r) const;
  // The numeric value of column `name` for a record (NaN when absent).
  double value(const FrameRecord& r, const std::string& name) const;
  const std::vector<std::string>& pass_names() const { return passes_; }

 private:
  std::vector<Column> columns_;
  std::vector<std::string> passes_;
};

// summary.json's "metric_info" (and tune's study): for each name that has a row in the metric table
// (metrics/metric_registry.h), {"unit", "label", "direction", "group", "temporal", "floor",
// "check_tolerance" (null: not gated by default), "description"}. Names without a row are left out.
nlohmann::json metric_info_json(const std::vector<std::string>& names);

// The unit of a metric or timing name ("ms", "ΔE00", ...).
std::string unit_of(const std::string& name);

// A number for CSV: 7 significant digits, "" for NaN, "inf"/"-inf".
std::string csv_number(double x);

}  // namespace glintlab

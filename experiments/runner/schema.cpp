#include "experiments/runner/schema.h"

#include "metrics/metric_registry.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace glintlab {

namespace {

// The units of the columns that are not metrics (a metric's unit is its row's: metrics/metric_registry.h).
const std::map<std::string, std::string>& unit_table() {
  static const std::map<std::string, std::string> t = {
      {"frame", "index in the camera path"},
      {"time_s", "s"},
      {"spp", "samples per pixel"},
      {"gpu_ms", "ms (GPU timestamps)"},
      {"wall_ms", "ms (record, submit, wait, read back)"},
      {"nan_px", "pixels"},
      {"inf_px", "pixels"},
      {"negative_px", "pixels"},
      {"reference_cached", "0/1"},
  };
  return t;
}

}  // namespace

std::string unit_of(const std::string& name) {
  auto it = unit_table().find(name);
  if (it != unit_table().end()) return it->second;
  if (const metrics::MetricInfo* m = metrics::metric_info(name)) return m->unit;
  if (name.rfind("gpu_ms_", 0) == 0) return "ms (GPU timestamps)";
  if (name.rfind(kFloorPrefix, 0) == 0) return unit_of(name.substr(std::string(kFloorPrefix).size()));
  return "";
}

nlohmann::json metric_info_json(const std::vector<std::string>& names) {
  nlohmann::json out = nlohmann::json::object();
  for (const std::string& n : names)
    if (const metrics::MetricInfo* m = metrics::metric_info(n))
      out[n] = {{"unit", m->unit},
                {"label", m->label},
                {"direction", m->direction},
                {"group", m->group},
                {"temporal", m->temporal},
                {"floor", metrics::has_noise_floor(n)},
                {"check_tolerance", std::isnan(m->check_tolerance) ? nlohmann::json(nullptr)
                                                                   : nlohmann::json(m->check_tolerance)},
                {"description", m->description}};
  return out;
}

std::string csv_number(double x) {
  if (std::isnan(x)) return "";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::ostringstream o;
  o << std::setprecision(7) << x;
  return o.str();
}

FrameSchema::FrameSchema(const std::vector<std::string>& metric_names, const std::vector<std::string>& pass_names,
                         const std::vector<std::string>& floor_names)
    : passes_(pass_names) {
  auto add = [&](const std::string& n, bool summarised, bool integer) {
    columns_.push_back({n, unit_of(n), summarised, integer});
  };
  add("variant", false, false);
  add("frame", false, true);
  add("time_s", false, false);
  add("spp", false, true);
  add("gpu_ms", false, false);
  add("wall_ms", false, false);
  for (const auto& p : pass_names) add("gpu_ms_" + p, false, false);
  for (const char* n : {"nan_px", "inf_px", "negative_px"}) add(n, false, true);
  add("nonfinite_pixels", true, true);
  add("negative_pixels", true, true);
  for (const auto& m : metric_names) add(m, true, is_pixel_count(m));
  if (!metric_names.empty()) add("reference_cached", false, true);  // 1: the reference frame came from the cache
  for (const auto& m : floor_names) add(kFloorPrefix + m, false, false);  // summary.json: references[].floor
}

double FrameSchema::value(const FrameRecord& r, const std::string& name) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (name == "frame") return r.frame;
  if (name == "time_s") return r.time_s;
  if (name == "spp") return r.spp;
  if (name == "gpu_ms") return r.gpu_ms;
  if (name == "wall_ms") return r.wall_ms;
  if (name == "nan_px") return double(r.scan.nan);
  if (name == "inf_px") return double(r.scan.infinite);
  if (name == "negative_px") return double(r.scan.negative);
  if (name == "nonfinite_pixels") return double(r.scan.nan + r.scan.infinite);
  if (name == "negative_pixels") return double(r.scan.negative);
  if (name == "reference_cached") return r.reference_cached ? 1.0 : 0.0;
  if (name.rfind(kFloorPrefix, 0) == 0) {
    for (const auto& [n, v] : r.floor)
      if (kFloorPrefix + n == name) return v;
    return nan;
  }
  if (name.rfind("gpu_ms_", 0) == 0) {
    for (const auto& t : r.passes)
      if ("gpu_ms_" + t.pass == name) return t.gpu_ms;
    return nan;
  }
  for (const auto& [n, v] : r.metrics)
    if (n == name) return v;
  return nan;
}

std::vector<std::string> FrameSchema::row(const FrameRecord& r) const {
  std::vector<std::string> cells;
  cells.reserve(columns_.size());
  for (const Column& c : columns_) {
    if (c.name == "variant") {
      cells.push_back(r.name);
      continue;
    }
    const double v = value(r, c.name);
    cells.push_back(c.integer && std::isfinite(v) ? std::to_string(static_cast<long long>(v)) : csv_number(v));
  }
  return cells;
}

}  // namespace glintlab

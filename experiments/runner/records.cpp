#include "experiments/runner/records.h"

#include <cmath>
#include <limits>

namespace glintlab {

namespace {

nlohmann::json number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

double number(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  throw std::invalid_argument("journal: \"" + s + "\" is not a number");
}

nlohmann::json values(const metrics::NamedValues& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& [n, x] : v) a.push_back({n, number(x)});
  return a;
}

metrics::NamedValues values(const nlohmann::json& a) {
  metrics::NamedValues v;
  for (const auto& e : a) v.emplace_back(e.at(0).get<std::string>(), number(e.at(1)));
  return v;
}

// An integer field of a journal line: a JSON integer in [lo, hi]. Anything else (a float such as
// 6.7e32, a negative count) is not converted (no float-to-int conversion of out-of-range values): the
// line is refused (std::invalid_argument), and the journal reader drops it.
template <typename T>
T integer(const nlohmann::json& j, long long lo, long long hi) {
  bool ok = false;
  long long v = 0;
  if (j.is_number_unsigned()) {
    const auto u = j.get<unsigned long long>();
    ok = u <= static_cast<unsigned long long>(hi);  // hi > 0: then it fits a long long
    v = ok ? static_cast<long long>(u) : 0;
  } else if (j.is_number_integer()) {
    v = j.get<long long>();
    ok = true;
  }
  if (ok && v >= lo && v <= hi) return static_cast<T>(v);
  throw std::invalid_argument("journal: " + j.dump() + " is not an integer in [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "]");
}
constexpr long long kMaxIndex = 1LL << 30, kMaxCount = 1LL << 48;

}  // namespace

nlohmann::json to_json(const FrameRecord& r) {
  nlohmann::json passes = nlohmann::json::array();
  for (const auto& t : r.passes) passes.push_back({t.pass, number(t.gpu_ms)});
  nlohmann::json j = {{"type", "frame"},
          {"variant", r.variant},
          {"name", r.name},
          {"frame", r.frame},
          {"time_s", number(r.time_s)},
          {"sequence_start", r.sequence_start},
          {"spp", r.spp},
          {"gpu_ms", number(r.gpu_ms)},
          {"passes", passes},
          {"wall_ms", number(r.wall_ms)},
          {"scan", {r.scan.pixels, r.scan.nan, r.scan.pos_inf, r.scan.neg_inf, r.scan.infinite, r.scan.negative}},
          {"metrics", values(r.metrics)},
          {"metric_cost_ms", values(r.metric_cost_ms)},
          {"reference_cached", r.reference_cached}};
  if (!r.floor.empty()) j["floor"] = values(r.floor);
  return j;
}

nlohmann::json to_json(const ReferenceRecord& r) {
  nlohmann::json j = {{"type", "reference"}, {"reference", r.reference}, {"name", r.name},       {"frame", r.frame},
                      {"cached", r.cached},  {"rebuilt", r.rebuilt},     {"gpu_ms", number(r.gpu_ms)}, {"wall_ms", number(r.wall_ms)}};
  if (!r.halves_metrics.empty()) j["halves_metrics"] = values(r.halves_metrics);
  return j;
}

FrameRecord frame_record_from_json(const nlohmann::json& j) {
  FrameRecord r;
  r.variant = integer<int>(j.at("variant"), -kMaxIndex, kMaxIndex);
  r.name = j.at("name").get<std::string>();
  r.frame = integer<int>(j.at("frame"), -kMaxIndex, kMaxIndex);
  r.time_s = number(j.at("time_s"));
  r.sequence_start = j.at("sequence_start").get<bool>();
  r.spp = integer<int>(j.at("spp"), 0, kMaxIndex);
  r.gpu_ms = number(j.at("gpu_ms"));
  for (const auto& p : j.at("passes")) r.passes.push_back({p.at(0).get<std::string>(), number(p.at(1))});
  r.wall_ms = number(j.at("wall_ms"));
  const auto& s = j.at("scan");
  r.scan.pixels = integer<size_t>(s.at(0), 0, kMaxCount);
  r.scan.nan = integer<size_t>(s.at(1), 0, kMaxCount);
  r.scan.pos_inf = integer<size_t>(s.at(2), 0, kMaxCount);
  r.scan.neg_inf = integer<size_t>(s.at(3), 0, kMaxCount);
  r.scan.infinite = integer<size_t>(s.at(4), 0, kMaxCount);
  r.scan.negative = integer<size_t>(s.at(5), 0, kMaxCount);
  r.metrics = values(j.at("metrics"));
  r.metric_cost_ms = values(j.at("metric_cost_ms"));
  r.reference_cached = j.at("reference_cached").get<bool>();
  if (j.contains("floor")) r.floor = values(j.at("floor"));
  return r;
}

ReferenceRecord reference_record_from_json(const nlohmann::json& j) {
  ReferenceRecord r;
  r.reference = integer<int>(j.at("reference"), -kMaxIndex, kMaxIndex);
  r.name = j.at("name").get<std::string>();
  r.frame = integer<int>(j.at("frame"), -kMaxIndex, kMaxIndex);
  r.cached = j.at("cached").get<bool>();
  r.rebuilt = j.at("rebuilt").get<bool>();
  r.gpu_ms = number(j.at("gpu_ms"));
  r.wall_ms = number(j.at("wall_ms"));
  if (j.contains("halves_metrics")) r.halves_metrics = values(j.at("halves_metrics"));
  return r;
}

}  // namespace glintlab

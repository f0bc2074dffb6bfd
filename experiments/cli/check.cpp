#include "experiments/cli/check.h"

#include "core/util/json_check.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/schema.h"
#include "metrics/metric_registry.h"

#include <charconv>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <set>

namespace glintlab {

namespace {

enum class Sense { Lower, Higher, NearOne, Zero };

Sense sense_of(const std::string& m) {
  if (m == "flicker_ratio" || m == "frame_diff_ratio") return Sense::NearOne;
  if (m == "psnr") return Sense::Higher;
  if (m == "nonfinite_pixels" || m == "negative_pixels") return Sense::Zero;
  return Sense::Lower;
}

// A metric the gate can be asked to guard: declared (metrics/metric_registry.h) with a sense of worse;
// pooled_bias_<s> is signed (no direction is worse), psnr is the one signed metric with one.
bool gateable(const std::string& m) {
  const auto range = metrics::value_range(m);
  return range && (range->lo >= 0 || m == "psnr");
}

[[noreturn]] void bad(const std::string& file, const std::string& what) {
  throw std::invalid_argument(file + ": " + what);
}

// The noise floor of metric m of the truth the baseline's variant `v` was measured against
// (summary.json references[].floor; 0 where the baseline has none).
double floor_of(const nlohmann::json& baseline, const nlohmann::json& v, const std::string& m) {
  const auto refs = baseline.find("references");
  if (refs == baseline.end() || !refs->is_array() || !v.contains("reference")) return 0;
  for (const auto& r : *refs)
    if (r.is_object() && r.value("name", nlohmann::json()) == v["reference"] && r.contains("floor") &&
        r["floor"].is_object() && r["floor"].contains(m) && r["floor"][m].is_number()) {
      const double f = r["floor"][m].get<double>();
      return std::isfinite(f) && f > 0 ? f : 0;
    }
  return 0;
}

// The mean of metric m of a validated variant entry: absent (nullopt), null (NaN) or a number.
std::optional<double> mean_of(const nlohmann::json& variant, const std::string& m) {
  const auto& metrics = variant["metrics"];
  const auto entry = metrics.find(m);
  if (entry == metrics.end()) return std::nullopt;
  const auto& mean = (*entry)["mean"];
  return mean.is_null() ? std::numeric_limits<double>::quiet_NaN() : mean.get<double>();
}

// A baseline's floors widen what the gate allows, so they are validated as means are: "references" an
// array of objects with unique names; each "floor" an object of metrics that have a noise floor, each a
// finite number >= 0 in the metric's range and no larger than the largest mean of that metric among the
// variants measured against that truth (the truth's own noise is part of every such error). Throws
// std::invalid_argument naming `file`, the reference and the metric.
void validate_floors(const nlohmann::json& j, const std::string& file) {
  const auto refs = j.find("references");
  if (refs == j.end()) return;
  if (!refs->is_array()) bad(file, "\"references\" must be an array of the truths");
  std::set<std::string> names;
  for (const auto& r : *refs) {
    if (!r.is_object() || !r.contains("name") || !r["name"].is_string())
      bad(file, "every entry of \"references\" must be an object with a string \"name\"");
    const std::string name = r["name"];
    if (!names.insert(name).second)
      bad(file, "reference \"" + name + "\" is given twice; reference names must be unique (a floor is a truth's)");
    if (!r.contains("floor")) continue;
    if (!r["floor"].is_object()) bad(file, "reference \"" + name + "\": \"floor\" must be an object of metric -> number");
    for (const auto& [metric, f] : r["floor"].items()) {
      const std::string where = "reference \"" + name + "\", floor of \"" + metric + "\": ";
      if (!metrics::has_noise_floor(metric)) bad(file, where + metric + " has no noise floor (no floor is allowed)");
      const auto range = metrics::value_range(metric);
      if (!f.is_number() || !std::isfinite(f.get<double>()) || f.get<double>() < 0 ||
          (range && !range->contains(f.get<double>())))
        bad(file, where + dump_json(f) + "; allowed: " + (range ? range->allowed : std::string("a number")) +
                      ", at least 0");
      double largest = -1;  // the largest mean of the metric among the variants measured against this truth
      for (const auto& v : j["variants"])
        if (v.value("reference", nlohmann::json()) == name && v["metrics"].contains(metric) &&
            v["metrics"][metric]["mean"].is_number())
          largest = std::max(largest, v["metrics"][metric]["mean"].get<double>());
      if (largest >= 0 && f.get<double>() > largest)
        bad(file, where + dump_json(f) + " is larger than every mean of " + metric + " measured against it (the " +
                      "largest is " + dump_json(largest) + "): a truth's noise cannot exceed the errors it is part of");
    }
  }
}

// Throws std::invalid_argument naming `file` unless `j` is a glintlab summary whose every variant has a
// unique name and whose every metric mean is null or a number in its declared range. In a baseline, a
// metric that `tolerances` gates must have a finite mean where it is present: null cannot gate.
void validate_summary(const nlohmann::json& j, const std::string& file, bool baseline,
                      const std::map<std::string, double>& tolerances) {
  if (!j.is_object()) bad(file, "not a glintlab summary.json (not a JSON object)");
  const auto schema = j.find("schema");
  if (schema == j.end() || !schema->is_string() || *schema != kSummarySchema)
    bad(file, "\"schema\" is " + (schema == j.end() ? std::string("missing") : dump_json(*schema)) + "; allowed: \"" +
                  kSummarySchema + "\" (a summary.json of `run` or `measure`)");
  const auto experiment = j.find("experiment");
  if (experiment == j.end() || !experiment->is_string())
    bad(file, "\"experiment\" must be the experiment's name (a string)");
  const auto variants = j.find("variants");
  if (variants == j.end() || !variants->is_array()) bad(file, "\"variants\" must be an array of variants");
  std::set<std::string> names;
  for (const auto& v : *variants) {
    if (!v.is_object() || !v.contains("name") || !v["name"].is_string() || v["name"].get<std::string>().empty())
      bad(file, "every entry of \"variants\" must be an object with a non-empty string \"name\"");
    const std::string name = v["name"];
    if (!names.insert(name).second)
      bad(file, "variant \"" + name + "\" is given twice; variant names must be unique");
    if (!v.contains("metrics") || !v["metrics"].is_object())
      bad(file, "variant \"" + name + "\": \"metrics\" must be an object of metric -> {\"mean\", ...}");
    for (const auto& [metric, entry] : v["metrics"].items()) {
      const std::string where = "variant \"" + name + "\", metric \"" + metric + "\": ";
      const auto range = metrics::value_range(metric);
      const std::string allowed = range ? range->allowed : "a number";
      if (!entry.is_object() || !entry.contains("mean"))
        bad(file, where + "must be an object with a \"mean\"");
      const auto& mean = entry["mean"];
      const bool gated = baseline && tolerances.count(metric);
      if (mean.is_null() && gated)
        bad(file, where + "\"mean\" is null (a NaN or infinite frame), so this baseline cannot gate " + metric +
                      "; allowed: " + allowed + " (measure the baseline again)");
      if (mean.is_null()) continue;
      if (!mean.is_number() || !std::isfinite(mean.get<double>()) || (range && !range->contains(mean.get<double>())))
        bad(file, where + "\"mean\" is " + dump_json(mean) + "; allowed: " + allowed + (gated ? "" : " or null"));
    }
  }
  if (baseline) validate_floors(j, file);
}

}  // namespace

const std::map<std::string, double>& default_check_tolerances() {
  static const std::map<std::string, double> t = [] {
    std::map<std::string, double> out;  // each metric row's default (metrics/metric_registry.h)
    for (const metrics::MetricInfo& m : metrics::metric_table())
      if (!std::isnan(m.check_tolerance)) out[m.name] = m.check_tolerance;
    return out;
  }();
  return t;
}

std::map<std::string, double> parse_check_tolerances(const std::vector<std::string>& args) {
  std::map<std::string, double> tol = default_check_tolerances();
  std::set<std::string> given;
  for (const auto& a : args) {
    const auto eq = a.find('=');
    const std::string metric = a.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : a.substr(eq + 1);
    const std::string got = "--tolerance \"" + a + "\": ";
    if (eq == std::string::npos || metric.empty())
      throw std::invalid_argument(got + "expected metric=x (e.g. flicker_ratio=0.05)");
    if (!gateable(metric)) {
      std::string known;
      for (const auto& [m, x] : default_check_tolerances()) known += (known.empty() ? "" : ", ") + m;
      throw std::invalid_argument(got + "\"" + metric + "\" is not a metric the gate can guard (names are exact, " +
                                  "case included); allowed: " + known +
                                  ", or another metric of summary.json except pooled_bias_<s>");
    }
    double x = 0;
    const char* end = value.data() + value.size();
    const auto [ptr, ec] = std::from_chars(value.data(), end, x);
    if (value.empty() || ec != std::errc() || ptr != end || !std::isfinite(x) || x < 0)
      throw std::invalid_argument(got + "the tolerance \"" + value + "\" is not allowed; allowed: a finite " +
                                  "decimal number >= 0 and nothing after it (e.g. " + metric + "=0.05)");
    if (!given.insert(metric).second) throw std::invalid_argument(got + metric + " is given twice");
    tol[metric] = x;
  }
  return tol;
}

std::vector<CheckRow> check_summary(const nlohmann::json& summary, const nlohmann::json& baseline,
                                    const std::map<std::string, double>& tolerances, const std::string& summary_file,
                                    const std::string& baseline_file) {
  validate_summary(summary, summary_file, false, tolerances);
  validate_summary(baseline, baseline_file, true, tolerances);
  if (summary["experiment"] != baseline["experiment"])
    throw std::invalid_argument(summary_file + " is of experiment " + dump_json(summary["experiment"]) + " but " +
                                baseline_file + " of " + dump_json(baseline["experiment"]) +
                                "; a summary is checked against the baseline of its own experiment");
  std::vector<CheckRow> rows;
  for (const auto& bv : baseline["variants"]) {
    const std::string name = bv["name"];
    const nlohmann::json* sv = nullptr;
    for (const auto& v : summary["variants"])
      if (v["name"] == name) sv = &v;
    for (const auto& [metric, tol] : tolerances) {
      CheckRow r;
      r.variant = name;
      r.metric = metric;
      r.tolerance = tol;
      const std::optional<double> base = mean_of(bv, metric);
      if (!base) {
        r.skipped = true;
        r.note = "not measured in the baseline";
        rows.push_back(r);
        continue;
      }
      r.baseline = *base;
      if (!sv) {
        r.regression = true;
        r.note = "variant missing from the summary";
        rows.push_back(r);
        continue;
      }
      r.current = mean_of(*sv, metric).value_or(std::numeric_limits<double>::quiet_NaN());
      if (std::isnan(r.current)) {
        r.regression = true;
        r.note = "missing or not finite in the summary";
        rows.push_back(r);
        continue;
      }
      switch (sense_of(metric)) {
        case Sense::Lower:
          r.change = (r.current - r.baseline) / std::max(std::abs(r.baseline), 1e-12);
          // A change the truth's own noise could make is not a regression: the tolerance is at least
          // the baseline truth's noise floor of the metric (stated in the output).
          if (const double f = floor_of(baseline, bv, metric) / std::max(std::abs(r.baseline), 1e-12); f > r.tolerance) {
            r.tolerance = f;
            r.floor = f;
          }
          break;
        case Sense::Higher:
          r.change = (r.baseline - r.current) / std::max(std::abs(r.baseline), 1e-12);
          break;
        case Sense::NearOne:
          r.change = (r.current > 0 && r.baseline > 0)
                         ? std::abs(std::log(r.current)) - std::abs(std::log(r.baseline))
                         : std::numeric_limits<double>::infinity();
          break;
        case Sense::Zero:
          r.change = r.current - r.baseline;
          break;
      }
      r.regression = r.change > r.tolerance;
      rows.push_back(r);
    }
  }
  return rows;
}

static int check_command(const std::string& summary_path, const std::string& baseline_path,
                         const std::vector<std::string>& tolerance_args, std::ostream& out) {
  // Bad input throws: run_check's run_guarded says it and returns 2.
  const std::map<std::string, double> tol = parse_check_tolerances(tolerance_args);
  const nlohmann::json summary = read_json_file(summary_path);
  const nlohmann::json baseline = read_json_file(baseline_path);
  std::vector<CheckRow> rows;
  try {
    rows = check_summary(summary, baseline, tol, summary_path, baseline_path);
  } catch (const std::invalid_argument& e) {  // which command the message is from
    throw ConfigError(std::string("check: ") + e.what());
  }
  size_t regressions = 0, checks = 0;
  std::map<std::string, std::vector<std::string>> skipped;  // metric -> variants whose baseline lacks it
  out << std::left << std::setw(18) << "variant" << std::setw(20) << "metric" << std::right << std::setw(12)
      << "baseline" << std::setw(12) << "current" << std::setw(10) << "worse by" << std::setw(10) << "allowed"
      << "  status\n";
  for (const CheckRow& r : rows) {
    if (r.skipped) {
      skipped[r.metric].push_back(r.variant);
      continue;
    }
    ++checks;
    regressions += r.regression;
    out << std::left << std::setw(18) << r.variant << std::setw(20) << r.metric << std::right << std::setprecision(5)
        << std::setw(12) << r.baseline << std::setw(12) << (r.note.empty() ? r.current : NAN) << std::setw(10)
        << std::setprecision(3) << (r.note.empty() ? r.change : NAN) << std::setw(10) << r.tolerance << "  "
        << (r.regression ? "REGRESSION" : "ok") << (r.note.empty() ? "" : " (" + r.note + ")")
        << (r.floor > 0 ? " (allowed raised to the truth's noise floor)" : "") << "\n";
  }
  out << (regressions ? std::to_string(regressions) + " regression(s)" : std::string("no regression")) << " in "
      << checks << " checks against " << baseline_path;
  if (skipped.empty()) out << "; none skipped";
  for (const auto& [metric, variants] : skipped) {
    out << "; skipped " << metric << " (not measured in the baseline for ";
    for (size_t i = 0; i < variants.size(); ++i) out << (i ? ", " : "") << variants[i];
    out << ")";
  }
  out << "\n";
  return regressions ? kExitDefect : kExitOk;
}

int run_check(const std::string& summary_path, const std::string& baseline_path,
              const std::vector<std::string>& tolerance_args, std::ostream& out, std::ostream& err) {
  return run_guarded([&] { return check_command(summary_path, baseline_path, tolerance_args, out); }, err);
}

void add_check_command(CLI::App& app, int& exit_code) {
  auto summary = std::make_shared<std::string>(), baseline = std::make_shared<std::string>();
  auto tolerances = std::make_shared<std::vector<std::string>>();
  CLI::App* c = app.add_subcommand("check", "compare a run's summary.json with a baseline; exit 1 on a regression");
  c->add_option("summary", *summary, "summary.json of the run")->required();
  c->add_option("baseline", *baseline, "baseline summary.json (e.g. results/baselines/<experiment>.json)")->required();
  c->add_option("--tolerance", *tolerances, "metric=x: allowed worsening (relative; |log| for ratios); repeatable");
  c->callback([=, &exit_code] {
    exit_code = run_guarded([&] { return run_check(*summary, *baseline, *tolerances, std::cout, std::cerr); },
                            std::cerr);
  });
}

}  // namespace glintlab

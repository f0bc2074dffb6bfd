#include "experiments/cli/check.h"

#include "core/util/json_check.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"

#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>

namespace glintlab {

namespace {

enum class Sense { Lower, Higher, NearOne, Zero };

Sense sense_of(const std::string& m) {
  if (m == "flicker_ratio" || m == "frame_diff_ratio") return Sense::NearOne;
  if (m == "psnr") return Sense::Higher;
  if (m == "nonfinite_pixels" || m == "negative_pixels") return Sense::Zero;
  return Sense::Lower;
}

// The mean of metric m of a summary's variant entry; NaN when any level is missing or of another type
// (a summary is input: nothing here may assume its shape).
double mean_of(const nlohmann::json& v, const std::string& m) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!v.is_object()) return nan;
  const auto metrics = v.find("metrics");
  if (metrics == v.end() || !metrics->is_object()) return nan;
  const auto entry = metrics->find(m);
  if (entry == metrics->end() || !entry->is_object()) return nan;
  const auto mean = entry->find("mean");
  return mean != entry->end() && mean->is_number() ? mean->get<double>() : nan;
}

void require_summary(const nlohmann::json& j, const char* what) {
  if (!j.is_object() || !j.contains("schema") || !j.contains("variants") || !j["variants"].is_array())
    throw std::invalid_argument(std::string(what) + " is not a glintlab summary.json (no \"schema\"/\"variants\")");
}

}  // namespace

const std::map<std::string, double>& default_check_tolerances() {
  static const std::map<std::string, double> t = {
      {"deltaE2000", 0.02},        {"flip", 0.02},          {"flicker_ratio", 0.02}, {"temporal_error", 0.02},
      {"temporal_error_mc", 0.02}, {"pooled_error", 0.05},  {"nonfinite_pixels", 0.0},
      {"negative_pixels", 0.0},   {"flicker_contrast", 0.02},
      {"flicker_excess", 0.05},    {"temporal_lag", 0.05}};
  return t;
}

std::vector<CheckRow> check_summary(const nlohmann::json& summary, const nlohmann::json& baseline,
                                    const std::map<std::string, double>& tolerances) {
  require_summary(summary, "the summary");
  require_summary(baseline, "the baseline");
  if (summary.value("experiment", "") != baseline.value("experiment", ""))
    throw std::invalid_argument("the summary is of experiment \"" + summary.value("experiment", "") +
                                "\" but the baseline of \"" + baseline.value("experiment", "") + "\"");
  std::vector<CheckRow> rows;
  for (const auto& bv : baseline["variants"]) {
    const std::string name = bv.value("name", "");
    const nlohmann::json* sv = nullptr;
    for (const auto& v : summary["variants"])
      if (v.value("name", "") == name) sv = &v;
    for (const auto& [metric, tol] : tolerances) {
      CheckRow r;
      r.variant = name;
      r.metric = metric;
      r.tolerance = tol;
      r.baseline = mean_of(bv, metric);
      if (std::isnan(r.baseline)) continue;  // not in the baseline: nothing to guard
      if (!sv) {
        r.regression = true;
        r.note = "variant missing from the summary";
        rows.push_back(r);
        continue;
      }
      r.current = mean_of(*sv, metric);
      if (std::isnan(r.current)) {
        r.regression = true;
        r.note = "missing or not finite in the summary";
        rows.push_back(r);
        continue;
      }
      switch (sense_of(metric)) {
        case Sense::Lower:
          r.change = (r.current - r.baseline) / std::max(std::abs(r.baseline), 1e-12);
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

int run_check(const std::string& summary_path, const std::string& baseline_path,
              const std::vector<std::string>& tolerance_args, std::ostream& out, std::ostream& err) {
  std::map<std::string, double> tol = default_check_tolerances();
  for (const auto& a : tolerance_args) {
    const auto eq = a.find('=');
    double x = std::numeric_limits<double>::quiet_NaN();
    if (eq != std::string::npos) {
      try {
        x = std::stod(a.substr(eq + 1));
      } catch (const std::exception&) {
      }
    }
    if (eq == std::string::npos || eq == 0 || !(x >= 0.0) || !std::isfinite(x)) {
      err << "error: --tolerance: expected metric=x with x >= 0 (e.g. flicker_ratio=0.05), got \"" << a << "\"\n";
      return kExitBadInput;
    }
    tol[a.substr(0, eq)] = x;
  }
  nlohmann::json summary, baseline;
  std::vector<CheckRow> rows;
  try {
    summary = read_json_file(summary_path);
    baseline = read_json_file(baseline_path);
    rows = check_summary(summary, baseline, tol);
  } catch (const ConfigError& e) {
    err << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    err << "error: " << summary_path << " vs " << baseline_path << ": " << e.what() << "\n";
    return kExitBadInput;
  } catch (const nlohmann::json::exception& e) {  // a field of the wrong type
    err << "error: " << summary_path << " vs " << baseline_path << ": not glintlab summaries of the schema "
        << "glintlab-summary/1 (" << e.what() << ")\n";
    return kExitBadInput;
  }
  size_t regressions = 0;
  out << std::left << std::setw(18) << "variant" << std::setw(20) << "metric" << std::right << std::setw(12)
      << "baseline" << std::setw(12) << "current" << std::setw(10) << "worse by" << std::setw(10) << "allowed"
      << "  status\n";
  for (const CheckRow& r : rows) {
    regressions += r.regression;
    out << std::left << std::setw(18) << r.variant << std::setw(20) << r.metric << std::right << std::setprecision(5)
        << std::setw(12) << r.baseline << std::setw(12) << (r.note.empty() ? r.current : NAN) << std::setw(10)
        << std::setprecision(3) << (r.note.empty() ? r.change : NAN) << std::setw(10) << r.tolerance << "  "
        << (r.regression ? "REGRESSION" : "ok") << (r.note.empty() ? "" : " (" + r.note + ")") << "\n";
  }
  out << (regressions ? std::to_string(regressions) + " regression(s)" : std::string("no regression")) << " in "
      << rows.size() << " checks against " << baseline_path << "\n";
  return regressions ? kExitDefect : kExitOk;
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

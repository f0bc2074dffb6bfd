#include "experiments/runner/density_sweep.h"

#include "core/util/json_check.h"
#include "experiments/cli/exit_codes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kMatchedBound = std::log(1.25);  // |ln ratio| a matched row may keep

// The metrics a row holds (means over the frames), besides the ratio made of two of them.
const char* const kRowMetrics[] = {"glint_density_test", "glint_density_ref", "temporal_score", "flicker_excess",
                                   "temporal_lag", "temporal_error_mc", "deltaE2000"};

double mean_of(const nlohmann::json& stats) {
  return stats.is_object() && stats.contains("mean") && stats["mean"].is_number() ? stats["mean"].get<double>() : kNaN;
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

// A variant's row of a sub-run's summary: the parameter, its value, the metrics' means and the ratio of
// the two glint densities' means (the registry's glint_density_ratio).
nlohmann::json row_of(const nlohmann::json& variant, const std::string& parameter, double value) {
  nlohmann::json row = {{"parameter", parameter}, {"value", value}};
  const nlohmann::json& m = variant.value("metrics", nlohmann::json::object());
  for (const char* name : kRowMetrics) row[name] = number_or_null(m.contains(name) ? mean_of(m[name]) : kNaN);
  const double t = row["glint_density_test"].is_number() ? row["glint_density_test"].get<double>() : kNaN;
  const double r = row["glint_density_ref"].is_number() ? row["glint_density_ref"].get<double>() : kNaN;
  row["glint_density_ratio"] = number_or_null(r > 0 ? t / r : kNaN);
  row["gpu_ms"] = number_or_null(mean_of(variant.value("gpu_ms", nlohmann::json())));
  return row;
}

double ln_ratio(const nlohmann::json& row) {
  const nlohmann::json& r = row["glint_density_ratio"];
  return r.is_number() && r.get<double>() > 0 ? std::log(r.get<double>()) : kNaN;
}

std::string value_text(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

// The experiment's JSON with `variants` as its variants, and no sweep of its own.
nlohmann::json sub_source(const nlohmann::json& source, nlohmann::json variants) {
  nlohmann::json s = source;
  s.erase("density_sweep");
  s["variants"] = std::move(variants);
  return s;
}

// The variant `name` of `source` at `value` of the sweep's parameter, named `as`.
nlohmann::json derived_variant(const nlohmann::json& source, const ExperimentSpec& spec,
                               const DensitySweepSpec::Method& m, double value, const std::string& as) {
  const std::string& name = m.variant;
  nlohmann::json v;
  for (const auto& x : source.at("variants"))
    if (x.value("name", "") == name) v = x;
  const auto it = std::find_if(spec.variants.begin(), spec.variants.end(),
                               [&](const VariantSpec& s) { return s.name == name; });
  v["name"] = as;
  v["material"] = density_sweep_material(*it, m, value);
  v["truth_material"] = it->truth_material ? it->truth_material_json : it->material_json;  // the run's own truth
  return v;
}

// Runs `variants` of the experiment into `dir` (no images, no report) and returns its summary.json's
// variants by name, or an exit code in *status.
std::map<std::string, nlohmann::json> run_sub(const RunOptions& opt, const nlohmann::json& source,
                                              nlohmann::json variants, const fs::path& dir, std::ostream& log,
                                              int* status) {
  RunOptions o = opt;
  o.source = sub_source(source, std::move(variants));
  o.out_dir = dir.string();
  o.variants.clear();
  o.report = false;
  o.images = false;
  o.density_sweep = false;
  o.resume = opt.resume && fs::exists(dir / "records.jsonl");
  *status = run_experiment(o, log);
  std::map<std::string, nlohmann::json> out;
  if (*status != kExitOk && *status != kExitDefect) return out;  // a defect is counted in its frames.csv
  *status = kExitOk;
  const nlohmann::json summary = read_json_file((dir / "summary.json").string());
  for (const auto& v : summary.at("variants")) out[v.at("name").get<std::string>()] = v;
  return out;
}

// The measured point whose ratio is nearest to 1, or nullptr.
const SweepPoint* nearest_to_one(const std::vector<SweepPoint>& points) {
  const SweepPoint* best = nullptr;
  for (const SweepPoint& p : points)
    if (std::isfinite(p.ln_ratio) && (!best || std::fabs(p.ln_ratio) < std::fabs(best->ln_ratio))) best = &p;
  return best;
}

}  // namespace

double matched_value(std::vector<SweepPoint> points, bool* bracketed) {
  points.erase(std::remove_if(points.begin(), points.end(), [](const SweepPoint& p) { return !std::isfinite(p.ln_ratio); }),
               points.end());
  std::sort(points.begin(), points.end(), [](const SweepPoint& a, const SweepPoint& b) { return a.value < b.value; });
  *bracketed = false;
  if (points.size() < 2) return kNaN;
  auto line = [](const SweepPoint& a, const SweepPoint& b) {  // where the line through a and b crosses 0
    return a.value - a.ln_ratio * (b.value - a.value) / (b.ln_ratio - a.ln_ratio);
  };
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const SweepPoint &a = points[i], &b = points[i + 1];
    if (a.ln_ratio == 0) {
      *bracketed = true;
      return a.value;
    }
    if ((a.ln_ratio < 0) != (b.ln_ratio < 0) || b.ln_ratio == 0) {
      *bracketed = true;
      return line(a, b);
    }
  }
  // No crossing: every point is on one side. Where the point nearest to 0 is an end, extrapolate that
  // end's pair; where it is inside, the ratio turns back before reaching 1: no value matches.
  size_t best = 0;
  for (size_t i = 1; i < points.size(); ++i)
    if (std::fabs(points[i].ln_ratio) < std::fabs(points[best].ln_ratio)) best = i;
  if (best != 0 && best != points.size() - 1) return kNaN;
  const bool low = best == 0;
  const SweepPoint a = low ? points[0] : points[points.size() - 2], b = low ? points[1] : points.back();
  if (!(a.ln_ratio != b.ln_ratio)) return kNaN;
  const double x = line(a, b), step = b.value - a.value;
  if (!((low ? x < a.value : x > b.value))) return kNaN;  // the end pair leads away from 1
  return low ? std::max(x, a.value - 2 * step) : std::min(x, b.value + 2 * step);
}

int run_density_sweep(const RunOptions& opt, const nlohmann::json& source, const ExperimentSpec& spec,
                      std::ostream& log, nlohmann::json* summary_extra) {
  const fs::path root(opt.out_dir);
  nlohmann::json sweep = nlohmann::json::object(), matched = nlohmann::json::object();
  std::map<std::string, std::vector<SweepPoint>> points;
  std::map<std::string, const DensitySweepSpec::Method*> method;  // the swept variants this run has
                                                                   // (--variants may leave some out)
  for (const auto& m : spec.density_sweep.methods) {
    if (std::none_of(spec.variants.begin(), spec.variants.end(), [&](const VariantSpec& v) { return v.name == m.variant; }))
      continue;
    method[m.variant] = &m;
    nlohmann::json variants = nlohmann::json::array();
    std::vector<std::string> names;
    for (double x : m.values) {
      names.push_back(m.variant + "." + m.parameter + "_" + value_text(x));
      variants.push_back(derived_variant(source, spec, m, x, names.back()));
    }
    log << "density sweep: " << m.variant << " at " << m.values.size() << " values of " << m.parameter << "\n";
    int status = kExitOk;
    auto rows = run_sub(opt, source, variants, root / "density-sweep" / m.variant, log, &status);
    if (status != kExitOk) return status;
    sweep[m.variant] = nlohmann::json::array();
    for (size_t i = 0; i < m.values.size(); ++i) {
      nlohmann::json row = row_of(rows.at(names[i]), m.parameter, m.values[i]);
      if (!m.glints.empty()) row["glints"] = m.glints;
      sweep[m.variant].push_back(row);
      points[m.variant].push_back({m.values[i], ln_ratio(row)});
    }
  }
  std::vector<std::string> open;  // not yet matched
  for (const auto& [name, m] : method) open.push_back(name);
  for (int round = 1; round <= kMatchRounds && !open.empty(); ++round) {
    nlohmann::json variants = nlohmann::json::array();
    std::map<std::string, std::pair<double, std::string>> at;  // the value and how it was chosen
    for (const auto& name : open) {
      bool bracketed = false;
      double x = matched_value(points[name], &bracketed);
      const VariantSpec& v = *std::find_if(spec.variants.begin(), spec.variants.end(),
                                           [&](const VariantSpec& s) { return s.name == name; });
      std::string problem = std::isfinite(x) ? density_sweep_problem(spec, v, *method[name], x) : "";
      const SweepPoint* best = nearest_to_one(points[name]);
      std::string how = bracketed ? "interpolated" : "extrapolated";
      if (!std::isfinite(x) || !problem.empty()) {  // nothing to interpolate: the point nearest to 1, if close
        if (best && std::fabs(best->ln_ratio) <= kMatchedBound) {
          x = best->value;
          how = "nearest";
          problem.clear();
        }
      }
      if (!std::isfinite(x) || !problem.empty()) {
        std::string why = "no value of " + method[name]->parameter + " swept reaches glint density ratio 1 or leads to it";
        if (best)
          why += " (the nearest, " + value_text(std::exp(best->ln_ratio)) + ", at " + value_text(best->value) + ")";
        if (!problem.empty()) why += "; the line through the end values leads outside the range: " + problem;
        log << "warning: density sweep: " << name << ": not matched: " << why << "\n";
        matched[name] = {{"parameter", method[name]->parameter}, {"value", nullptr}, {"rounds", round - 1},
                         {"how", "not matched"}, {"reason", why}};
        if (best) {
          matched[name]["nearest_value"] = best->value;
          matched[name]["nearest_ratio"] = std::exp(best->ln_ratio);
        }
        continue;
      }
      at[name] = {x, how};
      variants.push_back(derived_variant(source, spec, *method[name], x, name + ".matched"));
    }
    if (variants.empty()) break;
    log << "density sweep: matched density, round " << round << "\n";
    int status = kExitOk;
    auto rows = run_sub(opt, source, variants, root / "matched-density" / ("round-" + std::to_string(round)), log,
                        &status);
    if (status != kExitOk) return status;
    std::vector<std::string> still;
    for (const auto& [name, xb] : at) {
      const double x = xb.first;  // a copy: C++17 lambdas may not capture a structured binding (clang)
      nlohmann::json row = row_of(rows.at(name + ".matched"), method[name]->parameter, x);
      if (!method[name]->glints.empty()) row["glints"] = method[name]->glints;
      row["rounds"] = round;
      row["how"] = xb.second;
      matched[name] = row;
      const double lr = ln_ratio(row);
      const bool seen = std::any_of(points[name].begin(), points[name].end(),  // a swept value: no new point
                                    [&](const SweepPoint& p) { return p.value == x; });
      if (!seen) points[name].push_back({x, lr});
      log << "density sweep: " << name << " at " << method[name]->parameter << " " << x << ": glint density ratio "
          << row["glint_density_ratio"] << "\n";
      if (!(std::fabs(lr) <= kMatchedBound) && !seen) still.push_back(name);
    }
    open = still;
  }
  for (const auto& name : open)
    if (matched.contains(name) && matched[name]["value"].is_number())
      log << "warning: density sweep: " << name << ": the glint density ratio is still outside [0.8, 1.25] after "
          << kMatchRounds << " rounds (summary.json matched_density has the last one)\n";
  (*summary_extra)["density_sweep"] = sweep;
  (*summary_extra)["matched_density"] = matched;
  return kExitOk;
}

}  // namespace glintlab

#include "experiments/stress/stress.h"

#include "core/util/image.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/stress/stress_internal.h"

#include <chrono>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>

namespace glintlab {

namespace stress {

PixelScan scan_image(const Image& img, int channels) {
  PixelScan s;
  const int nc = std::min(channels, img.channels);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    const float* p = img.data.data() + i * img.channels;
    bool nonfinite = false, negative = false;
    for (int c = 0; c < nc; ++c) {
      if (!std::isfinite(p[c])) nonfinite = true;
      else if (p[c] < 0) negative = true;
      if (c < 3 && std::isfinite(p[c])) {
        s.max_value = std::max(s.max_value, double(p[c]));
        s.sum += p[c];
      }
    }
    s.nonfinite += nonfinite;
    s.negative += negative && !nonfinite;
    ++s.pixels;
  }
  return s;
}

StressCaseResult make_result(const std::string& name, const std::string& category, const ValueScan& scan,
                             const ErrorStat* err, std::optional<double> bound, bool ok, std::string detail) {
  StressCaseResult r;
  r.name = name;
  r.category = category;
  r.nonfinite = scan.nonfinite;
  r.negative = scan.negative;
  r.items = scan.items;
  if (err && err->compared > 0) {
    r.max_rel_error = err->max_rel;
    r.compared = err->compared;
  }
  r.bound = bound;
  bool within = !(r.max_rel_error && bound) || *r.max_rel_error <= *bound;
  r.pass = ok && within && scan.nonfinite == 0 && scan.negative == 0;
  r.detail = std::move(detail);
  return r;
}

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  add_math_cases(cases);
  add_sand_cases(cases);
  add_glint_cases(cases);
  add_render_cases(cases);
  add_taa_cases(cases);
  return cases;
}

}  // namespace stress

bool StressReport::all_pass() const {
  for (const auto& c : cases)
    if (!c.pass) return false;
  return !cases.empty();
}

std::vector<std::string> stress_case_names(bool fast) {
  std::vector<std::string> names;
  for (const auto& c : stress::all_cases())
    if (!fast || c.fast) names.push_back(c.name);
  return names;
}

StressReport run_stress(const StressOptions& options, std::ostream& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  StressReport report;
  report.fast = options.fast;
  report.validation = options.validation;
  std::vector<stress::Case> cases;
  for (auto& c : stress::all_cases()) {
    if (options.fast && !c.fast) continue;
    if (!options.only.empty()) {
      bool keep = false;
      for (const auto& o : options.only) keep = keep || c.name.find(o) != std::string::npos;
      if (!keep) continue;
    }
    cases.push_back(std::move(c));
  }
  if (cases.empty()) return report;
  core::VkContext ctx(core::ContextOptions{options.device, options.validation});
  report.device = ctx.info().name;
  progress << "stress: device " << report.device << (options.validation ? " (validation on)" : "") << "\n";
  stress::Env env{ctx, options.fast};
  size_t k = 0;
  for (auto& c : cases) {
    ++k;
    const size_t messages_before = ctx.validation_message_count();
    const auto c0 = std::chrono::steady_clock::now();
    StressCaseResult r;
    try {
      r = c.run(env);
    } catch (const core::VulkanError&) {
      throw;  // the device failed: no later case can run
    } catch (const std::exception& e) {
      r = StressCaseResult{};
      r.name = c.name;
      r.pass = false;
      r.detail = std::string("threw: ") + e.what();
    }
    r.name = c.name;
    r.category = c.category;
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - c0).count();
    const size_t messages = ctx.validation_message_count() - messages_before;
    if (messages > 0) {
      r.pass = false;
      auto all = ctx.validation_messages();
      r.detail += "; " + std::to_string(messages) + " validation message(s), first: " + all[messages_before];
      r.extra["validation_messages"] = messages;
    }
    progress << "stress: [" << k << "/" << cases.size() << "] " << (r.pass ? "pass " : "FAIL ") << c.name << " ("
             << std::fixed << std::setprecision(1) << r.ms / 1000.0 << " s)\n"
             << std::defaultfloat;
    report.cases.push_back(std::move(r));
  }
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

nlohmann::ordered_json stress_json(const StressReport& report) {
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  auto num_or_null = [](const std::optional<double>& v) -> nlohmann::ordered_json {
    if (v && std::isfinite(*v)) return *v;
    return nullptr;
  };
  for (const auto& c : report.cases) {
    nlohmann::ordered_json j;
    j["name"] = c.name;
    j["nonfinite"] = c.nonfinite;
    j["negative"] = c.negative;
    // a non-finite error (a NaN output compared) is reported as null with pass = false
    j["max_rel_error"] = num_or_null(c.max_rel_error);
    j["pass"] = c.pass;
    j["category"] = c.category;
    j["bound"] = num_or_null(c.bound);
    j["items"] = c.items;
    j["compared"] = c.compared;
    j["detail"] = c.detail;
    j["ms"] = c.ms;
    for (auto it = c.extra.begin(); it != c.extra.end(); ++it) j[it.key()] = it.value();
    cases.push_back(std::move(j));
  }
  nlohmann::ordered_json out;
  out["cases"] = std::move(cases);
  return out;
}

void print_stress_text(const StressReport& report, std::ostream& out) {
  size_t failed = 0, width = 0;
  for (const auto& c : report.cases) width = std::max(width, c.name.size());
  for (const auto& c : report.cases) {
    failed += !c.pass;
    out << (c.pass ? "pass  " : "FAIL  ") << std::left << std::setw(int(width)) << c.name << std::right
        << "  nonfinite " << c.nonfinite << "  negative " << c.negative << "  max_rel_error ";
    if (c.max_rel_error) {
      out << std::setprecision(3) << *c.max_rel_error;
      if (c.bound) out << " (bound " << *c.bound << ")";
    } else {
      out << "-";
    }
    out << std::defaultfloat << "  [" << std::fixed << std::setprecision(2) << c.ms / 1000.0 << " s]"
        << std::defaultfloat << "\n";
    if (!c.pass) out << "      " << c.detail << "\n";
  }
  out << "stress: " << report.cases.size() - failed << " of " << report.cases.size() << " cases pass"
      << (report.fast ? " (fast subset)" : "") << "; wall time " << std::fixed << std::setprecision(1)
      << report.wall_s << " s on " << report.device << std::defaultfloat << "\n";
}

void add_stress_command(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<StressOptions>();
  auto json = std::make_shared<bool>(false);
  auto list = std::make_shared<bool>(false);
  opt->validation = core::VkContext::validation_requested_by_env();
  CLI::App* c = app.add_subcommand(
      "stress", "numerical stability on extreme inputs: renderer and shader math vs fp64 (exit 1 if a case fails)");
  c->add_flag("--json", *json, "print {\"cases\": [...]} on stdout instead of the text table");
  c->add_flag("--fast", opt->fast, "only the fast subset (what CI runs)");
  c->add_flag("--list", *list, "print the case names and exit");
  c->add_option("--case", opt->only, "only the cases whose name contains this (repeatable)");
  c->add_option("--device", opt->device, "Vulkan device: index or part of its name (default: lavapipe)");
  c->add_flag("--validation", opt->validation, "enable Vulkan validation layers (also GLINTLAB_VALIDATION=1)");
  c->callback([=, &exit_code] {
    exit_code = run_guarded(
        [=] {
          if (*list) {
            for (const auto& n : stress_case_names(opt->fast)) std::cout << n << "\n";
            return int(kExitOk);
          }
          StressReport r = run_stress(*opt, std::cerr);
          if (r.cases.empty()) {
            std::cerr << "error: --case: no case matches\n";
            return int(kExitBadInput);
          }
          if (*json) {
            std::cout << stress_json(r).dump(2) << "\n";
            std::cerr << "stress: " << (r.all_pass() ? "every case passes" : "a case FAILED") << "; wall time "
                      << std::fixed << std::setprecision(1) << r.wall_s << " s\n";
          } else {
            print_stress_text(r, std::cout);
          }
          return int(r.all_pass() ? kExitOk : kExitDefect);
        },
        std::cerr);
  });
}

}  // namespace glintlab

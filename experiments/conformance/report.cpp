#include "experiments/conformance/report.h"

#include "experiments/cli/exit_codes.h"

#include <algorithm>
#include <iostream>
#include <memory>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace glintlab {

namespace {
std::string fmt(double v, int prec = 3) {
  std::ostringstream o;
  o << std::setprecision(prec) << v;
  return o.str();
}
}  // namespace

void apply_declaration(ConformanceCheck& c, const std::vector<std::string>& checks, const std::vector<std::string>& fails) {
  const bool listed = std::find(checks.begin(), checks.end(), c.name) != checks.end();
  c.expected_failure = std::find(fails.begin(), fails.end(), c.name) != fails.end();
  c.applies = listed || c.expected_failure;
}

bool ConformanceReport::all_pass() const {
  for (const auto& c : checks)
    if (c.applies && !c.figure_only && c.pass == c.expected_failure) return false;
  return true;
}

const ConformanceCheck* ConformanceReport::check(const std::string& name) const {
  for (const auto& c : checks)
    if (c.name == name) return &c;
  return nullptr;
}

nlohmann::ordered_json ConformanceReport::json() const {
  nlohmann::ordered_json j;
  j[subject_key] = subject;
  j["file"] = file;
  j["device"] = device;
  j["parameters"] = parameters;
  nlohmann::ordered_json cs = nlohmann::ordered_json::array();
  for (const auto& c : checks) {
    nlohmann::ordered_json e;
    e["check"] = c.name;
    e["applies"] = c.applies;
    if (c.expected_failure) e["expected_failure"] = true;
    e["figure"] = std::isfinite(c.figure) ? nlohmann::ordered_json(c.figure) : nlohmann::ordered_json(nullptr);
    e["unit"] = c.unit;
    if (!c.figure_only) {
      e["bound"] = c.bound;
      e["pass"] = c.pass;
    }
    e["detail"] = c.detail;
    cs.push_back(e);
  }
  j["checks"] = cs;
  j["pass"] = all_pass();
  return j;
}

std::string ConformanceReport::text() const {
  std::ostringstream o;
  o << suite << " " << subject << " (" << file << ")";
  for (const auto& [k, v] : parameters.items()) o << " " << k << "=" << (v.is_string() ? v.get<std::string>() : v.dump());
  o << " on " << device << "\n";
  for (const auto& c : checks) {
    const char* verdict = c.figure_only        ? "      "
                          : !c.applies         ? "n/a   "
                          : c.expected_failure ? (c.pass ? "PASS? " : "fails ")
                          : c.pass             ? "pass  "
                                               : "FAIL  ";
    o << "  " << verdict << std::left << std::setw(16) << c.name << std::right << fmt(c.figure, 4) << " " << c.unit;
    if (!c.figure_only) o << " (bound " << fmt(c.bound) << ")";
    if (!c.applies) o << " [not declared]";
    if (c.expected_failure)
      o << (c.pass ? " [declared fails= but passes: take it out of fails=]" : " [declared fails=: the published method's own]");
    o << "\n        " << c.detail << "\n";
  }
  o << suite << ": " << (all_pass() ? "every applying check passes" : "a check FAILED") << "\n";
  return o.str();
}

void add_conformance_command(CLI::App& app, int& exit_code, const std::string& name, const std::string& description,
                             const std::string& subject_name, const std::string& subject_help,
                             std::function<ConformanceSuite(const ConformanceCommandOptions&)> prepare,
                             const std::function<void(CLI::App&)>& extra_options) {
  struct Options : ConformanceCommandOptions {
    bool json = false, validation = false;
  };
  auto o = std::make_shared<Options>();
  o->validation = core::VkContext::validation_requested_by_env();
  CLI::App* c = app.add_subcommand(name, description);
  c->add_option(subject_name, o->subject, subject_help)->required();
  c->add_option("--parameters", o->parameters, "NAME=VALUE of the file's declared parameters (repeatable)");
  c->add_flag("--json", o->json, "print the report as JSON on stdout");
  c->add_option("--device", o->device, "Vulkan device: index or part of its name (default: lavapipe)");
  c->add_flag("--validation", o->validation, "enable Vulkan validation layers (also GLINTLAB_VALIDATION=1)");
  if (extra_options) extra_options(*c);
  c->callback([o, prepare, &exit_code] {
    exit_code = run_guarded(
        [&] {
          const ConformanceSuite suite = prepare(*o);
          core::VkContext ctx(core::ContextOptions{o->device, o->validation});
          const ConformanceReport r = suite(ctx);
          if (o->json) std::cout << r.json().dump(2) << "\n";
          else std::cout << r.text();
          if (ctx.validation_message_count() > 0) {
            std::cerr << "error: " << ctx.validation_message_count()
                      << " Vulkan validation message(s), first: " << ctx.validation_messages().front() << "\n";
            return int(kExitDefect);
          }
          return int(r.all_pass() ? kExitOk : kExitDefect);
        },
        std::cerr);
  });
}

}  // namespace glintlab

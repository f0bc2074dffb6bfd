// A temporal resolve is one GLSL file with one function
//   TaaResult taa_resolve(TaaPixel p);        (shaders/taa/interface.glsl states the interface)
// whose declaration -- conformance checks, parameters, compile-time options -- is in comment lines of
// the file itself:
//   // taa_resolve checks=finite,deterministic,... [fails=CHECK,...] [extends=BUILT-IN]
//   // taa_parameter NAME default=V range=LO,HI [requires=BOOL]     (a float field p.NAME)
//   // taa_parameter NAME default=true|false [requires=BOOL]        (a bool field p.NAME)
//   // taa_option NAME=a|b|c default=a [requires=BOOL]              (compile-time: TAA_NAME == TAA_NAME_a)
// A parameter is a field of TaaPixel at run time; the preprocessor also sees TAA_ON_NAME (1 where its
// value is non-zero), so that a file compiles out what a zero parameter switches off and the pass then
// binds nothing that code would read. The built-in resolves are the files of shaders/taa/, named by
// their file names: this registry reads them, and no other list of their names or options exists.
// The jitter is the variant's, whatever the resolve (TaaSettings::jitter).
#pragma once

#include "core/render/sample_schedule.h"
#include "core/vk/user_shader.h"

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace glintlab::core {

// The resolve an experiment's "taa" object without "name" or "file" means (the old flat form:
// "taa": {"clamp": ..., "alpha": ...} sets falcor's parameters and options).
inline constexpr const char* kTaaDefaultResolve = "falcor";

// Most parameters a resolve may declare (the pass's push constants: 4 vec4).
inline constexpr size_t kMaxTaaParameters = 16;

// A compile-time choice among names.
struct TaaOption {
  std::string name;
  std::vector<std::string> choices;
  size_t def = 0;
  std::string requires_bool;  // a bool parameter that must be true for this option to apply ("" none)
};

// Which of the interface's resources a resolve reads (found in its preprocessed source, for its
// options): the pass binds and keeps only these.
struct TaaUses {
  bool motion = false;    // taa_motion, taa_distance(_prev), taa_render_motion/distance: "motion" is written
  bool glint = false;     // taa_glint, taa_render_glint: the surface pass writes "glint"
  bool state = false;     // taa_state: "taa.state" is kept
  bool state2 = false;    // taa_state2: "taa.state2" is kept
  bool history2 = false;  // taa_history2: "taa.history2" is kept
};

// The conformance checks of `glintlab taa-test` a declaration may name.
std::vector<std::string> taa_check_names();

struct TaaResolveDecl {
  std::string name;  // built-in: the file name without .glsl; a user file: its path as given
  std::string file;  // built-in: relative to the shader folder; a user file: absolute
  bool builtin = false;
  std::vector<std::string> checks;  // which of taa_check_names() apply
  std::vector<std::string> fails;   // checks the published design fails (run, expected to fail)
  // extends=NAME: a built-in resolve whose parameters and options this file takes first (its own follow);
  // the file includes the built-in's and changes it through the hooks it offers (taau: falcor's).
  std::string extends;
  std::vector<DeclaredParameter> parameters;  // in declaration order = push-constant order
  std::vector<TaaOption> options;
  std::string content_hash;  // of the file's bytes

  const DeclaredParameter* parameter(const std::string& name) const;
  const TaaOption* option(const std::string& name) const;
};

// Parses the declaration lines of a resolve file; `where` names the file in errors. ConfigError naming
// the file, the line and what is allowed.
TaaResolveDecl parse_taa_resolve(const std::string& name, const std::string& where, const std::string& text);

// A user's resolve file: read, declaration parsed, checked for what it may not declare (resources of
// its own, discard), `file` made absolute. ConfigError naming the file and line.
TaaResolveDecl taa_resolve_from_file(const std::string& path);

// Every file of shaders/taa/ (but the interface), sorted by name (read once).
const std::vector<TaaResolveDecl>& builtin_taa_resolves();
const TaaResolveDecl* find_builtin_taa_resolve(const std::string& name);
std::vector<std::string> taa_resolve_names();

// A resolve with its parameter values and option choices, and the variant's jitter.
struct TaaSettings {
  JitterSequence jitter = JitterSequence::Halton16;
  std::shared_ptr<const TaaResolveDecl> resolve;
  std::vector<double> values;   // per declared parameter
  std::vector<size_t> choices;  // per declared option

  TaaSettings();  // kTaaDefaultResolve with its defaults
  explicit TaaSettings(const TaaResolveDecl& decl);

  // std::invalid_argument naming the resolve and what is allowed for an unknown name or a value out of
  // range.
  double value(const std::string& name) const;
  bool on(const std::string& name) const { return value(name) != 0.0; }
  const std::string& option(const std::string& name) const;
  TaaSettings& set(const std::string& name, double v);
  TaaSettings& set(const std::string& name, bool v) { return set(name, v ? 1.0 : 0.0); }
  TaaSettings& set(const std::string& name, const std::string& choice);
  TaaSettings& set(const std::string& name, const char* choice) { return set(name, std::string(choice)); }

  // The defines that compile the resolve into passes/taa.frag (options, TAA_ON_*, the parameter fields,
  // the include of the file, what it uses); without the host's TAA_QUAD_SHARE.
  std::vector<std::string> defines() const;
  // What the resolve reads with these options (preprocesses the file).
  TaaUses uses() const;
  // The record of the settings: {"name" or "file" and "hash", "jitter", every parameter and option}.
  nlohmann::json to_json() const;
};

}  // namespace glintlab::core

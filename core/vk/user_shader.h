// What glint models (core/material/glint_model.h) and TAA resolves (core/render/taa_resolve.h) share as
// files a user brings: declaration lines in comments ("// KIND NAME key=value ..."), parameters
// declared there, and the refusal of what such a file may not declare. One definition each.
#pragma once

#include <functional>
#include <set>
#include <string>
#include <vector>

namespace glintlab::core {

// `s` split at `sep` (empty items kept).
std::vector<std::string> split_list(const std::string& s, char sep);

// A whole-string finite number.
bool parse_finite(const std::string& s, double& v);

// A value a shader's float holds as a finite number.
bool fits_float(double x);

// One declared parameter: "NAME default=VALUE range=LO,HI", or a bool "NAME default=true|false"
// (with or without "type=bool"), and optionally "requires=OTHER" (it applies only where the bool
// parameter OTHER is true; TAA resolves).
struct DeclaredParameter {
  std::string name;
  double def = 0.0, lo = 0.0, hi = 0.0;
  bool is_bool = false;
  std::string requires_bool;
};

// "" when `n` may name a parameter that becomes a field of a GLSL struct and a JSON key, else why not:
// lower_snake_case (upper case names are the shaders' macros), no GLSL keyword, reserved word or type
// name, nothing in `reserved` (the struct's own fields, the JSON object's other keys).
std::string parameter_name_problem(const std::string& n, const std::set<std::string>& reserved);

// The fields of a parameter line after its kind ("NAME key=value ..."); `fail` throws with the file,
// line and syntax. `allow_requires`: whether "requires=" is part of the syntax.
DeclaredParameter parse_declared_parameter(const std::vector<std::string>& fields, const std::set<std::string>& reserved,
                                           bool allow_requires, const std::function<void(const std::string&)>& fail);

// A user's file, preprocessed as glintlab compiles it (includes resolved, macros expanded: a
// "#define B buffer" hides nothing), may not declare resources, work-group memory, or leave the
// pipeline's control flow (discard). ConfigError "PATH[:LINE]: a WHAT may not use "X" (why)...";
// `data_hint` says where the file's data comes from instead. `defines` as the compiler takes them.
void refuse_what_a_user_shader_may_not_declare(const std::string& path, const std::string& text, const std::string& what,
                                               const std::string& data_hint,
                                               const std::vector<std::string>& defines = {});

}  // namespace glintlab::core

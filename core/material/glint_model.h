// The glint term of the sand (DESIGN "Ground truth"): which model shades the
// sparkles. Two models are part of the material itself: "kajs" (Kajs 2022
// eq. 4.17-4.23, a per-grain gate, not an NDF; shaders/sand/glints.glsl) and
// "none". Every other model is one GLSL file with one function
//   vec3 glint_D(GlintQuery q);             (shaders/glint/query.glsl)
// whose declaration -- truth, smooth limit, conformance checks, parameters --
// is in comment lines of the file itself. The built-in ones are the files of
// shaders/glint/models/, named by their file name: this registry reads them,
// and no other list of their names exists (a test checks it).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace glintlab::core {

// The name of the thesis model and of no glints (SAND_GLINT_KAJS, SAND_GLINT_NONE).
inline constexpr const char* kGlintModelKajs = "kajs";
inline constexpr const char* kGlintModelNone = "none";

// One parameter of a model, a float field of GlintQuery:
//   // glint_parameter NAME default=VALUE range=LO,HI
//   // glint_parameter NAME default=true|false type=bool
struct GlintParameter {
  std::string name;
  double def = 0.0, lo = 0.0, hi = 0.0;
  bool is_bool = false;  // JSON true/false, 1/0 in the query
};

// The conformance checks of `glintlab glint-test` a declaration may name.
std::vector<std::string> glint_check_names();

// A model's declaration:
//   // glint_model truth=self|grains limit=beckmann|ggx checks=finite,unbiased,limit,deterministic [fails=CHECK,...]
//   // glint_table size=N            (optional: a data table, see core/material/glint_table.h)
struct GlintModelDecl {
  std::string name;  // built-in: the file name without .glsl; a user file: its path as given
  std::string file;  // built-in: relative to the shader folder; a user file: absolute
  bool builtin = false;
  // "self": the model's own point evaluation supersampled is its truth; else
  // the built-in model (of truth "self") whose supersampled image is (grains:
  // the explicit microdetails a filtering model approximates).
  std::string truth = "self";
  std::string limit = "beckmann";   // the smooth limit (or "ggx", GGX with alpha_g): the far field and the checks
  std::vector<std::string> checks;  // which of glint_check_names() apply
  // Checks the published method fails by its own design: run and reported, and
  // expected to fail (glint-test reports it when one passes); none also in checks.
  std::vector<std::string> fails;
  // Floats of the model's data table (0: none): the file defines
  // float glint_table_entry(uint i) and glint_D reads glint_table[i].
  uint32_t table_size = 0;
  std::vector<GlintParameter> parameters;  // in declaration order = slot order in the material block
  std::string content_hash;                // of the file's bytes

  const GlintParameter* parameter(const std::string& name) const;
};

// Largest data table a model may declare (floats, 8 MiB: one dispatch of 64-wide groups).
inline constexpr uint32_t kMaxGlintTableSize = 1u << 21;

// Most parameters a model may declare (SandParams.glint_parameters, 2 vec4).
inline constexpr size_t kMaxGlintParameters = 8;

// Parses the declaration lines of a model file. `name` is what the model is
// called, `where` how errors name the file. ConfigError naming the file, the
// line and what is allowed for a malformed or missing declaration.
GlintModelDecl parse_glint_model(const std::string& name, const std::string& where, const std::string& text);

// A user's model file: read, declaration parsed (ConfigError naming the file
// and line), `file` made absolute, `name` = the path as given.
GlintModelDecl glint_model_from_file(const std::string& path);

// Every file of shaders/glint/models/, sorted by name (read once).
const std::vector<GlintModelDecl>& builtin_glint_models();
// nullptr when `name` is not a built-in glint_D model.
const GlintModelDecl* find_builtin_glint_model(const std::string& name);
// "kajs", the built-in glint_D models, "none": every name "glint_model" takes.
std::vector<std::string> glint_model_names();

// The value of SandParams.glint_model on the GPU: SAND_GLINT_NONE 0,
// SAND_GLINT_KAJS 1, a built-in glint_D model 2 + its index in
// builtin_glint_models(), a user file 2 + their count.
uint32_t glint_model_gpu_id(const std::string& name);

}  // namespace glintlab::core

// `glintlab glint-test MODEL|FILE`: the conformance suite of a glint model,
// the same for every model, built-in or brought. The model's glint_D runs on
// the GPU through the query the renderer builds (shaders/glint/
// conformance.comp includes sand/glint_models.glsl with the model's defines)
// over a stated grid; each check gives its figure and its bound:
//   finite         NaN, Inf or negative values on the stress inputs (bound 0)
//   unbiased       |mean of D over random uv - D_g| in standard errors (bound 5)
//   limit          one evaluation at 10^14 per uv area over a 1e-3 footprint vs D_g (bound 3 %)
//   deterministic  values that differ between two identical dispatches (bound 0)
//   LOD coherence, shift coherence: figures (correlations), no bound.
// Checks a model's declaration does not name are reported as not applying;
// checks it names in fails= are expected to fail (and reported if they pass).
#pragma once

#include "core/material/glint_model.h"
#include "experiments/conformance/report.h"
#include "core/vk/vk_context.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace glintlab {

using GlintCheckResult = ConformanceCheck;
using GlintTestReport = ConformanceReport;

// A built-in model's name, or a path to a model file.
core::GlintModelDecl resolve_glint_model(const std::string& model_or_file);
// "k=v" overrides of the declared defaults, validated (ConfigError naming the key and its range).
std::vector<float> glint_test_parameters(const core::GlintModelDecl& d, const std::vector<std::string>& overrides);

GlintTestReport run_glint_test(core::VkContext& ctx, const core::GlintModelDecl& d, const std::vector<float>& parameters);

void add_glint_test_command(CLI::App& app, int& exit_code);

}  // namespace glintlab

// `glintlab taa-test NAME|FILE`: the conformance suite of a temporal resolve, the same for every
// resolve, built-in or brought. Each check renders a small fixed scene through the resolve (with the
// parameters and options given, the jitter Halton(2,3) x16 unless said) and gives one figure and its
// bound:
//   finite         NaN, Inf or negative values in every frame the suite renders (bound 0)
//   deterministic  values that differ between two renders of the same sequence (bound 0)
//   converges      static camera, 64 frames of R2 jitter (64 distinct samples): CIEDE2000 of the last
//                  frame against a 1024-sample truth over that of 8x8 supersampling (64 samples; bound 1.25)
//   ghosting       a sphere crossing the sky before a static camera: what is left of the sphere's
//                  contrast 4 frames after it left a pixel (sum |resolve - current| / sum |sphere - sky|;
//                  bound 5 %)
//   cut            the first frame after a camera cut, between two sequences whose first shots differ
//                  (nothing of the history may remain), relative to the frame's maximum (bound 1e-4)
//   pan            a steady pan over sand: pooled RMS error of 2x2-pixel means against the truth, over
//                  that of one sample per pixel (whose aliasing mostly averages out at 2 px: what a
//                  resolve adds there is blur, lag and ghosts; bound 1.25), 4x4 supersampling beside it
//   flicker        a close orbit over glinting sand: flicker excess above the truth's floor, over that
//                  of one sample per pixel (the share of aliasing flicker the resolve leaves; bound 1/2)
// Checks the file's declaration does not name are reported as not applying; checks it names in fails=
// are expected to fail (and reported if they pass).
#pragma once

#include "core/render/taa_resolve.h"
#include "core/vk/vk_context.h"
#include "experiments/conformance/report.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace glintlab {

// A built-in resolve's name or a resolve file, with "NAME=VALUE" overrides of its declared parameters
// and options (ConfigError naming the key and what is allowed).
core::TaaSettings taa_test_settings(const std::string& resolve_or_file, const std::vector<std::string>& overrides);

// Runs every check on `ctx` and, for the checks measured by runs, on `device` (the same device, as
// --device names it); `work_dir` holds the runs' folders (a fresh folder, removed by the caller). The
// truths are cached beside the SPIR-V cache (content-keyed, shared between runs of the suite).
// `render_scale` below 1: every scene is rendered at that scale and resolved to its output resolution
// (jitter halton_fsr2; converges keeps R2), against the same truths and SSAA at the output resolution;
// "one sample per pixel" (pan, flicker) is then one sample per render texel upscaled bilinearly: the
// resolve's own input, spatially upscaled.
ConformanceReport run_taa_test(core::VkContext& ctx, const core::TaaSettings& s, const std::string& work_dir,
                               const std::string& device, double render_scale = 1.0);

void add_taa_test_command(CLI::App& app, int& exit_code);

}  // namespace glintlab

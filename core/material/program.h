// A material program: what a surface pass needs to shade with a material —
// the fragment shader, its compile-time defines, the contents of its material
// uniform block (set 0, binding 1) — and the content key that identifies what
// it renders (for the reference cache). The sand factory below knows which
// features each role needs; nothing outside core/material decides defines.
#pragma once

#include "core/material/sand_material.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace glintlab::core {

struct MaterialProgram {
  std::string fragment;              // path under shaders/, e.g. "passes/sand.frag"
  std::vector<std::string> defines;  // "NAME" or "NAME=VALUE"
  std::vector<std::byte> block;      // material UBO contents; may be empty
  // The frame's sun and sky term (frame_sun_dir, frame_sun_L, env_sh of
  // shaders/common/frame.glsl) as constants: the surface pass compiles them in
  // and compiles again when a frame brings other values (a run's lighting does
  // not change between frames). On llvmpipe this cut a 1280x720 frame of the
  // full sand material from 35.7 to 27.0 ms and from 33.7 to 29.0 ms (two
  // interleaved bench runs; each value read from a uniform block costs a
  // bounds-checked load per eight fragments there); on any device it changes
  // results only by the compiler's constant folding (ulps).
  bool frame_lighting_constants = false;
  // The glint model whose data table the fragment shader reads (set 0,
  // binding 3; core/material/glint_table.h), when the program builds in a
  // model that declares one.
  std::optional<GlintModelDecl> glint_table_model;

  // XXH3-128 of the preprocessed fragment source (all includes), the defines
  // and the block: equal keys render equal images.
  std::string cache_key() const;
};

// What a program is for.
enum class ProgramRole {
  Variant,    // what a variant renders: every feature the run's distances reach (pruned by shader_defines)
  Reference,  // the ground truth: the footprint integral of the *micro* model, so no far field and no
              // close-to-far transition (SAND_FAR=0, SAND_CLOSE=1), whatever the distances
};

// The sand material as a program for `role`. `needs` carries the run's
// distance range and debug output.
MaterialProgram sand_program(const SandParams& params, const SandFeatures& needs, ProgramRole role);

// The material block as the define SAND_PARAMS_WORDS (its 32-bit words, in order): with it
// passes/sand.frag takes its parameters as constants instead of from the uniform block, so the
// shader compiler folds every expression of the parameters alone, and the shader reads no uniform
// block for them. sand_program() adds it. On llvmpipe this halved the material's own cost (each
// uniform-block read in a fragment shader cost there about 0.3 ms of a 1280x720 frame); on any
// device it changes results only by the compiler's constant folding (ulps).
std::string material_constants_define(const std::vector<std::byte>& block);

// A program that shades nothing (colour 0, alpha = coverage): motion vectors
// only, or the floor of a benchmark.
MaterialProgram geometry_only_program();

}  // namespace glintlab::core

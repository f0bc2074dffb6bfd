#include "core/material/program.h"

#include "core/util/content_hash.h"
#include "core/vk/shader_compiler.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace glintlab::core {

std::string MaterialProgram::cache_key() const {
  ContentHash h;
  // v2: accumulating passes add one fragment per pixel and sample where
  // surfaces tie at the nearest depth (before, each of them); v3: meshes are
  // drawn chunk by chunk (which of two tying triangles comes first can change)
  h.add(std::string_view("material-program-v3"))
      .add(default_shader_compiler().source_hash(fragment, ShaderStage::Fragment, defines));
  for (const auto& d : defines) h.add(std::string_view(d));
  h.add(block.data(), block.size());
  h.add(std::string_view(frame_lighting_constants ? "frame-lighting-constants" : "frame-lighting-uniforms"));
  return h.hex();
}

MaterialProgram sand_program(const SandParams& params, const SandFeatures& needs, ProgramRole role) {
  MaterialProgram p;
  p.fragment = "passes/sand.frag";
  SandFeatures f = needs;
  if (role == ProgramRole::Reference) f.min_distance = f.max_distance = 0.0;  // the close field is always reached
  // the truth of a filtered glint model is its point-evaluated microstructure (zirr -> grains)
  const SandParams shaded = role == ProgramRole::Reference ? params.reference() : params;
  p.defines = shader_defines(shaded, f);
  if (role == ProgramRole::Reference) {
    // DESIGN "Ground truth": the far model and the sigmoid transition are
    // approximations of the footprint average, so the truth has neither.
    p.defines.erase(std::remove_if(p.defines.begin(), p.defines.end(),
                                   [](const std::string& d) {
                                     return d.rfind("SAND_FAR=", 0) == 0 || d.rfind("SAND_CLOSE=", 0) == 0;
                                   }),
                    p.defines.end());
    p.defines.push_back("SAND_FAR=0");
    p.defines.push_back("SAND_CLOSE=1");
  }
  SandParamsGPU gpu = shaded.pack();
  p.block.resize(sizeof gpu);
  std::memcpy(p.block.data(), &gpu, sizeof gpu);
  p.defines.push_back(material_constants_define(p.block));
  p.frame_lighting_constants = true;
  const bool table = std::any_of(p.defines.begin(), p.defines.end(),
                                 [](const std::string& d) { return d.rfind("GLINT_TABLE_SIZE=", 0) == 0; });
  if (const GlintModelDecl* d = shaded.glint_decl(); d && table) p.glint_table_model = *d;
  return p;
}

std::string material_constants_define(const std::vector<std::byte>& block) {
  return words_define("SAND_PARAMS_WORDS", block.data(), block.size());
}

MaterialProgram geometry_only_program() {
  MaterialProgram p;
  p.fragment = "passes/motion.frag";
  return p;
}

}  // namespace glintlab::core

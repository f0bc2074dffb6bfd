#include "experiments/runner/variant_factory.h"

#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"

namespace glintlab {

RenderSetup build_variant(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                          const VariantSpec& v, const core::MaterialProgram& program) {
  RenderSetup r;
  r.graph = std::make_unique<core::FrameGraph>(ctx, width, height);
  core::SurfacePassOptions o;
  o.program = program;
  switch (v.aa) {
    case AaMethod::None:
    case AaMethod::Ssaa:
      r.output = "color";
      r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
      break;
    case AaMethod::Taa:
      o.motion = true;
      r.output = "taa.color";
      r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
      r.graph->add(std::make_unique<core::TaaPass>(ctx, v.taa));
      break;
  }
  r.graph->build({r.output});
  return r;
}

RenderSetup build_reference(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                            const core::MaterialProgram& program) {
  RenderSetup r;
  r.graph = std::make_unique<core::FrameGraph>(ctx, width, height);
  core::SurfacePassOptions o;
  o.name = "reference";
  o.program = program;
  r.output = "color";
  r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  r.graph->build({r.output});
  return r;
}

RenderSetup build_motion(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height) {
  RenderSetup r;
  r.graph = std::make_unique<core::FrameGraph>(ctx, width, height);
  core::SurfacePassOptions o;
  o.name = "motion";
  o.program = core::geometry_only_program();
  o.motion = true;
  r.output = "motion";
  r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  r.graph->build({r.output});
  return r;
}

std::vector<glm::vec2> variant_offsets(const VariantSpec& v, int k) {
  switch (v.aa) {
    case AaMethod::Ssaa: return v.ssaa_grid <= 1 ? std::vector<glm::vec2>{glm::vec2(0.0f)}
                                                 : core::stratified_offsets(v.ssaa_grid, kSsaaPatternSeed);
    case AaMethod::Taa: return {core::jitter_offset(v.taa.jitter, k)};
    case AaMethod::None: break;
  }
  return {glm::vec2(0.0f)};
}

std::vector<glm::vec2> reference_offsets(int grid) {
  return grid <= 1 ? std::vector<glm::vec2>{glm::vec2(0.0f)} : core::stratified_offsets(grid, kReferencePatternSeed);
}

}  // namespace glintlab

#include "experiments/sources/variant_factory.h"

#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"
#include "core/render/upscale_pass.h"

namespace glintlab {

RenderSetup build_variant(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                          const VariantSpec& v, const core::MaterialProgram& program) {
  RenderSetup r;
  r.graph = std::make_unique<core::FrameGraph>(ctx, width, height);
  core::SurfacePassOptions o;
  o.program = program;
  const bool scaled = v.render_scale < 1.0;
  if (scaled) {  // the surface pass renders below the output resolution; a resolve or an upscale fills it
    o.width = v.render_width(width);
    o.height = v.render_height(height);
    if (v.glint_footprint == "display") o.footprint_scale = float(v.render_scale);
    o.sky_jittered = true;
  }
  // One sample per frame (no AA, TAA, a 1x1 SSAA grid): one opaque draw with
  // depth test LESS instead of a depth pre-pass and an EQUAL shading pass, the
  // same nearest surface (core/render/surface_pass.h).
  o.single_sample = v.samples_per_pixel() == 1;
  switch (v.aa) {
    case AaMethod::None:
    case AaMethod::Ssaa:  // one geometry pass per sample: a jittered stratified pattern (finer than an ordered grid)
      r.output = "color";
      r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
      if (scaled) {
        r.graph->add(std::make_unique<core::UpscalePass>(ctx, "color", "upscaled"));
        r.output = "upscaled";
      }
      break;
    case AaMethod::Taa:
      auto taa = std::make_unique<core::TaaPass>(ctx, v.taa);
      // Motion vectors and the glint layer only where the resolve reads them; the surface pass writes the
      // glint layer beside the motion vectors, so a resolve that reads only the glint layer gets both.
      o.glint = taa->uses().glint;
      o.motion = taa->uses().motion || o.glint;
      r.output = "taa.color";
      r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
      r.graph->add(std::move(taa));
      break;
  }
  r.graph->build({r.output});
  return r;
}

Supersampling supersampling(int grid, int width, int height, uint32_t seed) {
  Supersampling s;
  if (grid <= 1) {
    s.offsets = {glm::vec2(0.0f)};
    return s;
  }
  constexpr double kMaxPixels = double(1 << 22);
  for (int f = grid; f >= 1; --f)
    if (grid % f == 0 && double(f) * f * width * height <= kMaxPixels) {
      s.factor = f;
      break;
    }
  for (const glm::vec2& o : core::stratified_offsets(grid / s.factor, seed))
    s.offsets.push_back(o / float(s.factor));
  return s;
}

RenderSetup build_reference(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                            const core::MaterialProgram& program, int grid) {
  RenderSetup r;
  r.graph = std::make_unique<core::FrameGraph>(ctx, width, height);
  core::SurfacePassOptions o;
  o.name = "reference";
  o.program = program;
  o.supersample = supersampling(grid, width, height, kReferencePatternSeed).factor;
  o.halves = o.supersample >= 2;  // the split-half truth: the noise floor of every metric
  r.output = "color";
  r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  std::vector<std::string> readback = {r.output};
  if (o.halves) readback.insert(readback.end(), {o.half_targets[0], o.half_targets[1]});
  r.halves = o.halves;
  r.graph->build(readback);
  return r;
}

RenderSetup build_motion(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height) {
  RenderSetup r;
  r.graph = std::make_unique<core::FrameGraph>(ctx, width, height);
  core::SurfacePassOptions o;
  o.name = "motion";
  o.program = core::geometry_only_program();
  o.motion = true;
  o.single_sample = true;  // measured: one opaque draw beats pre-pass + EQUAL for a trivial shader
  r.output = "motion";
  r.graph->add(std::make_unique<core::SurfacePass>(ctx, scene, o));
  r.graph->build({r.output});
  return r;
}

std::vector<glm::vec2> variant_offsets(const VariantSpec& v, int k) {
  switch (v.aa) {
    case AaMethod::Ssaa: return v.ssaa_grid <= 1 ? std::vector<glm::vec2>{glm::vec2(0.0f)}
                                                 : core::stratified_offsets(v.ssaa_grid, kSsaaPatternSeed);
    case AaMethod::Taa: return {core::jitter_offset(v.taa.jitter, k, v.render_scale)};
    case AaMethod::None: break;
  }
  return {glm::vec2(0.0f)};
}


}  // namespace glintlab

// Variants are data: this factory turns a variant spec into what the renderer
// runs — a frame graph of passes, the target read back as the variant's image
// and its sample schedule — with the material program from
// core/material/program.h.
//   none  = surface pass, one sample at the pixel centre
//   ssaa  = surface pass, ssaa_grid^2 stratified samples (one fixed pattern)
//   taa   = surface pass with motion vectors, one jittered sample (the TAA
//           jitter sequence), then the TAA resolve pass
// The reference of a variant is a surface pass with the reference program and
// its sample grid; the motion pass (exact motion vectors for the flicker
// metric) a surface pass with the geometry-only program.
#pragma once

#include "core/material/program.h"
#include "core/render/frame_graph.h"
#include "core/render/scene_gpu.h"
#include "experiments/spec/experiment_spec.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace glintlab {

// Fixed sub-pixel patterns: a reference is a fixed quadrature of the pixel
// footprint (a static camera gives identical frames, so its own estimator
// noise never shows up as flicker), and SSAA the fixed-pattern supersampling a
// renderer would ship.
constexpr uint32_t kReferencePatternSeed = 0x5eed0001u;
constexpr uint32_t kSsaaPatternSeed = 17u;

struct RenderSetup {
  std::unique_ptr<core::FrameGraph> graph;
  std::string output;  // the target that is the image ("color", "taa.color", "motion")
};

// The graph of a variant whose material program is `program`.
RenderSetup build_variant(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                          const VariantSpec& v, const core::MaterialProgram& program);
// The reference: `program` accumulated over `grid`^2 stratified samples.
RenderSetup build_reference(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                            const core::MaterialProgram& program);
// Exact motion vectors and distances of the unjittered geometry (and sky).
RenderSetup build_motion(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height);

// Sub-pixel offsets of frame `k`: the pixel centre (none), the fixed grid
// (ssaa), this frame's jitter (taa).
std::vector<glm::vec2> variant_offsets(const VariantSpec& v, int k);
std::vector<glm::vec2> reference_offsets(int grid);

}  // namespace glintlab

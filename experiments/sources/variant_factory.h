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
  bool halves = false;  // a reference that also reads back its two halves ("color.a", "color.b")
};

// The graph of a variant whose material program is `program`.
RenderSetup build_variant(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                          const VariantSpec& v, const core::MaterialProgram& program);
// How the reference takes its grid^2 samples per pixel: the surface pass
// renders at `factor` times the resolution (each high-resolution pixel is one
// cell of a factor x factor grid over the pixel) and every one of the
// (grid / factor)^2 passes shifts the image by one `offsets` entry, a
// stratified jitter within one cell. Together: a grid x grid stratified
// pattern, one fixed quadrature of the pixel box for every frame. `factor` is
// the largest divisor of grid whose high-resolution image stays within 2^22
// pixels (about 4 MPix).
struct Supersampling {
  int factor = 1;
  std::vector<glm::vec2> offsets;  // pixel units
};
// `seed` fixes the jitters (kReferencePatternSeed). (SSAA keeps one geometry
// pass per jittered sample: measured, an ordered grid with one jitter gave a
// 4x4 CIEDE2000 18 % higher on glinting sand.)
Supersampling supersampling(int grid, int width, int height, uint32_t seed);

// The reference: `program` with the sampling above.
// Where the factor is at least 2 the graph also reads back the truth's two halves (the checkerboard
// halves of each pixel's factor x factor cells: core/render/surface_pass.h `halves`), from which the
// frame loop measures every metric's noise floor.
RenderSetup build_reference(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height,
                            const core::MaterialProgram& program, int grid);
// Exact motion vectors and distances of the unjittered geometry (and sky).
RenderSetup build_motion(const core::VkContext& ctx, const core::SceneGpu& scene, int width, int height);

// Sub-pixel offsets of frame `k`: the pixel centre (none), the fixed grid
// (ssaa), this frame's jitter (taa).
std::vector<glm::vec2> variant_offsets(const VariantSpec& v, int k);

}  // namespace glintlab

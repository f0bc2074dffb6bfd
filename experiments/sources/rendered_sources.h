// Rendered frame sources (experiments/sources/frame_source.h): a variant's
// frame graph, a truth from the reference cache or rendered with its sample
// grid (and its two halves), and the motion pass. They share one
// RenderedFrames: the camera and uniforms of frame k, computed once a frame.
#pragma once

#include "core/material/program.h"
#include "core/render/scene_gpu.h"
#include "core/vk/vk_context.h"
#include "experiments/sources/frame_source.h"
#include "experiments/sources/reference_cache.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"

#include <functional>
#include <memory>
#include <ostream>

namespace glintlab {

// Frame k's inputs every rendered source starts from: frame, uniforms, camera cut (no samples).
class RenderedFrames {
 public:
  RenderedFrames(const ExperimentSpec& spec, const SceneData& data) : spec_(spec), data_(data) {}
  const core::FrameInputs& inputs(int k);
  // The same at another render resolution (a variant rendered below the output resolution).
  core::FrameInputs inputs(int k, int width, int height);
  const ExperimentSpec& spec() const { return spec_; }

 private:
  const ExperimentSpec& spec_;
  const SceneData& data_;
  core::FrameInputs in_;
  int k_ = -1;
};

// Variant `v`, shading `program`, rendered by its frame graph.
std::unique_ptr<ColourSource> rendered_variant(const core::VkContext& ctx, const core::SceneGpu& scene,
                                               const VariantSpec& v, const core::MaterialProgram& program,
                                               RenderedFrames& frames);
// The truth of `program` with the run's sample grid: frame k loaded from `cache` by key(its uniforms),
// else rendered and stored (a corrupt entry is said on `log`, removed and rendered again).
using ReferenceKey = std::function<std::string(const core::FrameUniforms&)>;
std::unique_ptr<ColourSource> rendered_reference(const core::VkContext& ctx, const core::SceneGpu& scene,
                                                 const core::MaterialProgram& program, ReferenceKey key,
                                                 const ReferenceCache& cache, RenderedFrames& frames,
                                                 std::ostream& log);
// Exact motion vectors and distances of the unjittered geometry.
std::unique_ptr<MotionSource> rendered_motion(const core::VkContext& ctx, const core::SceneGpu& scene,
                                              RenderedFrames& frames);

}  // namespace glintlab

#include "experiments/sources/rendered_sources.h"

#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/util/strings.h"
#include "experiments/sources/variant_factory.h"
#include "metrics/pixel_scan.h"

#include <chrono>
#include <cmath>
#include <optional>

namespace glintlab {

namespace {

using Clock = std::chrono::steady_clock;

class RenderedVariant final : public ColourSource {
 public:
  RenderedVariant(const core::VkContext& ctx, const core::SceneGpu& scene, const VariantSpec& v,
                  const core::MaterialProgram& program, RenderedFrames& frames)
      : v_(v), frames_(frames),
        setup_(build_variant(ctx, scene, frames.spec().width, frames.spec().height, v_, program)) {}

  SourceFrame frame(int k) override {
    const ExperimentSpec& spec = frames_.spec();
    // Below the output resolution the frame is rendered at the variant's render resolution (its uniforms,
    // its samples and its jitter in render pixels).
    const int rw = v_.render_width(spec.width), rh = v_.render_height(spec.height);
    core::FrameInputs in = frames_.inputs(k, rw, rh);
    const std::vector<glm::vec2> offsets = variant_offsets(v_, k);
    in.samples = core::samples_for(spec.path, k, rw, rh, offsets);
    in.jitter_px = offsets.size() == 1 ? offsets[0] : glm::vec2(0.0f);
    const auto t0 = Clock::now();
    core::FrameResult fr = setup_.graph->execute(in);
    SourceFrame f;
    f.wall_ms = ms_since(t0);
    f.gpu_ms = fr.gpu_ms;
    f.passes = std::move(fr.timings);
    f.image = std::make_shared<const Image>(std::move(fr.images.at(setup_.output)));
    f.scan = metrics::scan_pixels(*f.image, 3);
    return f;
  }
  int samples_per_pixel() const override { return v_.samples_per_pixel(); }

 private:
  const VariantSpec& v_;
  RenderedFrames& frames_;
  RenderSetup setup_;
};

// The truth and, where it has them, its two halves: cached as three entries, rendered again unless all
// three load.
class RenderedReference final : public ColourSource {
 public:
  RenderedReference(const core::VkContext& ctx, const core::SceneGpu& scene, const core::MaterialProgram& program,
                    ReferenceKey key, const ReferenceCache& cache, RenderedFrames& frames, std::ostream& log)
      : key_(std::move(key)), cache_(cache), frames_(frames), log_(log),
        setup_(build_reference(ctx, scene, frames.spec().width, frames.spec().height, program,
                               frames.spec().reference.grid)) {}

  SourceFrame frame(int k) override {
    const ExperimentSpec& spec = frames_.spec();
    core::FrameInputs in = frames_.inputs(k);
    const std::string key = key_(in.uniforms);
    const std::string half_keys[2] = {key + "-half-a", key + "-half-b"};
    SourceFrame f;
    std::optional<Image> img, halves[2];
    bool corrupt = false;
    // An entry of another size than the run's is no entry of this truth (written by a defect): rendered again.
    auto sized = [&](std::optional<Image> im) {
      if (im && (im->width != spec.width || im->height != spec.height)) {
        corrupt = true;
        im.reset();
      }
      return im;
    };
    img = sized(cache_.load(key, &corrupt));
    for (int h = 0; setup_.halves && img && h < 2; ++h) {
      halves[h] = sized(cache_.load(half_keys[h], &corrupt));
      if (!halves[h]) img.reset();
    }
    if (corrupt) {
      log_ << "warning: corrupt reference cache entry " << cache_.path_of(key) << " removed; re-rendering\n";
      f.rebuilt = true;
    }
    if (img) {
      f.cached = true;
    } else {
      in.samples = core::samples_for(
          spec.path, k, spec.width, spec.height,
          supersampling(spec.reference.grid, spec.width, spec.height, kReferencePatternSeed).offsets);
      const auto t0 = Clock::now();
      core::FrameResult fr = setup_.graph->execute(in);
      f.wall_ms = ms_since(t0);
      f.gpu_ms = fr.gpu_ms;
      img = std::move(fr.images.at(setup_.output));
      cache_.store(key, *img);
      for (int h = 0; setup_.halves && h < 2; ++h) {
        halves[h] = std::move(fr.images.at(core::SurfacePassOptions().half_targets[h]));
        cache_.store(half_keys[h], *halves[h]);
      }
    }
    if (setup_.halves) {
      f.half_a = std::make_shared<const Image>(std::move(*halves[0]));
      f.half_b = std::make_shared<const Image>(std::move(*halves[1]));
    }
    f.image = std::make_shared<const Image>(std::move(*img));
    f.scan = metrics::scan_pixels(*f.image, 3);
    return f;
  }

 private:
  const ReferenceKey key_;
  const ReferenceCache& cache_;
  RenderedFrames& frames_;
  std::ostream& log_;
  RenderSetup setup_;
};

class RenderedMotion final : public MotionSource {
 public:
  RenderedMotion(const core::VkContext& ctx, const core::SceneGpu& scene, RenderedFrames& frames)
      : frames_(frames), setup_(build_motion(ctx, scene, frames.spec().width, frames.spec().height)) {}

  MotionFrame frame(int k, const std::shared_ptr<const Image>&) override {
    const ExperimentSpec& spec = frames_.spec();
    core::FrameInputs in = frames_.inputs(k);
    in.samples = core::samples_for(spec.path, k, spec.width, spec.height, {glm::vec2(0.0f)});
    MotionFrame m;
    m.motion = std::move(setup_.graph->execute(in).images.at(setup_.output));
    return m;
  }

 private:
  RenderedFrames& frames_;
  RenderSetup setup_;
};

}  // namespace

core::FrameInputs RenderedFrames::inputs(int k, int width, int height) {
  if (width == spec_.width && height == spec_.height) return inputs(k);
  core::FrameInputs in = inputs(k);
  in.uniforms = frame_uniforms(spec_.path.frame(k, width, height), data_.env, width, height,
                               data_.env_texture.mips_rgba.size(), spec_.mesh.motion);
  return in;
}

const core::FrameInputs& RenderedFrames::inputs(int k) {
  if (k != k_) {
    const core::FrameCamera cam = spec_.path.frame(k, spec_.width, spec_.height);
    in_ = core::FrameInputs{};
    in_.frame = k;
    in_.uniforms = frame_uniforms(spec_, data_, k);
    in_.camera_cut = cam.cut;
    k_ = k;
  }
  return in_;
}

std::unique_ptr<ColourSource> rendered_variant(const core::VkContext& ctx, const core::SceneGpu& scene,
                                               const VariantSpec& v, const core::MaterialProgram& program,
                                               RenderedFrames& frames) {
  return std::make_unique<RenderedVariant>(ctx, scene, v, program, frames);
}

std::unique_ptr<ColourSource> rendered_reference(const core::VkContext& ctx, const core::SceneGpu& scene,
                                                 const core::MaterialProgram& program, ReferenceKey key,
                                                 const ReferenceCache& cache, RenderedFrames& frames,
                                                 std::ostream& log) {
  return std::make_unique<RenderedReference>(ctx, scene, program, std::move(key), cache, frames, log);
}

std::unique_ptr<MotionSource> rendered_motion(const core::VkContext& ctx, const core::SceneGpu& scene,
                                              RenderedFrames& frames) {
  return std::make_unique<RenderedMotion>(ctx, scene, frames);
}

}  // namespace glintlab

// The plan of a run: which variants run, with which material programs, which
// reference each is measured against (variants that share a reference program
// share its frames), and the cache keys of the reference frames. Built once
// from the spec before anything renders.
#pragma once

#include "core/material/program.h"
#include "core/render/frame_uniforms.h"
#include "experiments/sources/sequence.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"

#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace glintlab {

struct RunPlan {
  struct Variant {
    const VariantSpec* spec = nullptr;
    core::SandParams params;        // in the working space
    core::SandParams truth_params;  // what its truth shades: params, or its "truth_material" (measured runs)
    core::MaterialProgram program;  // what its surface pass shades
    int reference = -1;             // index into references; -1 when not measured
    std::optional<FrameFiles> files;  // a frame source ("frames": SEQ): read, not rendered
  };
  struct Reference {
    std::string name;  // "reference", or "reference-<first variant>" when a run has several
    core::MaterialProgram program;
    std::string program_key;  // program.cache_key()
    std::vector<int> variants;
    std::optional<FrameFiles> files;  // "reference": {"frames": SEQ}: read, not rendered
  };

  const ExperimentSpec* spec = nullptr;
  int frames = 0;
  bool measure = false;
  std::vector<Variant> variants;      // in the spec's order
  std::vector<Reference> references;  // in order of first use
  // Hash of everything about a reference frame except its program and frame.
  std::string scene_key;

  // The cache key of reference `r`'s frame with frame uniforms `fu`.
  std::string reference_key(int r, const core::FrameUniforms& fu) const;
};

// Frame sources are opened here (every header checked against the run's size): ConfigError.
// `log` receives the note of a frame source without a colour-space tag.
RunPlan make_plan(const ExperimentSpec& spec, int frames, bool measure, const metrics::ColorManager& cm,
                  const SceneData& scene, const std::string& device_name, std::ostream* log = nullptr);

}  // namespace glintlab

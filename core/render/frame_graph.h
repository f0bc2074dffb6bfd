// A small frame graph: an ordered list of passes (core/render/pass.h). It
// allocates every declared target by name, keeps two images for each history
// target and swaps them every frame, inserts the image barriers that the
// declarations imply (also across frames), records all passes of a frame into
// one command buffer with a GPU timestamp around each, submits once, and
// reads back only the targets named at build().
//
//   FrameGraph g(ctx, 640, 360);
//   g.add(std::make_unique<SurfacePass>(...));
//   g.add(std::make_unique<TaaPass>(...));
//   g.build({"taa.history"});
//   FrameResult r = g.execute(inputs);   // r.images["taa.history"], r.timings
#pragma once

#include "core/render/pass.h"
#include "core/util/image.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace glintlab::core {

struct PassTiming {
  std::string pass;
  double gpu_ms = 0;  // GPU timestamps around the pass's commands; 0 if the device has none
};

struct FrameResult {
  std::map<std::string, Image> images;  // the read-back targets (float, the target's channel count)
  std::vector<PassTiming> timings;      // one per pass, in graph order
  double gpu_ms = 0;                    // first pass's start to last pass's end
};

class FrameGraph {
 public:
  FrameGraph(const VkContext& ctx, int width, int height);
  ~FrameGraph();
  FrameGraph(const FrameGraph&) = delete;
  FrameGraph& operator=(const FrameGraph&) = delete;

  // Appends a pass (execution order = order of add). Only before build().
  Pass& add(std::unique_ptr<Pass> pass);

  // Checks the declarations (every read has an earlier writer, every target
  // one writer and one format), allocates the targets and calls every pass's
  // setup(). `readback`: targets copied to the host by every execute().
  // Throws std::invalid_argument naming the pass and target on a bad graph.
  void build(const std::vector<std::string>& readback);

  // Records, submits and waits for one frame.
  FrameResult execute(const FrameInputs& in);

  // Forgets all temporal state: every history target becomes invalid and
  // every pass's reset_history() is called.
  void reset_history();

  const TargetSet& targets() const;
  std::vector<std::string> pass_names() const;
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_, height_;
};

}  // namespace glintlab::core

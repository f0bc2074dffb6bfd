// A render pass of the frame graph (core/render/frame_graph.h), in the manner
// of Falcor's render passes: it declares the targets it reads, writes and
// keeps across frames, then only records commands into the frame's command
// buffer. The graph allocates the targets, inserts the barriers the
// declarations imply, submits once per frame and times every pass.
//
//   class MyPass : public Pass {
//     std::string name() const override { return "my"; }
//     void declare(PassIO& io) const override {
//       io.read("color");                                  // written by an earlier pass
//       io.write("my.out", VK_FORMAT_R32G32B32A32_SFLOAT, TargetUse::Storage);
//     }
//     void setup(const TargetSet& targets) override { ... descriptors ... }
//     void record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& t) override { ... }
//   };
#pragma once

#include "core/render/frame_uniforms.h"
#include "core/vk/gpu_resources.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace glintlab::core {

// How a pass uses a target inside its commands; the graph derives the image
// layout, pipeline stages and access masks of the barrier from it.
enum class TargetUse {
  ColorAttachment,  // colour attachment (read-modify-write: blending, loadOp LOAD)
  DepthAttachment,  // depth attachment
  Sampled,          // read in a fragment or compute shader through a sampler (texelFetch/texture)
  Storage,          // read/written by a compute shader with imageLoad/imageStore
};

struct TargetDecl {
  std::string name;
  VkFormat format = VK_FORMAT_UNDEFINED;  // UNDEFINED for reads of a target declared elsewhere
  TargetUse use = TargetUse::Sampled;
  bool writes = false;    // the pass writes it (else it only reads it)
  bool discard = false;   // writes every texel without reading: older contents need not be kept
  bool previous = false;  // reads last frame's value of a history target
  int width = 0, height = 0;  // a written target's size; 0: the graph's (a render-scaled pass's targets)
};

// What a pass declares (Falcor's reflect()).
class PassIO {
 public:
  // A target written by an earlier pass of the same frame.
  void read(const std::string& name, TargetUse use = TargetUse::Sampled) {
    decls_.push_back({name, VK_FORMAT_UNDEFINED, use, false, false, false});
  }
  // A target this pass writes. `discard`: it overwrites every texel (or clears
  // first) without reading the old contents.
  // `width`, `height`: its size where it is not the graph's (a pass rendering below the output
  // resolution); 0 = the graph's.
  void write(const std::string& name, VkFormat format, TargetUse use, bool discard = true, int width = 0,
             int height = 0) {
    decls_.push_back({name, format, use, true, discard, false, width, height});
  }
  // A target this pass writes and keeps across frames (its history): the graph
  // holds two images and swaps them every frame; read_previous() reads the one
  // written last frame.
  void keep(const std::string& name, VkFormat format, TargetUse use, bool discard = true, int width = 0,
            int height = 0) {
    write(name, format, use, discard, width, height);
    history_.push_back(name);
  }
  void read_previous(const std::string& name, TargetUse use = TargetUse::Sampled) {
    decls_.push_back({name, VK_FORMAT_UNDEFINED, use, false, false, true});
  }

  const std::vector<TargetDecl>& decls() const { return decls_; }
  const std::vector<std::string>& history() const { return history_; }

 private:
  std::vector<TargetDecl> decls_;
  std::vector<std::string> history_;
};

// Everything a frame's passes need from the host. Passes take what they use.
struct FrameInputs {
  int frame = 0;                    // index in the camera path
  FrameUniforms uniforms;           // camera, sun, sky, resolution
  std::vector<SamplePush> samples;  // the surface pass draws one per sample (>= 1)
  glm::vec2 jitter_px{0.0f};        // this frame's sub-pixel jitter (one-sample schedules; TAA)
  bool camera_cut = false;          // the path jumps here: temporal passes drop their history
};

// The targets of a built graph, by name. `previous` selects last frame's image
// of a history target; for a target without history it is the same image.
// `slot` (0 or 1) names one of a history target's two images directly, for
// passes that prepare a descriptor set per slot in setup().
class TargetSet {
 public:
  virtual ~TargetSet() = default;
  virtual const Image2D& image(const std::string& name) const = 0;
  virtual const Image2D& previous(const std::string& name) const = 0;
  virtual const Image2D& slot(const std::string& name, int slot) const = 0;
  // Which slot is "current" in this frame (0 or 1); 0 for targets without history.
  virtual int current_slot(const std::string& name) const = 0;
  // False in the first frame after build() or reset_history(): the history
  // holds nothing yet.
  virtual bool history_valid(const std::string& name) const = 0;
  // The graph's size (its output resolution); a target's own is its image's (image(name).width()).
  virtual int width() const = 0;
  virtual int height() const = 0;
};

class Pass {
 public:
  virtual ~Pass() = default;
  virtual std::string name() const = 0;
  virtual void declare(PassIO& io) const = 0;
  // Called once after the graph allocated every target: build framebuffers,
  // descriptor sets and pipelines that refer to them.
  virtual void setup(const TargetSet& targets) = 0;
  // Records this frame's commands. The graph has already transitioned every
  // declared target; the pass must not submit. It may write its own
  // host-visible buffers (the previous frame has completed).
  virtual void record(VkCommandBuffer cmd, const FrameInputs& in, const TargetSet& targets) = 0;
  // Drops temporal state the pass keeps outside graph targets (graph histories
  // are invalidated by the graph itself).
  virtual void reset_history() {}
};

}  // namespace glintlab::core

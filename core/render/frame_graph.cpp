#include "core/render/frame_graph.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace glintlab::core {

namespace {

bool is_depth(VkFormat f) { return (aspects_of(f) & VK_IMAGE_ASPECT_DEPTH_BIT) != 0; }

// Where an image must be (layout) and what touches it (stages, accesses) for
// one use inside a pass.
struct UseState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags stages = VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT;
  VkAccessFlags access = 0;
};

constexpr VkAccessFlags kWriteAccess = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                       VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;

UseState required_state(TargetUse use, bool writes) {
  switch (use) {
    case TargetUse::ColorAttachment:
      return {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
              VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT};
    case TargetUse::DepthAttachment:
      return {VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
              VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
    case TargetUse::Sampled:
      return {VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
              VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT};
    case TargetUse::Storage:
      return {VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
              VkAccessFlags(VK_ACCESS_SHADER_READ_BIT) | (writes ? VkAccessFlags(VK_ACCESS_SHADER_WRITE_BIT) : VkAccessFlags(0))};
  }
  return {};
}

VkImageUsageFlags usage_bit(TargetUse use) {
  switch (use) {
    case TargetUse::ColorAttachment: return VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    case TargetUse::DepthAttachment: return VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    case TargetUse::Sampled: return VK_IMAGE_USAGE_SAMPLED_BIT;
    case TargetUse::Storage: return VK_IMAGE_USAGE_STORAGE_BIT;
  }
  return 0;
}

}  // namespace

struct FrameGraph::Impl final : TargetSet {
  struct Target {
    std::string name;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageUsageFlags usage = 0;
    std::string writer;
    bool history = false;
    Image2D img[2];
    UseState state[2];
    int current = 0;
    bool valid = false;     // history: the previous image holds last frame's value
    int w = 0, h = 0;       // its size
    Buffer staging;         // readback targets only
    bool readback = false;
  };

  const VkContext& ctx;
  int w, h;
  std::vector<std::unique_ptr<Pass>> passes;
  std::vector<PassIO> io;
  std::map<std::string, Target> targets;
  std::vector<std::string> readback;
  QueryPool queries;
  bool built = false;

  Impl(const VkContext& c, int width, int height) : ctx(c), w(width), h(height) {}

  const Target& find(const std::string& name) const {
    auto it = targets.find(name);
    if (it == targets.end()) throw std::invalid_argument("frame graph: no target named \"" + name + "\"");
    return it->second;
  }
  Target& find(const std::string& name) { return const_cast<Target&>(std::as_const(*this).find(name)); }

  // TargetSet
  const Image2D& image(const std::string& name) const override {
    const Target& t = find(name);
    return t.img[t.current];
  }
  const Image2D& previous(const std::string& name) const override {
    const Target& t = find(name);
    return t.history ? t.img[1 - t.current] : t.img[0];
  }
  const Image2D& slot(const std::string& name, int s) const override {
    const Target& t = find(name);
    return t.img[t.history ? (s & 1) : 0];
  }
  int current_slot(const std::string& name) const override { return find(name).current; }
  bool history_valid(const std::string& name) const override {
    const Target& t = find(name);
    return t.history && t.valid;
  }
  int width() const override { return w; }
  int height() const override { return h; }

  // Moves image `slot` of `t` into `want`, with a barrier when the layout
  // changes or either side writes. `discard`: old contents may be dropped.
  void transition_to(VkCommandBuffer cmd, Target& t, int slot, const UseState& want, bool discard) {
    UseState& cur = t.state[slot];
    const bool hazard = (cur.access & kWriteAccess) || (want.access & kWriteAccess);
    if (cur.layout == want.layout && !hazard) {
      cur.stages |= want.stages;
      cur.access |= want.access;
      return;
    }
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.oldLayout = discard ? VK_IMAGE_LAYOUT_UNDEFINED : cur.layout;
    b.newLayout = want.layout;
    b.srcAccessMask = cur.access & kWriteAccess;
    b.dstAccessMask = want.access;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = t.img[slot].handle();
    b.subresourceRange = {t.img[slot].aspect(), 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, cur.stages, want.stages, 0, 0, nullptr, 0, nullptr, 1, &b);
    cur = want;
  }
};

FrameGraph::FrameGraph(const VkContext& ctx, int width, int height)
    : impl_(std::make_unique<Impl>(ctx, width, height)), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw std::invalid_argument("frame graph: resolution " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1..16384");
}

FrameGraph::~FrameGraph() = default;

Pass& FrameGraph::add(std::unique_ptr<Pass> pass) {
  if (impl_->built) throw std::logic_error("frame graph: add() after build()");
  impl_->passes.push_back(std::move(pass));
  return *impl_->passes.back();
}

void FrameGraph::build(const std::vector<std::string>& readback) {
  Impl& g = *impl_;
  if (g.built) throw std::logic_error("frame graph: build() twice");
  // Writers first (a history target may be read as "previous" before its writer runs).
  for (auto& p : g.passes) {
    PassIO io;
    p->declare(io);
    for (const TargetDecl& d : io.decls()) {
      if (!d.writes) continue;
      auto [it, fresh] = g.targets.try_emplace(d.name);
      Impl::Target& t = it->second;
      if (!fresh)
        throw std::invalid_argument("frame graph: target \"" + d.name + "\" is written by both pass \"" + t.writer +
                                    "\" and pass \"" + p->name() + "\"");
      t.name = d.name;
      t.format = d.format;
      t.w = d.width > 0 ? d.width : g.w;
      t.h = d.height > 0 ? d.height : g.h;
      if (t.w > 16384 || t.h > 16384)
        throw std::invalid_argument("frame graph: target \"" + d.name + "\" is larger than 16384 pixels");
      t.writer = p->name();
      t.usage |= usage_bit(d.use);
    }
    for (const std::string& hname : io.history()) g.targets.at(hname).history = true;
    g.io.push_back(std::move(io));
  }
  // Reads: the writer must run earlier in the frame, or the read is of last
  // frame's value of a history target.
  for (size_t i = 0; i < g.passes.size(); ++i) {
    for (const TargetDecl& d : g.io[i].decls()) {
      Impl::Target* t = g.targets.count(d.name) ? &g.targets.at(d.name) : nullptr;
      const std::string who = "frame graph: pass \"" + g.passes[i]->name() + "\" ";
      if (!t) throw std::invalid_argument(who + "reads \"" + d.name + "\", which no pass writes");
      t->usage |= usage_bit(d.use);
      if (d.writes) continue;
      if (d.previous) {
        if (!t->history)
          throw std::invalid_argument(who + "reads the previous \"" + d.name + "\", which is not kept across frames");
        continue;
      }
      bool earlier = false;
      for (size_t k = 0; k < i; ++k)
        if (g.passes[k]->name() == t->writer) earlier = true;
      if (!earlier)
        throw std::invalid_argument(who + "reads \"" + d.name + "\" before its writer \"" + t->writer + "\" runs");
    }
  }
  for (const std::string& name : readback) {
    if (!g.targets.count(name)) throw std::invalid_argument("frame graph: read-back target \"" + name + "\" is not declared");
    Impl::Target& t = g.targets.at(name);
    if (is_depth(t.format)) throw std::invalid_argument("frame graph: depth target \"" + name + "\" cannot be read back");
    t.readback = true;
    t.usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  }
  g.readback = readback;
  for (auto& [name, t] : g.targets) {
    for (int s = 0; s < (t.history ? 2 : 1); ++s)
      t.img[s] = Image2D(g.ctx, uint32_t(t.w), uint32_t(t.h), t.format, t.usage, 1, aspects_of(t.format));
    if (t.readback) t.staging = make_readback_buffer(g.ctx, t.img[0]);
  }
  if (g.ctx.timestamps_supported() && !g.passes.empty()) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = uint32_t(2 * g.passes.size());
    VkQueryPool qp;
    vk_check(vkCreateQueryPool(g.ctx.device(), &qi, nullptr, &qp), "vkCreateQueryPool");
    g.queries = QueryPool(g.ctx.device(), qp);
  }
  g.built = true;
  for (auto& p : g.passes) p->setup(g);
}

FrameResult FrameGraph::execute(const FrameInputs& in) {
  Impl& g = *impl_;
  if (!g.built) throw std::logic_error("frame graph: execute() before build()");
  if (in.camera_cut) reset_history();
  const uint32_t nq = uint32_t(2 * g.passes.size());
  g.ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    if (g.queries.get()) vkCmdResetQueryPool(cmd, g.queries.get(), 0, nq);
    for (size_t i = 0; i < g.passes.size(); ++i) {
      for (const TargetDecl& d : g.io[i].decls()) {
        Impl::Target& t = g.targets.at(d.name);
        const int slot = d.previous ? 1 - t.current : t.current;
        // A history image that was never written holds nothing to keep.
        const bool discard = d.writes ? d.discard : (d.previous && !t.valid);
        g.transition_to(cmd, t, t.history ? slot : 0, required_state(d.use, d.writes), discard);
      }
      if (g.queries.get())
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, g.queries.get(), uint32_t(2 * i));
      g.passes[i]->record(cmd, in, g);
      if (g.queries.get())
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g.queries.get(), uint32_t(2 * i + 1));
    }
    for (const std::string& name : g.readback) {
      Impl::Target& t = g.targets.at(name);
      g.transition_to(cmd, t, t.current,
                      {VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT},
                      false);
      // The staging buffer is reused every frame: the host read of the last
      // frame finished before this submission (submit_and_wait).
      record_readback(cmd, t.img[t.current], t.staging);
    }
  });

  FrameResult out;
  for (const std::string& name : g.readback) {
    Impl::Target& t = g.targets.at(name);
    const Image2D& img = t.img[t.current];
    Image im;  // not Image(w, h, c): its zero-filled pixels would be overwritten at once
    im.width = t.w;
    im.height = t.h;
    im.channels = int(channel_count(img.format()));
    im.data = unpack_readback(img, t.staging);
    out.images[name] = std::move(im);
  }
  std::vector<uint64_t> ts(nq, 0);
  if (g.queries.get() && nq > 0)
    vk_check(vkGetQueryPoolResults(g.ctx.device(), g.queries.get(), 0, nq, ts.size() * sizeof(uint64_t), ts.data(),
                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
             "vkGetQueryPoolResults");
  const uint32_t bits = g.ctx.timestamp_valid_bits();
  const uint64_t mask = bits >= 64 ? ~uint64_t(0) : ((uint64_t(1) << bits) - 1);
  auto ms = [&](uint64_t a, uint64_t b) { return double((b - a) & mask) * g.ctx.timestamp_period_ns() * 1e-6; };
  for (size_t i = 0; i < g.passes.size(); ++i)
    out.timings.push_back({g.passes[i]->name(), g.queries.get() ? ms(ts[2 * i], ts[2 * i + 1]) : 0.0});
  if (g.queries.get() && nq > 0) out.gpu_ms = ms(ts[0], ts[nq - 1]);

  for (auto& [name, t] : g.targets)
    if (t.history) {
      t.current = 1 - t.current;
      t.valid = true;
    }
  return out;
}

void FrameGraph::reset_history() {
  for (auto& [name, t] : impl_->targets) t.valid = false;
  for (auto& p : impl_->passes) p->reset_history();
}

const TargetSet& FrameGraph::targets() const { return *impl_; }

std::vector<std::string> FrameGraph::pass_names() const {
  std::vector<std::string> out;
  for (const auto& p : impl_->passes) out.push_back(p->name());
  return out;
}

}  // namespace glintlab::core

#include "experiments/sources/file_sources.h"

#include "metrics/optical_flow.h"

#include <cmath>
#include <future>

namespace glintlab {

namespace {

// Reads frame k + 1 on a thread of its own as soon as frame k is handed out; a frame other than the
// one read ahead is read at once.
template <class T>
class ReadAhead {
 public:
  template <class Read>
  T get(int k, int count, Read read) {
    T value = pending_k_ == k ? pending_.get() : read(k);
    if (pending_.valid()) pending_.wait();
    pending_k_ = -1;
    if (k + 1 < count) start(k + 1, read);
    return value;
  }
  template <class Read>
  void start(int k, Read read) {
    if (pending_.valid()) pending_.wait();
    pending_ = std::async(std::launch::async, read, k);
    pending_k_ = k;
  }

 private:
  std::future<T> pending_;
  int pending_k_ = -1;
};

SourceFrame from_colour_frame(ColourFrame&& cf, const std::string& path) {
  SourceFrame f;
  f.image = std::make_shared<const Image>(std::move(cf.image));
  f.scan = cf.scan;
  f.wall_ms = cf.read_ms;
  f.gpu_ms = std::nan("");
  f.where = " ('" + path + "')";
  return f;
}

class FileSequence final : public ColourSource {
 public:
  FileSequence(const FrameFiles& files, const metrics::ColorManager& cm, const std::string& space)
      : files_(files), cm_(cm), space_(space) {}
  SourceFrame frame(int k) override {
    return ahead_.get(k, int(files_.paths.size()), [this](int j) { return read(size_t(j)); });
  }
  void read_ahead(int k) override { ahead_.start(k, [this](int j) { return read(size_t(j)); }); }

 private:
  SourceFrame read(size_t k) const {
    return from_colour_frame(read_colour_frame(files_, k, cm_, space_), files_.paths[k]);
  }
  const FrameFiles files_;
  const metrics::ColorManager& cm_;
  const std::string space_;
  ReadAhead<SourceFrame> ahead_;
};

Image mean_of_halves(const Image& a, const Image& b) {
  Image m = a;
  for (size_t i = 0; i < m.data.size(); ++i) m.data[i] = 0.5f * (a.data[i] + b.data[i]);
  return m;
}

metrics::PixelScan combined_scan(const metrics::PixelScan& a, const metrics::PixelScan& b) {
  metrics::PixelScan s = a;
  s.nan += b.nan;
  s.pos_inf += b.pos_inf;
  s.neg_inf += b.neg_inf;
  s.infinite += b.infinite;
  s.negative += b.negative;
  return s;
}

class FileReference final : public ColourSource {
 public:
  FileReference(const FrameFiles& files, const std::optional<FrameFiles>& half_b, const metrics::ColorManager& cm,
                const std::string& space, const metrics::FrameMetrics* prepare_with, bool several)
      : files_(files), half_b_(half_b), cm_(cm), space_(space), fm_(prepare_with), several_(several) {}
  SourceFrame frame(int k) override {
    return ahead_.get(k, int(files_.paths.size()), [this](int j) { return read(size_t(j)); });
  }
  void read_ahead(int k) override { ahead_.start(k, [this](int j) { return read(size_t(j)); }); }

 private:
  SourceFrame read(size_t k) const {
    ColourFrame a = read_colour_frame(files_, k, cm_, space_);
    if (!half_b_) {
      SourceFrame f = from_colour_frame(std::move(a), files_.paths[k]);
      if (fm_) f.prepared = fm_->prepare(f.image, several_);
      return f;
    }
    ColourFrame b = read_colour_frame(*half_b_, k, cm_, space_);
    ColourFrame mean{combined_scan(a.scan, b.scan), mean_of_halves(a.image, b.image), a.read_ms + b.read_ms};
    SourceFrame f = from_colour_frame(std::move(mean), files_.paths[k]);
    f.half_a = std::make_shared<const Image>(std::move(a.image));
    f.half_b = std::make_shared<const Image>(std::move(b.image));
    if (fm_) {
      f.half_a_prepared = fm_->prepare(f.half_a, false);
      f.prepared = fm_->prepare(f.image, several_);
    }
    return f;
  }

  const FrameFiles files_;
  const std::optional<FrameFiles> half_b_;
  const metrics::ColorManager& cm_;
  const std::string space_;
  const metrics::FrameMetrics* fm_;
  const bool several_;
  ReadAhead<SourceFrame> ahead_;
};

// The vectors of a frame and, where the files have them, its vectors to the next frame (the next
// frame's disocclusion test reads them).
struct VectorFrame {
  MotionFrame m;
  std::shared_ptr<const Image> forward;
};

class FileMotion final : public MotionSource {
 public:
  FileMotion(const ChannelFiles& vectors, const std::optional<ChannelFiles>& depth, MotionConvention convention,
             const MotionChannels& channels)
      : vectors_(vectors), depth_(depth), convention_(convention), channels_(channels) {}

  MotionFrame frame(int k, const std::shared_ptr<const Image>&) override {
    // Frame k's disocclusion reads frame k - 1's vectors to the next frame: frames are read in order,
    // the next one as soon as this one is (with this one's forward vectors).
    std::shared_ptr<const Image> before = k == last_k_ + 1 ? forward_ : nullptr;
    VectorFrame v = pending_k_ == k ? pending_.get() : read(size_t(k), before);
    if (pending_.valid()) pending_.wait();
    pending_k_ = -1;
    last_k_ = k;
    forward_ = v.forward;
    if (k + 1 < int(vectors_.paths.size())) start(k + 1, forward_);
    return std::move(v.m);
  }
  void read_ahead(int k) override { start(k, nullptr); }

 private:
  void start(int k, std::shared_ptr<const Image> before) {
    if (pending_.valid()) pending_.wait();
    pending_ = std::async(std::launch::async, [this, k, before] { return read(size_t(k), before); });
    pending_k_ = k;
  }

  VectorFrame read(size_t k, const std::shared_ptr<const Image>& prev_forward) const {
    VectorFrame out;
    Image raw = read_frame_channels(vectors_.paths[k], vectors_.channels);
    if (is_flicker_motion(convention_, channels_)) {
      out.m.motion = std::move(raw);  // glintlab's own four channels: already what the tracker reads
    } else {
      MotionVectors v = convert_motion(convention_, raw, channels_);
      std::optional<Image> depth;
      if (depth_) depth = read_frame_channels(depth_->paths[k], depth_->channels);
      out.m.motion = flicker_motion(v, depth ? &*depth : nullptr, prev_forward.get());
      if (v.forward) out.forward = std::make_shared<const Image>(std::move(*v.forward));
    }
    const Image& m = out.m.motion;
    for (size_t i = 0; i < m.pixel_count(); ++i)
      out.m.nonfinite += !(std::isfinite(m.data[4 * i]) && std::isfinite(m.data[4 * i + 1]));
    return out;
  }

  const ChannelFiles vectors_;
  const std::optional<ChannelFiles> depth_;
  const MotionConvention convention_;
  const MotionChannels channels_;
  std::future<VectorFrame> pending_;
  int pending_k_ = -1, last_k_ = -2;
  std::shared_ptr<const Image> forward_;
};

class EstimatedMotion final : public MotionSource {
 public:
  EstimatedMotion(int width, int height) : width_(width), height_(height) {}
  bool needs_base() const override { return true; }
  MotionFrame frame(int k, const std::shared_ptr<const Image>& base) override {
    MotionFrame m;
    if (k > 0 && k == prev_k_ + 1 && prev_ && base) {
      metrics::FlowOptions flow;
      flow.channel = 1;  // Y of XYZ
      flow.forward_backward = true;
      m.motion = metrics::estimate_motion(*prev_, *base, flow);
    } else {
      m.motion = Image(width_, height_, 4, 1.0f);
      for (size_t i = 0; i < m.motion.pixel_count(); ++i) m.motion.data[4 * i] = m.motion.data[4 * i + 1] = 0.0f;
    }
    prev_ = base;
    prev_k_ = k;
    return m;
  }

 private:
  const int width_, height_;
  std::shared_ptr<const Image> prev_;
  int prev_k_ = -2;
};

}  // namespace

std::unique_ptr<ColourSource> file_sequence(const FrameFiles& files, const metrics::ColorManager& cm,
                                            const std::string& space) {
  return std::make_unique<FileSequence>(files, cm, space);
}

std::unique_ptr<ColourSource> file_reference(const FrameFiles& files, const std::optional<FrameFiles>& half_b,
                                             const metrics::ColorManager& cm, const std::string& space,
                                             const metrics::FrameMetrics* prepare_with, bool several) {
  return std::make_unique<FileReference>(files, half_b, cm, space, prepare_with, several);
}

std::unique_ptr<MotionSource> file_motion(const ChannelFiles& vectors, const std::optional<ChannelFiles>& depth,
                                          MotionConvention convention, const MotionChannels& channels) {
  return std::make_unique<FileMotion>(vectors, depth, convention, channels);
}

std::unique_ptr<MotionSource> estimated_motion(int width, int height) {
  return std::make_unique<EstimatedMotion>(width, height);
}

}  // namespace glintlab

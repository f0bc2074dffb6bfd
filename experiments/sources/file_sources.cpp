#include "experiments/sources/file_sources.h"

#include "metrics/optical_flow.h"

#include <cmath>
#include <functional>
#include <future>

namespace glintlab {

namespace {

// One frame read on a thread of its own, ahead of the loop's asking for it: take(k) gives frame k, the
// one read ahead where it is k, else reads it at once (a frame read ahead and not asked for is dropped).
template <class T>
class ReadAhead {
 public:
  template <class Read>
  T take(int k, Read read) {
    T value = pending_k_ == k ? pending_.get() : read(k);
    if (pending_.valid()) pending_.wait();
    pending_k_ = -1;
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

// A colour sequence, or a truth (in two halves where `half_b` is given), read ahead.
class FileColour final : public ColourSource {
 public:
  FileColour(const FrameFiles& files, const std::optional<FrameFiles>& half_b, const metrics::ColorManager& cm,
                const std::string& space, const metrics::FrameMetrics* prepare_with, bool several)
      : files_(files), half_b_(half_b), cm_(cm), space_(space), fm_(prepare_with), several_(several) {}
  SourceFrame frame(int k) override {
    SourceFrame f = ahead_.take(k, reader());
    if (k + 1 < int(files_.paths.size())) ahead_.start(k + 1, reader());
    return f;
  }
  void read_ahead(int k) override { ahead_.start(k, reader()); }

 private:
  std::function<SourceFrame(int)> reader() const {
    return [this](int j) { return read(size_t(j)); };
  }
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
    VectorFrame v = ahead_.take(k, reader(k == last_k_ + 1 ? forward_ : nullptr));
    last_k_ = k;
    forward_ = v.forward;
    if (k + 1 < int(vectors_.paths.size())) ahead_.start(k + 1, reader(forward_));
    return std::move(v.m);
  }
  void read_ahead(int k) override { ahead_.start(k, reader(nullptr)); }

 private:
  // Reads a frame whose predecessor's vectors to the next frame are `before`.
  std::function<VectorFrame(int)> reader(std::shared_ptr<const Image> before) const {
    return [this, before](int j) { return read(size_t(j), before); };
  }

  VectorFrame read(size_t k, const std::shared_ptr<const Image>& prev_forward) const {
    VectorFrame out;
    Image raw = read_sequence_channels(vectors_.paths, vectors_.array.get(), k, vectors_.channels);
    if (is_flicker_motion(convention_, channels_)) {
      out.m.motion = std::move(raw);  // glintlab's own four channels: already what the tracker reads
    } else {
      MotionVectors v = convert_motion(convention_, raw, channels_);
      std::optional<Image> depth;
      if (depth_) depth = read_sequence_channels(depth_->paths, depth_->array.get(), k, depth_->channels);
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
  ReadAhead<VectorFrame> ahead_;
  int last_k_ = -2;
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
  return std::make_unique<FileColour>(files, std::nullopt, cm, space, nullptr, false);
}

std::unique_ptr<ColourSource> file_reference(const FrameFiles& files, const std::optional<FrameFiles>& half_b,
                                             const metrics::ColorManager& cm, const std::string& space,
                                             const metrics::FrameMetrics* prepare_with, bool several) {
  return std::make_unique<FileColour>(files, half_b, cm, space, prepare_with, several);
}

std::unique_ptr<MotionSource> file_motion(const ChannelFiles& vectors, const std::optional<ChannelFiles>& depth,
                                          MotionConvention convention, const MotionChannels& channels) {
  return std::make_unique<FileMotion>(vectors, depth, convention, channels);
}

std::unique_ptr<MotionSource> estimated_motion(int width, int height) {
  return std::make_unique<EstimatedMotion>(width, height);
}

}  // namespace glintlab

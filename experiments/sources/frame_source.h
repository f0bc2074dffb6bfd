// What the frame loop (experiments/runner/frame_loop.h) asks for frame k: a
// source of colour frames (a variant or a truth) and a source of motion. A
// renderer is one kind of source (rendered_sources.h: a variant's frame graph,
// a truth from the reference cache or rendered, the motion pass), files are
// another (file_sources.h: a sequence with its decode-ahead, a truth given as
// one sequence or two halves, vectors from files or optical flow). Everything
// after the frame — metrics, records, journal, writers — is the loop's and
// does not know which kind it was given.
//
// The loop asks every source for its frames in increasing order; a source may
// read ahead (file sources decode frame k + 1 while frame k is measured).
#pragma once

#include "core/render/frame_graph.h"
#include "core/util/image.h"
#include "metrics/frame_metrics.h"
#include "metrics/pixel_scan.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace glintlab {

// One frame of a colour source, in the run's working space.
struct SourceFrame {
  std::shared_ptr<const Image> image;
  metrics::PixelScan scan;               // its NaN / Inf / negative pixels
  double wall_ms = 0;                    // to render (record, submit, wait, read back) or to read
  double gpu_ms = 0;                     // NaN for frames read from files
  std::vector<core::PassTiming> passes;  // per render pass
  // A truth only:
  bool cached = false;   // loaded from the reference cache
  bool rebuilt = false;  // its cache entry was corrupt and it was rendered again
  // The truth's two independent halves, where it has them (the image is then their estimate together),
  // from which every metric's noise floor is measured.
  std::shared_ptr<const Image> half_a, half_b;
  // The metrics' view of the image and of half A where the source prepared them ahead (on its reading
  // thread); else the loop prepares them.
  std::optional<metrics::FrameMetrics::Reference> prepared, half_a_prepared;
  std::string where;  // what a warning names: "" for a rendered frame, "('path')" for a file
};

class ColourSource {
 public:
  virtual ~ColourSource() = default;
  virtual SourceFrame frame(int k) = 0;
  virtual int samples_per_pixel() const { return 0; }  // 0: read, not rendered
  // Starts reading frame k now, for a source that reads ahead (the run's first frame, while the journal
  // is opened).
  virtual void read_ahead(int /*k*/) {}
};

// The motion of frame k in glintlab's convention (4 channels: the vector to the previous frame in
// pixels, the distance now, the distance in the previous frame; core/render/surface_pass.h).
struct MotionFrame {
  Image motion;
  size_t nonfinite = 0;  // pixels whose vector is NaN or Inf (counted; the flicker tracker masks them)
};

class MotionSource {
 public:
  virtual ~MotionSource() = default;
  // `base`: the base sequence's frame k (the truth, or the first variant where there is none), for a
  // source that estimates the motion from the images; null where needs_base() is false.
  virtual MotionFrame frame(int k, const std::shared_ptr<const Image>& base) = 0;
  virtual bool needs_base() const { return false; }
  virtual void read_ahead(int /*k*/) {}  // as ColourSource::read_ahead
};

}  // namespace glintlab

// Frame sources that read files (experiments/sources/frame_source.h): a colour
// sequence, a truth given as one sequence or as two independent halves, the
// motion vectors (and depth) another renderer wrote, or optical flow where it
// wrote none. Each decodes its next frame on a thread of its own while the
// loop measures the current one. Any of them may hold its frames in memory
// instead (FrameArray: the Python module's arrays), read in place.
#pragma once

#include "experiments/sources/motion_convention.h"
#include "experiments/sources/sequence.h"
#include "experiments/sources/frame_source.h"
#include "metrics/color/color_manager.h"
#include "metrics/frame_metrics.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace glintlab {

// A sequence of vectors or depth: its selected frames' files (or its array) and the channels read of
// each.
struct ChannelFiles {
  std::string what;  // for messages: "--motion", "--depth"
  SequenceSpec seq;
  std::vector<std::string> paths;     // the selected frames, in order (an array's frame names)
  std::vector<std::string> channels;  // what is read of each frame
  std::shared_ptr<const FrameArray> array;  // the frames in memory; null: read from `paths`
};

// A colour sequence, each frame converted from its space into `space`.
std::unique_ptr<ColourSource> file_sequence(const FrameFiles& files, const metrics::ColorManager& cm,
                                            const std::string& space);

// A truth read from files, converted into `space`. With `half_b` it is given as two independent halves
// (`files` is half A): the truth is their mean, channel by channel (in CIE XYZ, where the mean of two
// estimates of light is the estimate of their samples together), and a defect in either half is a
// defect of the truth. With `prepare_with` the metrics' views of the truth (`several`: measured by
// several variants) and of half A are prepared on the reading thread too.
std::unique_ptr<ColourSource> file_reference(const FrameFiles& files, const std::optional<FrameFiles>& half_b,
                                             const metrics::ColorManager& cm, const std::string& space,
                                             const metrics::FrameMetrics* prepare_with, bool several);

// The vectors of `vectors` in `convention`, with `depth` where given, made into glintlab's motion (the
// disocclusion from the distances, depth or the vectors to the next frame: motion_convention.h).
std::unique_ptr<MotionSource> file_motion(const ChannelFiles& vectors, const std::optional<ChannelFiles>& depth,
                                          MotionConvention convention, const MotionChannels& channels);

// Optical flow (OpenCV DIS, forward-backward consistency) of the base sequence's Y channel, from the
// frame before; the first frame, and one whose predecessor was not asked for, has zero motion.
std::unique_ptr<MotionSource> estimated_motion(int width, int height);

}  // namespace glintlab

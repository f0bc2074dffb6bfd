// What a run must do at each frame when part of the work is done already
// (--resume: records in the journal) or belongs to other shards (--shard k/n
// takes the frames [k F / n, (k + 1) F / n)). Temporal state makes this more
// than a filter: a variant's TAA history and its flicker tracker at frame t
// depend on every earlier frame, so
//   emit    = its frames in this shard's range that the journal lacks;
//   render  = every frame up to its last emitted one (TAA history is rebuilt
//             exactly; reference frames are not needed for it); a variant
//             read from files has no history: only its measured frames;
//   measure = the emitted frames and the frame before each (the flicker
//             tracker compares a frame with its predecessor; it restarts where
//             the measured frames have a gap).
// A resumed or sharded run therefore records exactly the numbers an
// uninterrupted run would.
#pragma once

#include "experiments/runner/journal.h"
#include "experiments/runner/plan.h"

#include <vector>

namespace glintlab {

struct WorkSchedule {
  int frame_begin = 0, frame_end = 0;  // this shard's frames
  int last_frame = -1;                 // the loop runs frames 0..last_frame
  std::vector<std::vector<char>> render, measure, emit;  // [variant][frame]
  std::vector<char> motion;                              // [frame]: the motion pass runs
  std::vector<std::vector<char>> reference;              // [reference][frame]: the reference is needed
  size_t emitted_frames() const;
};

// The frame range of shard k of n over `frames` frames.
std::pair<int, int> shard_range(int frames, int shard_index, int shard_count);

WorkSchedule schedule_work(const RunPlan& plan, const Journal& journal, int frame_begin, int frame_end);

}  // namespace glintlab

// `glintlab measure`: the run's measurements for frames glintlab did not
// render. A test sequence is a variant whose frames come from files; the
// reference, the motion vectors and the depth come from files too (or the
// vectors are estimated by optical flow). Everything after reading is the
// run's own machinery: one FrameRecord per test and frame into the journal
// (DIR/records.jsonl, so --resume works as for `run`), then frames.csv,
// summary.json (schema glintlab-summary/1, the tests as variants) and the
// report from the journal, so `check` and `report` work unchanged.
//
// Frames of all sequences are matched by frame number; every file is checked
// from its header (size, channels, pixel count) and hashed before a pixel is
// measured, and the hashes go into the journal header, so a resume with other
// files is refused. Any input may be frames in memory instead (FrameArray),
// hashed likewise.
#pragma once

#include <climits>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

struct FrameArray;  // experiments/sources/sequence.h

constexpr double kMinFps = 1e-3, kMaxFps = 1000;  // --fps: one frame in 1000 s to 1000 frames a second

struct MeasureSource {
  std::string name;  // the variant name ("" = from the sequence's path)
  std::string seq;   // SEQ (experiments/sources/sequence.h)
  std::string space;  // its OCIO space ("" = MeasureOptions::space)
  std::shared_ptr<const FrameArray> array;  // its frames in memory instead of `seq` (read in place)
};

struct MeasureOptions {
  std::string reference;  // SEQ; "" = no reference (flicker_contrast of each test alone)
  std::string reference_space;  // its OCIO space ("" = space)
  // SEQ of the reference's second half: the reference is then given as two independent estimates of the
  // truth (half A = `reference`, half B this, each of half the samples, in the same space); the truth
  // measured against is their mean (in CIE XYZ) and every metric of B against A gives its noise floor.
  // "" = no halves: no floor.
  std::string reference_b;
  std::vector<MeasureSource> tests;
  std::string out_dir;
  std::string motion;                       // SEQ of motion vectors
  std::string motion_from;                  // "reference" | "test" (the first test's files) | ""
  std::string motion_convention = "pixels";
  std::string depth;                        // SEQ of depth (one channel: Z, Y, R or the layer's)
  std::string space;                        // OCIO space of every input; "" = file tag, else scene_linear
  std::vector<std::string> metrics;         // per-pixel metrics and groups (select_metrics); empty = deltaE2000, flip
  int first = INT_MIN, last = INT_MAX;      // --frames FIRST:LAST (frame numbers, inclusive)
  double fps = 24.0;                        // time_s = (frame index) / fps, in [kMinFps, kMaxFps]
  std::string name = "measure";             // the summary's "experiment" (what `check` matches)
  std::string file;                         // the experiment file, for a frames-only experiment
  std::string display, view;                // previews ("" = the defaults of an experiment's "output")
  double exposure = 0.0;
  std::string ocio_config;                  // "" = $OCIO, else the shipped config
  bool resume = false;
  bool report = true;
  // Frames in memory instead of files (the Python module's arrays; sequence.h FrameArray): the reference
  // (RGB, or Y), the vectors (channels named as the convention's files name them) and the depth (Z), each
  // instead of its SEQ. An array's frame k is the run's frame k; with any array, --frames is not allowed.
  std::shared_ptr<const FrameArray> reference_array, motion_array, depth_array;
};

// Exit codes as every command (experiments/cli/exit_codes.h): 0, 1 when a
// frame (test or reference) had NaN/Inf/negative pixels, 2 bad input.
int measure_sequences(const MeasureOptions& options, std::ostream& log);

}  // namespace glintlab

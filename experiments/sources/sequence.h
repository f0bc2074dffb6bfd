// Image sequences of any renderer, as `glintlab measure` and experiment files
// with "frames": SEQ name them. A SEQ is
//   - a folder of numbered frames (every regular image file in it whose name
//     holds a frame number; one sequence per folder: several prefixes are an
//     error that names them),
//   - a pattern with a printf field (`beauty.%04d.exr`, `%d`) or a run of '#'
//     (`beauty.####.exr`: one digit a '#', zero-padded, the convention of
//     Blender and Nuke; wider numbers are written in full, as printf does),
//   - either one followed by `:LAYER`, a layer of a multi-layer OpenEXR
//     (`shots/beauty.####.exr:ViewLayer.Combined`): the channels `LAYER.R`,
//     `LAYER.G`, ... of the file.
// Frames are matched across sequences by frame number. Everything is checked
// from the files' headers before a pixel is read: every frame exists and is a
// regular file, one size for the whole sequence, the channels asked for exist
// (the error lists those the file has), and no header claims more than
// kMaxSequencePixels pixels.
#pragma once

#include "core/util/image.h"
#include "metrics/color/color_manager.h"
#include "metrics/color/image_io.h"
#include "metrics/pixel_scan.h"

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

// Largest image a header may claim before anything is allocated (64 Mpix:
// 8K UHD is 33 Mpix). Larger is bad input (exit 2), not an allocation failure.
constexpr std::int64_t kMaxSequencePixels = metrics::kMaxImagePixels;
constexpr int kMaxSequenceFrames = 100000;

struct SequenceSpec {
  std::string text;     // as given
  std::string pattern;  // printf pattern with one %0Nd field ("" for a folder until listed)
  std::string layer;    // "" = the file's plain channels
};

// Splits "PATH[:LAYER]" (the layer is the part after the last ':' when it
// holds no '/'; a path that exists as given has no layer). Throws ConfigError.
SequenceSpec parse_sequence(const std::string& text, const std::string& what);

struct SequenceFrame {
  int number = 0;
  std::string path;
};

// The frames of a sequence, ascending by number. A folder is scanned for one
// numbered sequence. Throws ConfigError: no frame, not a folder or a pattern,
// several sequences in one folder, a path that is not a regular file.
std::vector<SequenceFrame> list_frames(const SequenceSpec& seq, const std::string& what);

// "1 frame, 4" or "3 frames, 4 to 6" (for messages).
std::string frame_count_text(size_t count, int first, int last);

// The files of the frames with these numbers, in that order: ConfigError naming the first missing one.
std::vector<std::string> frame_paths(const SequenceSpec& seq, const std::vector<int>& numbers, const std::string& what);

// Header facts of one frame file.
struct FrameHeader {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // every channel name of every part, in file order
  std::string colorspace;             // oiio:ColorSpace ("" if none)
};
// Opens only regular files; a header above kMaxSequencePixels, an unreadable
// or non-image file is an error naming the file (ConfigError for content,
// IoError for the system's reason).
FrameHeader read_frame_header(const std::string& path);

// The channel names that `layer` + one of `names` give in `header`, in the
// order of `names` (each entry of `names` is a list of accepted spellings,
// e.g. {"R", "r", "red"}); an empty result entry means that one is absent.
std::vector<std::string> find_channels(const FrameHeader& header, const std::string& layer,
                                       const std::vector<std::vector<std::string>>& names);
// "R, G, B, A, ViewLayer.Vector.X, ..." (for error messages).
std::string channel_list(const FrameHeader& header);

// Reads the named channels of a frame (any part of a multi-part file) as a
// float image with channels in the given order; `image_channels` more than
// the names gives an image that wide, the channels after the names 1 (an
// alpha). Throws ConfigError / IoError naming the file.
Image read_frame_channels(const std::string& path, const std::vector<std::string>& channels,
                          int image_channels = 0);

// A colour frame: R, G, B of the layer (grey Y copied to all three; alpha 1);
// the error lists the channels the file has when none fit.
std::vector<std::string> colour_channels(const FrameHeader& header, const std::string& layer,
                                         const std::string& path);

// Frames held in memory instead of files (the Python module's numpy arrays): T x H x W x C float32,
// C-contiguous, read in place (never copied, never written) while the run lasts. `channels` names its
// C channels as a file's would be named (R, G, B, A; Y; X, Y; Z), so an array is read by the same
// channel rules as a file; frame k of an array is the run's frame k.
struct FrameArray {
  std::string name;  // what messages and the journal call it: "array test1"
  const float* data = nullptr;
  int frames = 0, height = 0, width = 0;
  std::vector<std::string> channels;
};
// A frame's header (`name`: its file or array frame) against the run: its size, which is the run's
// (or sets it, where *width is 0), and every channel read of it present. ConfigError naming `what`.
void check_frame_header(const FrameHeader& h, const std::vector<std::string>& channels, const std::string& what,
                        const std::string& name, int* width, int* height);
// An array of `count` frames, the run's: ConfigError naming `what` otherwise.
void check_array_frames(const FrameArray& a, size_t count, const std::string& what);
// An array's "header" (its size and channel names), as read_frame_header gives a file's.
FrameHeader array_header(const FrameArray& a);
// The name of frame k of an array in messages: "array test1, frame 3".
std::string array_frame_name(const FrameArray& a, size_t k);
// XXH3-128 of an array's shape, channel names and values: its identity in a journal header, as
// file_content_hash is a file's.
std::string array_content_hash(const FrameArray& a);

// A colour sequence ready to read: its frames' files (or its array), the channels read of each and
// the OCIO space its values are in.
struct FrameFiles {
  std::string seq;                    // as given (an array's name)
  std::vector<std::string> paths;     // one per frame, in order (an array's frame names)
  std::vector<std::string> channels;  // R, G, B of the layer (or Y three times)
  std::string space;                  // OCIO colour space (canonical name)
  std::shared_ptr<const FrameArray> array;  // the frames in memory; null: read from `paths`
};
// Frame `index` of a sequence: the named channels of its file, or of its array where `array` is set
// (read_frame_channels' rules for the channels after the names).
Image read_sequence_channels(const std::vector<std::string>& paths, const FrameArray* array, size_t index,
                             const std::vector<std::string>& channels, int image_channels = 0);
// The frames of `seq` with the given numbers (each must exist), every header checked (size
// width x height, or the first frame's size when width is 0, which is then set; the channels),
// the space: `forced` ("" = the first frame's tag, else scene_linear, said on `log`).
// Throws ConfigError naming `what`.
FrameFiles open_colour_sequence(const std::string& seq, const std::vector<int>& numbers, const std::string& forced,
                                const metrics::ColorManager& cm, const std::string& what, int* width, int* height,
                                std::ostream& log);
// The same for frames in memory: `count` frames of the array, every one of size width x height (set
// from the array when width is 0), its channels those of a colour frame, its space `forced` ("" =
// scene_linear, said on `log`). Throws ConfigError naming `what`.
FrameFiles open_colour_array(std::shared_ptr<const FrameArray> array, size_t count, const std::string& forced,
                             const metrics::ColorManager& cm, const std::string& what, int* width, int* height,
                             std::ostream& log);
// The numbers of the first `count` frames of `seq` (ConfigError when it has fewer, or a gap among them).
std::vector<int> first_frame_numbers(const std::string& seq, int count, const std::string& what);

// A colour frame as read: its values in its own space scanned for NaN/Inf/negative (3 channels),
// then converted through OCIO into `to_space`, RGBA with alpha 1.
struct ColourFrame {
  metrics::PixelScan scan;
  Image image;
  double read_ms = 0;
};
ColourFrame read_colour_frame(const FrameFiles& f, size_t index, const metrics::ColorManager& cm,
                              const std::string& to_space);

// XXH3-128 of a file's bytes (32 hex digits): what a journal header records of every input file,
// so a resume or merge with changed files is refused. Throws IoError.
std::string file_content_hash(const std::string& path);

}  // namespace glintlab

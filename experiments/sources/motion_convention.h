// Motion vectors in the conventions renderers write, converted once, at the
// edge, into glintlab's: v = p_t − p_{t−1} in pixels, +x right, +y down (the
// previous frame's point of pixel p is p − v). Everything after the edge (the
// flicker tracker, the motion check) sees only glintlab's convention.
//
// | name      | channels                      | units   | stored vector           | y axis | source |
// | --------- | ----------------------------- | ------- | ----------------------- | ------ | ------ |
// | `pixels`  | R,G [+ B,A distances], or X,Y (no distances) | pixels  | p_t − p_{t−1}           | down   | glintlab's own motion target (shaders/common/motion.glsl); B = the surface's distance now (0 = none), A = its distance in frame t−1 |
// | `blender` | X,Y,Z,W of the Vector pass    | pixels  | XY: p_{t−1} − p_t (to the previous frame); ZW: p_t − p_{t+1} (the offset to the next frame, negated) | up | measured on a Cycles render of Debian's Blender 3.4 (tests/data/blender): against the camera path's own motion, XY matches p_{t−1} − p_t with y up to 0.016 px RMS, every y-down or other-sign reading is ≥ 1.05 px off |
// | `unreal`  | R,G (or X,Y) of the velocity  | NDC [−1, 1] per axis | p_t − p_{t−1} (ScreenPos − PrevScreenPos) | up | UE4/5 velocity pass, decoded (not the 16-bit encoding with its 0.5 offset): an assumption from its shader source, checked only by the mirror test |
// | `unity`   | R,G of the motion-vector texture | UV [0, 1] per axis | p_t − p_{t−1} | up | Unity's DepthTextureMode.MotionVectors ("screen-space pixel motion encoded in UV space"); sign and y axis are assumptions (its shaders subtract the previous clip position), checked only by the mirror test |
//
// A convention whose channels the file lacks is an error listing the
// channels the file has. Which frame the vectors point to, their sign and
// their y axis are facts to verify, not to trust: the motion check
// (metrics/motion_check.h) compares them with their mirror images on every run.
#pragma once

#include "core/util/image.h"
#include "core/util/named_enum.h"
#include "experiments/sources/sequence.h"

#include <optional>
#include <string>
#include <vector>

namespace glintlab {

enum class MotionConvention { Pixels, Blender, Unreal, Unity };
inline constexpr EnumTable<MotionConvention, 4> kMotionConventionNames{{
    {MotionConvention::Pixels, "pixels"},
    {MotionConvention::Blender, "blender"},
    {MotionConvention::Unreal, "unreal"},
    {MotionConvention::Unity, "unity"},
}};

// The layer names (last component) that hold vectors in a convention's files,
// for --motion-from when no layer is named: Blender "Vector", Unreal
// "Velocity"/"MotionVectors", Unity "MotionVectors", glintlab "motion".
const std::vector<std::string>& motion_layer_names(MotionConvention c);

// Which channels of a frame file hold the vectors (and, for `pixels`, the
// distances): throws ConfigError naming the file, the convention and the
// channels the file has when they are not there.
struct MotionChannels {
  std::vector<std::string> backward;   // 2: the vector to the previous frame
  std::vector<std::string> forward;    // 2 or empty: the vector to the next frame
  std::vector<std::string> distances;  // 2 or empty (pixels): distance now, distance in frame t-1
};
MotionChannels motion_channels(MotionConvention c, const FrameHeader& header, const std::string& layer,
                               const std::string& path);

// A frame's vectors in glintlab's convention: `backward` 2 channels (v =
// p_t − p_{t−1}), `forward` 2 channels (p_{t+1} − p_t) where the renderer
// wrote them, `distances` 2 channels where it wrote glintlab's.
struct MotionVectors {
  Image backward;
  std::optional<Image> forward;
  std::optional<Image> distances;
};
// `raw`: the channels of motion_channels() in that order (backward, forward, distances).
MotionVectors convert_motion(MotionConvention c, const Image& raw, const MotionChannels& channels);
// Whether files of convention c with these channels hold the flicker's motion image as they are:
// `pixels` with glintlab's distances (R, G, B, A) and no other vector. Then
// flicker_motion(convert_motion(c, raw, channels), any depth, any forward) == raw, bit for bit, and
// the frame is not converted.
bool is_flicker_motion(MotionConvention c, const MotionChannels& channels);
// The inverse (tests and `run`'s motion output): glintlab vectors written in convention c, channels
// in motion_channels() order for that convention (forward and distances when given).
Image to_convention(MotionConvention c, const MotionVectors& v);

// The 4-channel motion image the flicker tracker reads (metrics/flicker.h:
// xy = v, z = distance now (0 = no surface), w = distance in frame t−1, < 0 =
// masked), from what a sequence gives:
//   distances (glintlab's own): as the renderer wrote them, exactly;
//   depth (depth_now; its previous frame is read by the tracker from the
//     previous motion image's z): z = w = depth_now(p), so the tracker's test
//     |depth_{t−1}(p − v) − depth_t(p)| <= tolerance · depth_t(p) masks a
//     point that was hidden; depth <= 0, non-finite or >= kDepthBackground is
//     background (Cycles writes 1e10 where no surface is);
//   forward vectors of frame t−1 (prev_forward): forward-backward consistency
//     (Sundaram, Brox & Keutzer 2010, eq. 5): masked where
//     |v + ŵ|² > 0.01 (|v|² + |ŵ|²) + 0.5, ŵ = −forward_{t−1}(p − v) bilinear;
//   neither: z = w = 1, so only points that come from off-screen are masked.
constexpr double kDepthBackground = 1e9;
Image flicker_motion(const MotionVectors& v, const Image* depth_now, const Image* prev_forward);

}  // namespace glintlab

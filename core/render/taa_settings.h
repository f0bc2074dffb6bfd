// Every design choice of the TAA resolve (core/render/taa_pass.h) as an
// experiment option, under a variant's "taa" object. Each enum has one name
// table (the JSON values). Defaults are Falcor's TAA pass
// (RenderPasses/Antialiasing/TAA: Halton(2,3) x16 jitter, alpha 0.1, clamp to
// mean +- 1.0 sigma over 3x3 in YCgCo, Catmull-Rom history, the longest
// motion vector in 3x3, Karis' alpha' = alpha d / (d + box range) near the
// box edge, no HDR weighting, no depth test). Options beyond Falcor, all off by
// default: `dering`, `anti_flicker`, `disocclusion`, and the glint-aware ones below (`accumulate`,
// `reactive`, `glint_layer`, `glint_lock`), which read the glint layer the
// surface pass writes (core/render/surface_pass.h, option `glint`).
#pragma once

#include "core/render/sample_schedule.h"
#include "core/util/named_enum.h"

namespace glintlab::core {

// History rectification.
enum class TaaClamp {
  None,      // no rectification (ghosts; converges to the mean under a static camera)
  MinMax,    // clamp to the 3x3 min/max box (UE4's "YCoCg min/max box")
  Clip,      // clip toward the box centre (INSIDE, Playdead's temporal reprojection)
  Variance,  // clamp to mean +- gamma sigma over 3x3 (Salvi 2016; Falcor gamma 1.0, UE4 1.25)
};
inline constexpr EnumTable<TaaClamp, 4> kTaaClampNames{{
    {TaaClamp::None, "none"}, {TaaClamp::MinMax, "minmax"}, {TaaClamp::Clip, "clip"}, {TaaClamp::Variance, "variance"}}};

// The colour space of the neighbourhood box.
enum class TaaSpace { Rgb, YCoCg };
inline constexpr EnumTable<TaaSpace, 2> kTaaSpaceNames{{{TaaSpace::Rgb, "rgb"}, {TaaSpace::YCoCg, "ycocg"}}};

// How the history is resampled at the reprojected position.
enum class TaaHistoryFilter {
  Bilinear,    // 4 taps
  CatmullRom,  // Falcor's Catmull-Rom (Falcor: 9 bilinear taps, Jimenez/vec3.ca; here its 16 texels)
};
inline constexpr EnumTable<TaaHistoryFilter, 2> kTaaHistoryFilterNames{
    {{TaaHistoryFilter::Bilinear, "bilinear"}, {TaaHistoryFilter::CatmullRom, "catmull_rom"}}};

// Which motion vector reprojects the pixel.
enum class TaaVelocity {
  Center,        // the pixel's own
  ClosestDepth,  // of the nearest surface in 3x3 (INSIDE)
  Longest,       // the longest in 3x3 (Falcor)
};
inline constexpr EnumTable<TaaVelocity, 3> kTaaVelocityNames{
    {{TaaVelocity::Center, "center"}, {TaaVelocity::ClosestDepth, "closest_depth"}, {TaaVelocity::Longest, "longest"}}};

// The weight of the current frame in the blend.
enum class TaaFeedback {
  Fixed,  // alpha
  Luma,   // INSIDE / Lottes: history weight lerp(0.88, 0.97, (1 - |L0 - L1| / max(L0, L1, 0.2))^2)
  Karis,  // Falcor: alpha' = alpha d / (d + box range), d = luma distance of the history to the nearer box edge
};
inline constexpr EnumTable<TaaFeedback, 3> kTaaFeedbackNames{
    {{TaaFeedback::Fixed, "fixed"}, {TaaFeedback::Luma, "luma"}, {TaaFeedback::Karis, "karis"}}};

// HDR handling: samples are mapped before the neighbourhood statistics and the
// blend, and the result is mapped back.
enum class TaaHdr {
  None,         // linear radiance
  InverseLuma,  // c / (1 + L) (Karis 2014, "High-quality temporal supersampling"): weights 1 / (1 + L)
  Tonemap,      // FSR2: c / (max(r, g, b) + 1), inverted after accumulating
};
inline constexpr EnumTable<TaaHdr, 3> kTaaHdrNames{
    {{TaaHdr::None, "none"}, {TaaHdr::InverseLuma, "inverse_luma"}, {TaaHdr::Tonemap, "tonemap"}}};

// How the glint layer's history is rectified (option `glint_layer`).
enum class TaaGlintClamp {
  None,    // not at all: the glint layer accumulates along the motion like a clamp-free TAA
  MinMax,  // to the min/max box of the 3x3 current glint layer (its own neighbourhood, not the colour's)
};
inline constexpr EnumTable<TaaGlintClamp, 2> kTaaGlintClampNames{
    {{TaaGlintClamp::None, "none"}, {TaaGlintClamp::MinMax, "minmax"}}};

struct TaaSettings {
  JitterSequence jitter = JitterSequence::Halton16;
  double alpha = 0.1;  // weight of the current frame, (0, 1]
  TaaClamp clamp = TaaClamp::Variance;
  double gamma = 1.0;  // variance box half-width in sigmas
  TaaSpace space = TaaSpace::YCoCg;
  TaaHistoryFilter history_filter = TaaHistoryFilter::CatmullRom;
  // Clamp the Catmull-Rom history to the range of the 2x2 texels around the
  // reprojected point (FSR2's deringing of its Lanczos history). Without it
  // the filter's negative lobes ring next to a bright HDR glint: the history
  // falls to 0 (it is floored there), the variance box of a glinting
  // neighbourhood is too wide to lift it, and black pixels appear beside
  // glints (seen in the default experiment, whose TAA variants turn it on).
  // Off by default so that the defaults stay Falcor's exactly. No effect with
  // the bilinear filter, which cannot overshoot.
  bool dering = false;
  TaaVelocity velocity = TaaVelocity::Longest;
  TaaFeedback feedback = TaaFeedback::Karis;
  TaaHdr hdr = TaaHdr::None;
  // A luma-oscillation guard (FSR2 "luma instability", UE5 TSR
  // "ShadingRejection.Flickering"): pixels whose luma alternated in sign over
  // the last frames keep more of their unrectified history.
  bool anti_flicker = false;
  // The disocclusion test (not in Falcor's pass, which relies on the rectification alone): the
  // history restarts where the nearest surface of the pixel's 3x3 was not where the history holds it
  // (passes/taa.frag, same_surface: FSR2's dilated depth and reconstructed previous depth, the
  // history's point-sampled distance read where the jittered sample saw the point, and an allowance
  // of the local slope of the distance so that jitter and motion within one surface do not restart).
  bool disocclusion = false;
  // With `disocclusion`: the relative distance mismatch, beyond the slope allowance, that restarts.
  double disocclusion_tolerance = 0.05;

  // ---- glint-aware options (passes/taa.frag's header states each mapping)
  // Accumulation schedule: the current frame's weight is max(alpha', 1/n), n the frames accumulated
  // at the pixel since the last reset or disocclusion (a per-pixel count kept with the history), so a
  // static view averages its first 1/alpha frames with equal weights, as supersampling does, instead
  // of weighting them exponentially (Yang et al. 2009, "Amortized supersampling", and every
  // progressive path tracer's running mean).
  bool accumulate = false;
  // Reactive mask from the material (FSR2's reactive mask, computed here rather than authored): with
  // r = reactive x the pixel's glint share (the glint term's share of its luma), the history weight
  // falls to (1 - r) of its value and the rectified history moves toward the unrectified one by r.
  double reactive = 0.0;
  // Layer separation: the glint term is resolved apart from the rest. The colour without its glints
  // goes through the resolve above (its box statistics then see no glints); the glint layer is
  // reprojected with the same vectors, filter and validity, rectified by `glint_clamp`, blended with
  // its own weight `glint_alpha` (with `accumulate`: max(glint_alpha, 1/n)) and added back.
  bool glint_layer = false;
  double glint_alpha = 0.5;
  TaaGlintClamp glint_clamp = TaaGlintClamp::None;
  // Glint locks (after FSR2's locks on thin features): where the current pixel is mostly glint (share
  // > 1/2) and the reprojected history is at least half as bright (the glint persisted along the
  // motion), the history is not rectified.
  bool glint_lock = false;

  // The resolve reads the surface pass's glint layer.
  bool reads_glints() const { return reactive > 0.0 || glint_layer || glint_lock; }
  // The resolve keeps a second history target (taa.extra: the glint layer's history, the count n).
  bool keeps_extra() const { return accumulate || glint_layer; }
};

}  // namespace glintlab::core

// Sub-pixel sample positions: the fixed stratified patterns of supersampling
// and the reference, and the per-frame jitter sequences of TAA. Offsets are in
// pixels in [-0.5, 0.5)^2 around the pixel centre (core/scene/camera.h: +x
// right, +y down).
#pragma once

#include "core/render/frame_uniforms.h"
#include "core/util/named_enum.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace glintlab::core {

class CameraPath;

// Offsets of an n x n stratified grid, each jittered inside its stratum by a
// fixed-seed generator (reproducible; the same pattern in every frame).
std::vector<glm::vec2> stratified_offsets(int n, uint32_t seed);

// TAA jitter sequences (one offset per frame, cycling).
enum class JitterSequence { None, Halton8, Halton16, Halton32, R2, HaltonFsr2 };
inline constexpr EnumTable<JitterSequence, 6> kJitterNames{{
    {JitterSequence::None, "none"},          // pixel centres
    {JitterSequence::Halton8, "halton8"},    // Halton(2,3), 8 per cycle (UE4's default count)
    {JitterSequence::Halton16, "halton16"},  // Halton(2,3), 16 per cycle (INSIDE, Falcor)
    {JitterSequence::Halton32, "halton32"},  // Halton(2,3), 32 per cycle
    {JitterSequence::R2, "r2"},              // Roberts' R2 low-discrepancy sequence (no cycle)
    // Halton(2,3) with 8 / s^2 per cycle at render scale s, rounded down (FSR 2's documentation, "Camera
    // jitter": 8 (display width / render width)^2 phases, 18, 23, 32 and 72 for its four modes); the
    // default of a render-scaled TAA.
    {JitterSequence::HaltonFsr2, "halton_fsr2"},
}};

// The phase count of halton_fsr2 at render scale s (the ratio of render to display width, in (0, 1]).
int fsr2_jitter_phases(double render_scale);

// Radical inverse of `index` in `base` (Halton 1964): index 1, 2, 3 in base 2
// give 1/2, 1/4, 3/4.
double radical_inverse(uint32_t index, uint32_t base);

// The jitter of frame `frame` (>= 0). Halton uses indices 1..N (index 0 would
// be the corner (0, 0) of every cycle); R2 is x_n = frac(1/2 + n (1/g, 1/g^2))
// with g the plastic number (Roberts 2018).
// halton_fsr2 takes the render scale (its phase count); the others ignore it.
glm::vec2 jitter_offset(JitterSequence sequence, int frame, double render_scale = 1.0);

// One sample per offset, each with the camera of `frame` jittered by it and
// weight 1 / offsets.size().
std::vector<SamplePush> samples_for(const CameraPath& path, int frame, int width, int height,
                                    const std::vector<glm::vec2>& offsets);

}  // namespace glintlab::core

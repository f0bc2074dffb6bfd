// Real spherical harmonics up to l = 2 and the irradiance environment map of Ramamoorthi &
// Hanrahan 2001 ("An efficient representation for irradiance environment maps").
//
// The Kajs eq. 4.2 sky term L_sky^Ω(x, Ω) -- the average of sky radiance over directions drawn
// in the hemisphere around n -- is, for cosine-distributed directions, E(n) / π with the
// irradiance E(n) = ∫ L(ω) max(0, n·ω) dω. E is smooth, so l <= 2 holds it to a few percent
// (R&H 2001 sec. 2.2).
//
// Basis order and constants (the GLSL in shaders/common/environment.glsl uses the same), with
// d = (x, y, z) the world direction (+Y up; the order is the usual one with the *formula's*
// z-axis, it is just a basis and need not be the up axis):
//   0: 0.282095                 1: 0.488603 y      2: 0.488603 z      3: 0.488603 x
//   4: 1.092548 x y             5: 1.092548 y z    6: 0.315392 (3 z² - 1)
//   7: 1.092548 x z             8: 0.546274 (x² - y²)
#pragma once

#include "core/scene/environment.h"

#include <glm/glm.hpp>

#include <array>

namespace glintlab::core {

using SH9 = std::array<glm::vec3, 9>;

// Y_i(d) for i = 0..8 (d unit).
std::array<double, 9> sh_basis(glm::dvec3 d);

// L_lm = ∫ L(ω) Y_lm(ω) dω of a lat-long map taken as piecewise constant per texel; the basis is
// integrated exactly over each texel (solid angle sin θ dθ dφ, closed forms in cos θ and φ), so a
// constant map gives exactly its band-0 term.
SH9 project_sh(const LatLong& map);

// Convolution with the clamped cosine (R&H 2001 eq. 8): E_lm = Â_l L_lm,
// Â_0 = π, Â_1 = 2π/3, Â_2 = π/4.
SH9 convolve_clamped_cosine(const SH9& L_lm);

// E(n) = Σ E_lm Y_lm(n) (R&H 2001 eq. 7), n need not be unit (must be non-zero); clamped to >= 0
// per channel (an l <= 2 fit may ring slightly negative behind a very bright lobe). Divide by π
// for the Kajs L_sky^Ω.
glm::vec3 eval_sh_irradiance(const SH9& E_lm, glm::vec3 n);

}  // namespace glintlab::core

// fp64 twin of shaders/sand/specular_aa.glsl (geometric specular anti-aliasing, the material option
// "specular_aa"), written from the papers' equations as that file states them: the kernel's alpha^2
// per axis and the widened glint_alpha (alpha_g widened, alpha_l kept).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace glintlab::reference {

// The methods as SAND_SPECULAR_AA numbers them (core::SandSpecularAA::define()).
enum class SpecularAA { Kaplanyan2016 = 1, Tokuyoshi2019 = 2, Tokuyoshi2021 = 3 };

struct SpecularAAInput {
  glm::dvec3 dn_dx{0.0}, dn_dy{0.0};  // screen derivatives of the unit macro normal
  glm::dvec2 dh_dx{0.0}, dh_dy{0.0};  // of the half vector in the method's domain (slope p; projected q)
};

// The kernel's alpha^2 per axis, clamped to kappa (a NaN kernel counts as kappa).
glm::dvec2 specular_aa_kernel(SpecularAA method, const SpecularAAInput& d, double sigma2, double kappa);

// glint_alpha = (alpha_g (t, b), alpha_l / alpha_g (t, b)) widened; unchanged where dn/dx = dn/dy = 0.
glm::dvec4 specular_aa_glint_alpha(SpecularAA method, const glm::dvec4& glint_alpha, const SpecularAAInput& d,
                                   double sigma2, double kappa);

}  // namespace glintlab::reference

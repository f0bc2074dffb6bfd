#include "core/testkit/specular_aa_fp64.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace glintlab::reference {

glm::dvec2 specular_aa_kernel(SpecularAA method, const SpecularAAInput& d, double sigma2, double kappa) {
  glm::dvec2 k{0.0};
  switch (method) {
    case SpecularAA::Kaplanyan2016:  // the slope-domain bounding rectangle b, alpha^2 += 2 sigma^2 b^2
      for (int i = 0; i < 2; ++i) {
        const double b = std::fabs(d.dh_dx[i]) + std::fabs(d.dh_dy[i]);
        k[i] = 2.0 * sigma2 * b * b;
      }
      break;
    case SpecularAA::Tokuyoshi2019: {  // 2 sigma^2 (|dn/dx|^2 + |dn/dy|^2) in both axes
      const double n2 = glm::dot(d.dn_dx, d.dn_dx) + glm::dot(d.dn_dy, d.dn_dy);
      k = glm::dvec2(2.0 * sigma2 * n2);
      break;
    }
    case SpecularAA::Tokuyoshi2021:  // the diagonal of 2 Sigma (eq. 3)
      for (int i = 0; i < 2; ++i) k[i] = 2.0 * sigma2 * (d.dh_dx[i] * d.dh_dx[i] + d.dh_dy[i] * d.dh_dy[i]);
      break;
  }
  for (int i = 0; i < 2; ++i) k[i] = std::isnan(k[i]) ? kappa : std::min(k[i], kappa);
  return k;
}

glm::dvec4 specular_aa_glint_alpha(SpecularAA method, const glm::dvec4& glint_alpha, const SpecularAAInput& d,
                                   double sigma2, double kappa) {
  if (d.dn_dx == glm::dvec3(0.0) && d.dn_dy == glm::dvec3(0.0)) return glint_alpha;
  const glm::dvec2 k = specular_aa_kernel(method, d, sigma2, kappa);
  glm::dvec4 out = glint_alpha;
  for (int i = 0; i < 2; ++i) {
    const double a = glint_alpha[i], a2 = a * a;
    double wide;
    if (method == SpecularAA::Tokuyoshi2021) {
      const double ap = a2 / std::max(1.0 - a2, 1e-6) + k[i];  // eq. 4 and the diagonal of eq. 6
      wide = std::sqrt(ap / (1.0 + ap));                        // eq. 7
    } else {
      wide = std::sqrt(std::min(a2 + k[i], 1.0));
    }
    wide = std::max(wide, a);
    out[i] = wide;
    out[2 + i] = glint_alpha[2 + i] * (a / wide);  // alpha_l = alpha_g * relative roughness, kept
  }
  return out;
}

}  // namespace glintlab::reference

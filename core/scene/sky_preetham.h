// Preetham, Shirley & Smits 1999, "A practical analytic model for daylight": the Perez et al. 1993
// all-weather sky distribution with turbidity-fitted coefficients for luminance Y and CIE 1931
// chromaticity x, y (paper sec. 3.1 and appendix A.2). Sky only: no sun disk, no aerial
// perspective. Valid for turbidity in [1.7, 10] (the paper's fit range) and the sun at or above
// the horizon; directions below the horizon are the caller's business (core/scene/environment.h).
#pragma once

#include <glm/glm.hpp>

namespace glintlab::core {

class PreethamSky {
 public:
  // `to_sun`: unit direction towards the sun, +Y up, to_sun.y >= 0. Throws std::invalid_argument
  // outside the valid range.
  PreethamSky(double turbidity, glm::dvec3 to_sun);

  // Perez et al. 1993 distribution F(θ, γ) = (1 + A e^{B / cos θ}) (1 + C e^{D γ} + E cos² γ),
  // θ = zenith angle of the view direction, γ = angle between view and sun.
  static double perez(const double coeff[5], double cos_theta, double gamma);

  // CIE xyY of direction `dir` (unit, dir.y >= 0 is the sky; below is evaluated at the horizon),
  // with Y relative to the zenith: Y(zenith) = 1 (Preetham eq. Y = Y_z F(θ,γ) / F(0,θ_s)).
  glm::dvec3 xyY(glm::dvec3 dir) const;
  // Same as CIE XYZ (X = x/y Y, Z = (1-x-y)/y Y).
  glm::dvec3 XYZ(glm::dvec3 dir) const;

  // Absolute zenith luminance Y_z in kcd/m² and zenith chromaticity (x_z, y_z) (Preetham app. A.2).
  double zenith_luminance_kcd() const { return Y_z_; }
  glm::dvec2 zenith_chromaticity() const { return {x_z_, y_z_}; }
  double sun_zenith_angle() const { return theta_s_; }

 private:
  double T_, theta_s_;
  glm::dvec3 to_sun_;
  double cY_[5], cx_[5], cy_[5];
  double Y_z_, x_z_, y_z_;
};

}  // namespace glintlab::core

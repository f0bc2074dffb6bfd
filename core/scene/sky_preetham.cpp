#include "core/scene/sky_preetham.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace glintlab::core {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Preetham et al. 1999 appendix A.2: Perez coefficients as linear functions of turbidity T,
// rows A..E, columns (slope, offset).
constexpr double kPerezY[5][2] = {{0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251}, {0.1206, -2.5771}, {-0.0670, 0.3703}};
constexpr double kPerezx[5][2] = {{-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125}, {-0.0641, -0.8989}, {-0.0033, 0.0452}};
constexpr double kPerezy[5][2] = {{-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102}, {-0.0441, -1.6537}, {-0.0109, 0.0529}};
// Zenith chromaticity: x_z = [T², T, 1] M [θ_s³, θ_s², θ_s, 1]ᵀ (appendix A.2).
constexpr double kZenithx[3][4] = {{0.00166, -0.00375, 0.00209, 0.0}, {-0.02903, 0.06377, -0.03202, 0.00394}, {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double kZenithy[3][4] = {{0.00275, -0.00610, 0.00317, 0.0}, {-0.04214, 0.08970, -0.04153, 0.00516}, {0.15346, -0.26756, 0.06670, 0.26688}};

double zenith_chroma(const double m[3][4], double T, double th) {
  double t[3] = {T * T, T, 1.0}, a[4] = {th * th * th, th * th, th, 1.0};
  double s = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) s += t[i] * m[i][j] * a[j];
  return s;
}
}  // namespace

PreethamSky::PreethamSky(double turbidity, glm::dvec3 to_sun) : T_(turbidity) {
  if (!(turbidity >= 1.7 && turbidity <= 10.0))
    throw std::invalid_argument("Preetham sky: turbidity " + std::to_string(turbidity) + " outside [1.7, 10]");
  double len = glm::length(to_sun);
  if (!(len > 0.0) || !std::isfinite(len)) throw std::invalid_argument("Preetham sky: sun direction is zero or not finite");
  to_sun_ = to_sun / len;
  if (to_sun_.y < -1e-6)
    throw std::invalid_argument("Preetham sky: the sun is below the horizon (the model is fitted for sun elevations >= 0)");
  theta_s_ = std::acos(std::clamp(to_sun_.y, 0.0, 1.0));
  for (int i = 0; i < 5; ++i) {
    cY_[i] = kPerezY[i][0] * T_ + kPerezY[i][1];
    cx_[i] = kPerezx[i][0] * T_ + kPerezx[i][1];
    cy_[i] = kPerezy[i][0] * T_ + kPerezy[i][1];
  }
  // Zenith luminance (appendix A.2), kcd/m²: χ = (4/9 - T/120)(π - 2θ_s).
  double chi = (4.0 / 9.0 - T_ / 120.0) * (kPi - 2.0 * theta_s_);
  Y_z_ = (4.0453 * T_ - 4.9710) * std::tan(chi) - 0.2155 * T_ + 2.4192;
  x_z_ = zenith_chroma(kZenithx, T_, theta_s_);
  y_z_ = zenith_chroma(kZenithy, T_, theta_s_);
}

double PreethamSky::perez(const double c[5], double cos_theta, double gamma) {
  // B < 0 over the fitted turbidity range, so e^{B / cos θ} -> 0 at the horizon; clamp the
  // exponent anyway so no input can overflow.
  double ct = std::max(cos_theta, 1e-4);
  double e1 = std::exp(std::min(c[1] / ct, 80.0));
  double e2 = std::exp(std::min(c[3] * gamma, 80.0));
  double cg = std::cos(gamma);
  return (1.0 + c[0] * e1) * (1.0 + c[2] * e2 + c[4] * cg * cg);
}

glm::dvec3 PreethamSky::xyY(glm::dvec3 dir) const {
  double len = glm::length(dir);
  if (!(len > 0.0)) return {x_z_, y_z_, 0.0};
  dir /= len;
  if (dir.y < 0.0) {  // evaluate the horizon at this azimuth
    glm::dvec2 h(dir.x, dir.z);
    double hl = glm::length(h);
    dir = hl > 0.0 ? glm::dvec3(h.x / hl, 0.0, h.y / hl) : glm::dvec3(1.0, 0.0, 0.0);
  }
  double cos_theta = dir.y;
  double gamma = std::acos(std::clamp(glm::dot(dir, to_sun_), -1.0, 1.0));
  // Preetham sec. 3.1: Y = Y_z F(θ, γ) / F(0, θ_s), likewise x and y.
  double Y = perez(cY_, cos_theta, gamma) / perez(cY_, 1.0, theta_s_);
  double x = x_z_ * perez(cx_, cos_theta, gamma) / perez(cx_, 1.0, theta_s_);
  double y = y_z_ * perez(cy_, cos_theta, gamma) / perez(cy_, 1.0, theta_s_);
  return {x, y, std::max(Y, 0.0)};
}

glm::dvec3 PreethamSky::XYZ(glm::dvec3 dir) const {
  glm::dvec3 c = xyY(dir);
  if (!(c.y > 1e-9)) return glm::dvec3(0.0);
  return {c.x / c.y * c.z, c.z, (1.0 - c.x - c.y) / c.y * c.z};
}

}  // namespace glintlab::core

#include "core/scene/spherical_harmonics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace glintlab::core {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Normalisation constants of the real SH (R&H 2001 eq. 3 numerically).
constexpr double kY00 = 0.282094791773878;  // 1 / (2 sqrt(π))
constexpr double kY1 = 0.488602511902920;   // sqrt(3 / 4π)
constexpr double kY2a = 1.092548430592079;  // sqrt(15 / 4π)
constexpr double kY20 = 0.315391565252520;  // sqrt(5 / 16π)
constexpr double kY22 = 0.546274215296040;  // sqrt(15 / 16π)
}  // namespace

std::array<double, 9> sh_basis(glm::dvec3 d) {
  const double x = d.x, y = d.y, z = d.z;
  return {kY00,           kY1 * y,     kY1 * z,
          kY1 * x,        kY2a * x * y, kY2a * y * z,
          kY20 * (3.0 * z * z - 1.0), kY2a * x * z, kY22 * (x * x - y * y)};
}

SH9 project_sh(const LatLong& map) {
  if (map.width <= 0 || map.height <= 0 || map.rgb.size() != size_t(map.width) * size_t(map.height) * 3)
    throw std::invalid_argument("project_sh: lat-long map is empty or its data size does not match width x height x 3");
  const int W = map.width, H = map.height;
  // Direction d = (s cos φ, μ, s sin φ), μ = cos θ, s = sin θ = sqrt(1 - μ²); dω = dμ dφ.
  // Per column: integrals over φ of 1, cos, sin, cos², sin², cos·sin.
  struct Phi { double one, c, s, cc, ss, cs; };
  std::vector<Phi> phi(W);
  for (int i = 0; i < W; ++i) {
    double a = 2.0 * kPi * i / W, b = 2.0 * kPi * (i + 1) / W;
    Phi& p = phi[i];
    p.one = b - a;
    p.c = std::sin(b) - std::sin(a);
    p.s = std::cos(a) - std::cos(b);
    p.cc = 0.5 * (b - a) + 0.25 * (std::sin(2 * b) - std::sin(2 * a));
    p.ss = 0.5 * (b - a) - 0.25 * (std::sin(2 * b) - std::sin(2 * a));
    p.cs = 0.5 * (std::sin(b) * std::sin(b) - std::sin(a) * std::sin(a));
  }
  std::array<glm::dvec3, 9> acc{};
  for (int j = 0; j < H; ++j) {
    // Row j: θ in [jπ/H, (j+1)π/H], μ from m1 = cos θ1 up to m0 = cos θ0.
    double m0 = std::cos(kPi * j / H), m1 = std::cos(kPi * (j + 1) / H);
    if (j == 0) m0 = 1.0;
    if (j == H - 1) m1 = -1.0;
    // Antiderivatives in μ of 1, μ, μ², s, μ s, s² (s = sqrt(1 - μ²)).
    auto S = [](double m) { return std::sqrt(std::max(0.0, 1.0 - m * m)); };
    auto F_s = [&](double m) { return 0.5 * (m * S(m) + std::asin(std::clamp(m, -1.0, 1.0))); };
    auto F_ms = [&](double m) { double s = S(m); return -s * s * s / 3.0; };
    double I1 = m0 - m1;
    double Im = 0.5 * (m0 * m0 - m1 * m1);
    double Imm = (m0 * m0 * m0 - m1 * m1 * m1) / 3.0;
    double Is = F_s(m0) - F_s(m1);
    double Ims = F_ms(m0) - F_ms(m1);
    double Iss = I1 - Imm;
    for (int i = 0; i < W; ++i) {
      const Phi& p = phi[i];
      // ∫ Y_k dω over the texel, with Y_k written in μ, s, φ.
      double B[9] = {kY00 * I1 * p.one,
                     kY1 * Im * p.one,
                     kY1 * Is * p.s,
                     kY1 * Is * p.c,
                     kY2a * Ims * p.c,
                     kY2a * Ims * p.s,
                     kY20 * (3.0 * Iss * p.ss - I1 * p.one),
                     kY2a * Iss * p.cs,
                     kY22 * (Iss * p.cc - Imm * p.one)};
      const float* t = &map.rgb[(size_t(j) * W + i) * 3];
      glm::dvec3 L(t[0], t[1], t[2]);
      for (int k = 0; k < 9; ++k) acc[k] += L * B[k];
    }
  }
  SH9 out;
  for (int k = 0; k < 9; ++k) out[k] = glm::vec3(acc[k]);
  return out;
}

SH9 convolve_clamped_cosine(const SH9& L) {
  // R&H 2001 eq. 8-9: Â_0 = π, Â_1 = 2π/3, Â_2 = π/4.
  const float A[3] = {float(kPi), float(2.0 * kPi / 3.0), float(kPi / 4.0)};
  SH9 E;
  for (int k = 0; k < 9; ++k) E[k] = L[k] * A[k == 0 ? 0 : (k < 4 ? 1 : 2)];
  return E;
}

glm::vec3 eval_sh_irradiance(const SH9& E_lm, glm::vec3 n) {
  double len = glm::length(glm::dvec3(n));
  if (!(len > 0.0)) throw std::invalid_argument("eval_sh_irradiance: zero normal");
  auto Y = sh_basis(glm::dvec3(n) / len);
  glm::dvec3 E(0.0);
  for (int k = 0; k < 9; ++k) E += glm::dvec3(E_lm[k]) * Y[k];
  return glm::vec3(glm::max(E, glm::dvec3(0.0)));
}

}  // namespace glintlab::core

#include "core/testkit/sand_fp64.h"

#include "core/testkit/glint_fp64.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace glintlab::reference::sand {

namespace {
const double kPi = 3.14159265358979323846;
double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }
}  // namespace

Params from_gpu(const core::SandParamsGPU& g) {
  Params p;
  for (int i = 0; i < 8; ++i) p.palette[i] = vec3(g.palette[i][0], g.palette[i][1], g.palette[i][2]);
  p.I_glints = vec3(g.I_glints[0], g.I_glints[1], g.I_glints[2]);
  p.SSS = g.SSS;
  p.R_s = g.R_s;
  p.T = g.T;
  p.R_t = g.R_t;
  p.sigma_g = g.sigma_g;
  p.P = g.P;
  p.noise_scale = g.noise_scale;
  p.noise_scale_f32 = g.noise_scale;
  p.ior = g.ior;
  p.scattering = g.scattering;
  p.absorption = g.absorption;
  p.sigma_on = g.sigma_on;
  p.sig_a = g.sig_a;
  p.sig_b = g.sig_b;
  p.appendix_compat = g.appendix_compat;
  p.fresnel_half_vector = g.fresnel_half_vector;
  p.glint_model = g.glint_model <= kGlintKajs ? g.glint_model : glint::twin_of_gpu(g.glint_model);
  p.energy_consistent = g.energy_consistent;
  p.gpu = g;
  return p;
}

uvec3 pcg3d(uvec3 v) {
  for (auto& c : v) c = c * 1664525u + 1013904223u;  // uint32 wrap-around is defined
  v[0] += v[1] * v[2];
  v[1] += v[2] * v[0];
  v[2] += v[0] * v[1];
  for (auto& c : v) c ^= c >> 16;
  v[0] += v[1] * v[2];
  v[1] += v[2] * v[0];
  v[2] += v[0] * v[1];
  return v;
}

uvec3 grain_cell_key(const std::array<float, 3>& x_obj, float noise_scale) {
  uvec3 k{};
  for (int i = 0; i < 3; ++i) {
    // fp32 product (exact in double, then one rounding to fp32), floored
    float c = std::floor(static_cast<float>(static_cast<double>(x_obj[i]) * static_cast<double>(noise_scale)));
    uint32_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    k[i] = (c == 0.0f) ? 0u : bits;
  }
  return k;
}

GrainRandom grain_random(const uvec3& key, uint32_t compat) {
  uvec3 h = pcg3d(key);
  GrainRandom r;
  if (compat & kCompatRandNormalized) {
    vec3 v(static_cast<int32_t>(h[0]), static_cast<int32_t>(h[1]), static_cast<int32_t>(h[2]));
    double len = std::sqrt(glm::dot(v, v));
    r.xi_pm = len > 0 ? v / len : vec3(0, 0, 1);
    r.xi = (r.xi_pm + 1.0) / 2.0;
  } else {
    for (int i = 0; i < 3; ++i) r.xi[i] = std::ldexp(static_cast<double>(h[i] >> 8), -24);
    r.xi_pm = 2.0 * r.xi - 1.0;
  }
  return r;
}

vec3 sphere_direction(double xi1, double xi2) {
  double phi = 2.0 * kPi * xi1;  // eq. 4.1, c = 0, R = 1
  double s = std::sqrt(std::max(0.0, xi2 * (1.0 - xi2)));
  return vec3(2.0 * std::cos(phi) * s, 2.0 * std::sin(phi) * s, 1.0 - 2.0 * xi2);
}

void frisvad_basis(const vec3& n, vec3& b1, vec3& b2) {
  double sign = n.z >= 0.0 ? 1.0 : -1.0;
  double a = -1.0 / (sign + n.z);
  double b = n.x * n.y * a;
  b1 = vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  b2 = vec3(b, sign + n.y * n.y * a, -n.y);
}

vec3 micro_normal(double xi1, double xi2, const vec3& wo, int& face, double& margin) {
  vec3 q = sphere_direction(xi1, xi2);
  vec3 b1, b2;
  frisvad_basis(q, b1, b2);
  const vec3 normals[6] = {b1, b2, q, -b1, -b2, -q};  // the rotated cube's faces in world space
  double d[6];
  face = 0;
  for (int k = 0; k < 6; ++k) {
    d[k] = glm::dot(wo, normals[k]);
    if (d[k] > d[face]) face = k;
  }
  double second = -1e300;
  for (int k = 0; k < 6; ++k)
    if (k != face) second = std::max(second, d[k]);
  margin = d[face] - second;
  return normals[face];
}

int palette_index(const vec3& xi) {
  int b[3];
  for (int i = 0; i < 3; ++i) b[i] = xi[i] < 0.5 ? 0 : 1;  // eq. 4.3
  return 4 * b[0] + 2 * b[1] + b[2];                       // eq. 4.4
}

vec3 rho_m(const Params& p, int index) { return p.palette[index]; }

vec3 rho_n(const Params& p) {
  vec3 s(0);
  for (const auto& c : p.palette) s += c;
  return s / 8.0;
}

double I_min(double P, double dist) {
  if (!(dist > 0)) return P > 0 ? 0.0 : 1.0;  // limit dist -> 0+
  return clamp01(std::exp(-P / dist));
}

double rho_m_intensity(double I_min_, double xi) { return I_min_ + (1.0 - (xi * (1.0 - I_min_) + I_min_)); }

double rho_n_intensity(double I_min_) { return I_min_ + (1.0 - I_min_) / 2.0; }

double f_s(double scattering, double SSS) { return scattering * SSS; }
double f_e(double absorption, double SSS) { return std::exp(-absorption * SSS); }

vec3 L_d(const vec3& rho, double f_s_, double f_e_, const vec3& L_i, const vec3& L_sky, double cos_ni) {
  vec3 L = rho / kPi * L_i * (f_s_ + (1.0 - f_s_) * cos_ni);
  L = L + rho / kPi * L_sky;
  return f_e_ * L;
}

double fresnel_f0(double ior) { return std::pow((1.0 - ior) / (1.0 + ior), 2.0); }

double schlick(double f0, double cos_ho) { return f0 + (1.0 - f0) * std::pow(1.0 - clamp01(cos_ho), 5.0); }

double fresnel_cos(const vec3& n, const vec3& wi, const vec3& wo, uint32_t mode, uint32_t compat) {
  vec3 h = n;
  if (mode == kFresnelLightView) {
    vec3 s = wi + wo;
    double len = std::sqrt(glm::dot(s, s));
    if (len > 0) h = s / len;
  }
  double c = glm::dot(h, wo);
  return (compat & kCompatFresnelAbs) ? std::min(1.0, std::fabs(c)) : clamp01(c);
}

double F_strength(double R_s) {
  double poly = -20.80 * std::pow(R_s, 5) + 60 * std::pow(R_s, 4) - 55.90 * std::pow(R_s, 3) +
                14.55 * std::pow(R_s, 2) + 2 * R_s + 0.25;
  return std::max(0.0, std::min(1.0, poly));
}

vec3 L_f(double f, const vec3& L_sky, const vec3& L_i, double cos_ni) { return f * (L_sky + L_i * cos_ni); }

double GDF(double x, double sigma) {
  const double mu = 0.0;
  return std::exp(-((x - mu) * (x - mu)) / (2.0 * sigma * sigma));
}

double g_glint(double gdf, const vec3& wo, const vec3& wi, const vec3& m, double cos_ni) {
  vec3 eq418 = wi - 2.0 * m * glm::dot(m, wi);  // as printed; the mirror direction is its negation
  return gdf * std::max(0.0, glm::dot(wo, -eq418)) * cos_ni;
}

double G_strength(double R_s) { return 1.0 / (1.0 + std::exp(13.5 * (R_s - 0.4))); }

vec3 L_g(double g, const vec3& L_i, const vec3& L_sky, const vec3& I_glints, uint32_t compat) {
  vec3 L = (compat & kCompatGlintSky) ? L_sky + L_i : L_i;
  return L * g * I_glints;
}

double T_ext(double T) {
  return clamp01(-3.2 * std::pow(T, 4) + 4.8 * std::pow(T, 3) - 2.2 * std::pow(T, 2) - 0.3 * T + 1.0);
}

double R_t_star(double R_t) { return 0.2 + R_t * (0.4 - 0.2); }
double R_t_strength(double R_t) { return 1.0 - 0.9 * R_t; }

double transmission_t(double T, double R_t, const vec3& n, const vec3& wo, const vec3& wi) {
  double base = 1.0 - std::max(0.0, std::min(1.0, glm::dot(n, wo)));
  return clamp01(R_t_strength(R_t) * T * std::pow(base, 1.0 / R_t_star(R_t)) * std::max(0.0, -glm::dot(wo, wi)));
}

vec3 L_t(const vec3& rho_n_, const vec3& L_i, double t) { return rho_n_ * L_i * t; }

double L_oren(const vec3& n, const vec3& wi, const vec3& wo, double sigma, uint32_t compat) {
  const bool world = compat & kCompatOrenNayarWorld;
  const vec3 N = world ? vec3(0, 0, 1) : n;
  double s2 = sigma * sigma;
  double A = 1.0 - s2 / (2.0 * (s2 + 0.33));
  double B = 0.45 * s2 / (s2 + 0.09);
  // polar angle from N, clamped to [0, pi/2] (|.| about the plane in world mode)
  auto theta = [&](const vec3& w) {
    double th = std::atan2(glm::length(glm::cross(N, w)), glm::dot(N, w));
    if (world) th = std::min(th, kPi - th);
    return std::min(th, kPi / 2);
  };
  double th_i = theta(wi), th_o = theta(wo);
  double cos_i = std::max(0.0, std::cos(th_i)), cos_o = std::max(0.0, std::cos(th_o));
  double sin_i = std::sin(th_i), sin_o = std::sin(th_o);
  // azimuths in a tangent frame of N
  vec3 t1, t2;
  frisvad_basis(N, t1, t2);
  vec3 pi = wi - N * glm::dot(N, wi), po = wo - N * glm::dot(N, wo);
  double cos_dphi = 0.0;
  bool defined = glm::dot(pi, pi) * glm::dot(po, po) > 1e-40 && (!world || (sin_i > 1e-4 && sin_o > 1e-4));
  if (defined) {
    double phi_i = std::atan2(glm::dot(pi, t2), glm::dot(pi, t1));
    double phi_o = std::atan2(glm::dot(po, t2), glm::dot(po, t1));
    cos_dphi = std::cos(phi_i - phi_o);
  }
  // alpha = max(theta_i, theta_o), beta = min: the larger cosine is beta's
  double sin_alpha = cos_i > cos_o ? sin_o : sin_i;
  double sin_beta = cos_i > cos_o ? sin_i : sin_o;
  double cos_beta = std::max(cos_i, cos_o);
  double tan_beta = sin_beta / std::max(cos_beta, 1e-4);  // OREN_NAYAR_MIN_COS of the GLSL
  if (world) tan_beta = clamp01(tan_beta);
  return A + B * std::max(0.0, cos_dphi) * sin_alpha * tan_beta;
}

vec3 L_brdf(const vec3& rho_n_, double f_s_, double f_e_, double L_oren_, double cos_ni, const vec3& L_i,
            const vec3& L_sky, double fresnel_weight, double T_ext_) {
  vec3 L = rho_n_ / kPi * L_i * (f_s_ + (1.0 - f_s_) * L_oren_ * cos_ni);
  L = L + rho_n_ / kPi * L_sky;
  return T_ext_ * (fresnel_weight * (f_e_ * L));
}

vec3 L_far(const vec3& L_brdf_, const vec3& L_f_, const vec3& L_t_, double rho_n_intensity_) {
  return (L_brdf_ + L_f_ + L_t_) * rho_n_intensity_;
}

double sig(double x, double a, double b) { return 0.5 * (1.0 + std::tanh(0.5 * a * (x - b))); }

vec3 L_close(const vec3& L_d_, const vec3& L_s_, const vec3& L_t_, double rho_m_intensity_) {
  return (L_d_ + L_s_ + L_t_) * rho_m_intensity_;
}

vec3 L_final(const vec3& L_close_, const vec3& L_far_, double sig_) { return (1.0 - sig_) * L_close_ + sig_ * L_far_; }

vec3 glint_radiance(const vec3& L_g_, const vec3& L_g_far_, double rho_m_intensity_, double rho_n_intensity_,
                    double sig_) {
  return (1.0 - sig_) * rho_m_intensity_ * L_g_ + sig_ * rho_n_intensity_ * L_g_far_;
}

double glint_share(const vec3& G, const vec3& L_final_) {
  const vec3 w(0.2126, 0.7152, 0.0722);
  const double lf = glm::dot(L_final_, w), lg = glm::dot(G, w);
  return lf > 0.0 ? std::clamp(lg / lf, 0.0, 1.0) : 0.0;
}

double sky_diffuse_scale(uint32_t energy_consistent) { return energy_consistent ? kPi : 1.0; }
double sun_lobe_scale(uint32_t energy_consistent) { return energy_consistent ? 1.0 / kPi : 1.0; }

Terms sand_terms(const Params& p, const Surface& s, const Light& l, const Features& ft) {
  Terms r;
  const uint32_t compat = p.appendix_compat;
  double cos_ni = std::max(0.0, glm::dot(s.n, l.wi));
  const vec3 L_sky_diffuse = l.L_sky_omega * sky_diffuse_scale(p.energy_consistent);
  const vec3 L_i_lobe = l.L_i * sun_lobe_scale(p.energy_consistent);
  const uint32_t model = ft.glints ? p.glint_model : kGlintNone;
  auto glint = [&](uint32_t m, glint::Slack* slack) {
    return glint::glint_term(m, glint::from_gpu(p.gpu), s.uv, s.duv_dx, s.duv_dy, s.t, s.b, s.n, l.wi, s.wo, l.L_i,
                             l.cone, slack);
  };
  r.rho_n = rho_n(p);
  r.I_min = I_min(p.P, s.dist);
  r.rho_n_intensity = rho_n_intensity(r.I_min);
  r.f_s = f_s(p.scattering, p.SSS);
  r.f_e = f_e(p.absorption, p.SSS);
  r.F_Rs = F_strength(p.R_s);
  r.f = r.F_Rs * schlick(fresnel_f0(p.ior), fresnel_cos(s.n, l.wi, s.wo, p.fresnel_half_vector, compat));
  r.L_f = L_f(r.f, l.L_sky_omega, L_i_lobe, cos_ni);
  if (ft.transmission) {
    r.T_ext = T_ext(p.T);
    r.t = transmission_t(p.T, p.R_t, s.n, s.wo, l.wi);
    r.L_t = L_t(r.rho_n, L_i_lobe, r.t);
  }
  if (ft.close) {
    GrainRandom gr = grain_random(grain_cell_key(s.x_obj, p.noise_scale_f32), compat);
    r.xi = gr.xi;
    r.xi_pm = gr.xi_pm;
    r.palette_margin = std::min({std::fabs(gr.xi.x - 0.5), std::fabs(gr.xi.y - 0.5), std::fabs(gr.xi.z - 0.5)});
    r.palette_index = palette_index(gr.xi);
    r.rho_m = rho_m(p, r.palette_index);
    r.rho_m_intensity = rho_m_intensity(r.I_min, (compat & kCompatIntensityXi1) ? gr.xi.x : gr.xi.z);
    r.L_d = L_d(r.rho_m, r.f_s, r.f_e, l.L_i, L_sky_diffuse, cos_ni) * (1.0 - r.f) * r.T_ext;  // eq. 4.24, 4.26
    if (model == kGlintKajs) {
      r.m = micro_normal(gr.xi.x, gr.xi.y, s.wo, r.face, r.face_margin);
      r.gate_x = (compat & kCompatGateXi1) ? gr.xi_pm.x : gr.xi_pm.z;
      r.gdf = GDF(r.gate_x, p.sigma_g);
      r.G_Rs = G_strength(p.R_s);
      r.g = r.G_Rs * g_glint(r.gdf, s.wo, l.wi, r.m, cos_ni);
      double lobe = sun_lobe_scale(p.energy_consistent);
      r.L_g = L_g(r.g, l.L_i * lobe, l.L_sky_omega * lobe, p.I_glints, compat);
    } else if (model != kGlintNone) {
      glint::Slack slack;
      glint::Term g = glint(model, &slack);
      r.L_g = g.L;
      r.glint_cells = g.cells;
      r.glint_slack = slack.min;
    }
    r.L_s = r.L_f + r.L_g;
    r.L_close = L_close(r.L_d, r.L_s, r.L_t, r.rho_m_intensity);
  }
  if (ft.far) {
    r.L_oren = L_oren(s.n, l.wi, s.wo, p.sigma_on, compat);
    r.L_brdf = L_brdf(r.rho_n, r.f_s, r.f_e, r.L_oren, cos_ni, l.L_i, L_sky_diffuse, 1.0 - r.f, r.T_ext);
    if (model != kGlintKajs && model != kGlintNone) r.L_g_far = glint(glint::kGlintBeckmann, nullptr).L;
    r.L_far = L_far(r.L_brdf, r.L_f + r.L_g_far, r.L_t, r.rho_n_intensity);
  }
  r.sig = (ft.close && ft.far) ? sig(s.dist, p.sig_a, p.sig_b) : (ft.far ? 1.0 : 0.0);
  r.L_final = L_final(r.L_close, r.L_far, r.sig);
  return r;
}

}  // namespace glintlab::reference::sand

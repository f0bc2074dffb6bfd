// Independent checks of the kemppinen glint model's parts
// (shaders/glint/models/kemppinen.glsl, through shaders/tests/glint_kemppinen.comp)
// against fp64 computations here:
//  - the compensation term of one LOD against a brute-force sum, over every
//    4D cell the query does not evaluate, of the expected contribution of its
//    facet (the mass of the spatial Gaussian on the spatial cell times the
//    mass of the angular Gaussian on the angular cell, each by composite
//    Gauss-Legendre quadrature of the density);
//  - the LOD roulette's mean against its average over the roulette number;
//  - the Lambert disk of the GGX-stretched half vector: GGX's projected-area
//    measure lands on the disk with the density (2 / pi)(1 - |p|^2), and the
//    factor the model multiplies the facet density by is GGX itself, so a
//    uniform density on the disk has the GGX NDF as its mean.
#include "core/vk/compute_harness.h"
#include "tests/support/vk_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

using namespace glintlab;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kIn = 16, kOut = 16;  // shaders/tests/glint_kemppinen.comp

// `beckmann`: the kemppinen_beckmann variant's map (KEMPPINEN_BECKMANN).
std::vector<float> run(int mode, const std::vector<float>& in, bool beckmann = false) {
  auto& ctx = test::shared_context();
  test::ValidationGuard guard(ctx);
  const size_t n = in.size() / kIn;
  std::vector<std::string> defines{"MODE=" + std::to_string(mode)};
  if (beckmann) defines.push_back("KEMPPINEN_BECKMANN");
  return core::run_compute(ctx, "tests/glint_kemppinen.comp", defines, in, n * kOut, uint32_t(n));
}

// 8-point Gauss-Legendre on [-1, 1] (nodes by Newton's method on P_8).
struct GaussLegendre {
  std::array<double, 8> x{}, w{};
  GaussLegendre() {
    const int n = 8;
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const double dz = p1 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-16) break;
      }
      x[size_t(i)] = z;
      w[size_t(i)] = 2 / ((1 - z * z) * dp * dp);
    }
  }
};
const GaussLegendre kGL;

// Integral of f over [a, b] by 8-point Gauss-Legendre on `parts` equal parts.
double integrate(const std::function<double(double)>& f, double a, double b, int parts) {
  double s = 0;
  const double h = (b - a) / parts;
  for (int p = 0; p < parts; ++p) {
    const double c = a + (p + 0.5) * h;
    for (size_t k = 0; k < 8; ++k) s += kGL.w[k] * f(c + 0.5 * h * kGL.x[k]);
  }
  return 0.5 * h * s;
}

// ---------------------------------------------------------------- compensation

struct CompCase {
  double lod, res, filter;
  double uv[2], dx[2], dy[2];
  double x[2], sigma[2];  // disk position and angular standard deviation (square units)
};

struct Brute {
  double unevaluated;  // sum over the cells not evaluated of their expected contribution
  double spatial_total;
  double spatial_block, angular_block, angular_square;
};

// The expected contribution of every 4D cell, summed explicitly (fp64). Cells
// relative to the spatial vertex v = round(uv res_s): spatial cell (i, j)
// covers [i, i + 1] x [j, j + 1]; the evaluated ones are i, j in {-1, 0}.
// Angular cells are absolute, [c, c + 1] in units of 2^-l, c in [0, 2^l); the
// evaluated ones are ka - 1 and ka with ka = clamp(round(x 2^l), 1, max(2^l - 1, 1)).
Brute brute_force(const CompCase& c) {
  const double res_s = c.res * std::exp2(-c.lod), res_a = std::exp2(c.lod);
  // the spatial Gaussian in cells: covariance filter^2 res_s^2 J J^T + (0.25 2^-l)^2 I
  const double a[2] = {c.filter * res_s * c.dx[0], c.filter * res_s * c.dx[1]};
  const double b[2] = {c.filter * res_s * c.dy[0], c.filter * res_s * c.dy[1]};
  const double e2 = std::pow(0.25 * std::exp2(-c.lod), 2);
  const double sxx = a[0] * a[0] + b[0] * b[0] + e2, syy = a[1] * a[1] + b[1] * b[1] + e2;
  const double sxy = a[0] * a[1] + b[0] * b[1];
  const double det = sxx * syy - sxy * sxy;
  double fs[2];
  for (int k = 0; k < 2; ++k) {
    const double t = c.uv[k] * res_s;
    fs[k] = t - std::floor(t + 0.5);
  }
  auto gauss2 = [&](double px, double py) {
    const double dx = px - fs[0], dy = py - fs[1];
    const double q = (syy * dx * dx - 2 * sxy * dx * dy + sxx * dy * dy) / det;
    return std::exp(-0.5 * q) / (2 * kPi * std::sqrt(det));
  };
  const double smax = std::sqrt(std::max(sxx, syy));
  const int K = int(std::ceil(10 * smax)) + 2;
  // quadrature parts per cell: nodes 1/16 of the narrowest conditional standard deviation apart
  const int parts = std::max(1, int(std::ceil(2.0 / std::sqrt(det / std::max(sxx, syy)))));
  std::vector<double> ms;  // spatial cell masses, (2K)^2
  std::vector<bool> s_block;
  Brute r{};
  for (int j = -K; j < K; ++j)
    for (int i = -K; i < K; ++i) {
      const double m = integrate([&](double py) { return integrate([&](double px) { return gauss2(px, py); }, i, i + 1, parts); },
                                 j, j + 1, parts);
      ms.push_back(m);
      const bool in_block = (i == -1 || i == 0) && (j == -1 || j == 0);
      s_block.push_back(in_block);
      r.spatial_total += m;
      if (in_block) r.spatial_block += m;
    }
  // angular: the covariance is diagonal, each axis its own Gaussian (cells of width 1 at res_a)
  std::array<std::vector<std::pair<int, double>>, 2> ma;  // (cell, mass) with mass > 0
  int ka[2];
  for (int k = 0; k < 2; ++k) {
    const double mu = c.x[k] * res_a, s = c.sigma[k] * res_a;
    ka[k] = int(std::clamp(std::floor(mu + 0.5), 1.0, std::max(res_a - 1, 1.0)));
    const int lo = std::max(0, int(std::floor(mu - 12 * s)) - 1), hi = std::min(int(res_a) - 1, int(std::ceil(mu + 12 * s)) + 1);
    const int p = std::max(1, int(std::ceil(2.0 / s)));
    for (int cell = lo; cell <= hi; ++cell) {
      const double m = integrate([&](double u) { return std::exp(-0.5 * (u - mu) * (u - mu) / (s * s)) / (std::sqrt(2 * kPi) * s); },
                                 cell, cell + 1, std::min(p, 256));
      ma[size_t(k)].push_back({cell, m});
    }
  }
  double square[2] = {0, 0}, block[2] = {0, 0};
  for (int k = 0; k < 2; ++k)
    for (auto [cell, m] : ma[size_t(k)]) {
      square[k] += m;
      if (cell == ka[k] - 1 || cell == ka[k]) block[k] += m;
    }
  r.angular_square = square[0] * square[1];
  r.angular_block = block[0] * block[1];
  // the explicit sum over every (spatial cell, angular cell) pair outside block x block
  double sum = 0;
  for (size_t s = 0; s < ms.size(); ++s)
    for (auto [cu, mu] : ma[0])
      for (auto [cv, mv] : ma[1]) {
        const bool a_block = (cu == ka[0] - 1 || cu == ka[0]) && (cv == ka[1] - 1 || cv == ka[1]);
        if (s_block[s] && a_block) continue;
        sum += ms[s] * mu * mv;
      }
  r.unevaluated = sum;
  return r;
}

std::vector<float> comp_inputs(const std::vector<CompCase>& cs) {
  std::vector<float> in(cs.size() * kIn, 0.0f);
  for (size_t i = 0; i < cs.size(); ++i) {
    const CompCase& c = cs[i];
    float* r = &in[i * kIn];
    r[0] = float(c.lod), r[1] = float(c.uv[0]), r[2] = float(c.uv[1]);
    r[3] = float(c.dx[0]), r[4] = float(c.dx[1]), r[5] = float(c.dy[0]), r[6] = float(c.dy[1]);
    r[7] = float(c.res), r[8] = float(c.filter);
    r[9] = float(c.x[0]), r[10] = float(c.x[1]), r[11] = float(c.sigma[0]), r[12] = float(c.sigma[1]);
  }
  return in;
}

// Cases whose inputs are exact in fp32 (the fp64 sum sees what the GPU sees).
std::vector<CompCase> compensation_cases(bool sheared) {
  std::mt19937_64 rng(sheared ? 0x73686561ull : 0x636f6d70ull);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto f32 = [](double v) { return double(float(v)); };
  std::vector<CompCase> out;
  for (double lod : {0.0, 1.0, 2.0, 4.0, 6.0})
    for (double cells : {0.3, 0.9, 2.5})          // footprint standard deviation in cells
      for (double sig_cells : {0.15, 0.6, 3.0}) {  // angular standard deviation in cells
        CompCase c;
        c.lod = lod;
        c.res = 100;
        c.filter = 0.7;
        const double w = cells / (c.filter * c.res * std::exp2(-lod));
        // multiples of 2^-10: uv res_s is exact in fp32 (res_s = 100 2^-l), so both sides see one position
        c.uv[0] = std::floor(10240 * U(rng)) / 1024, c.uv[1] = std::floor(10240 * U(rng)) / 1024;
        if (sheared && cells < 1 && out.size() % 2 == 1) {  // long and thin along the diagonal: correlation 0.995
          c.dx[0] = f32(w), c.dx[1] = f32(w), c.dy[0] = f32(-0.05 * w), c.dy[1] = f32(0.05 * w);
        } else if (sheared) {  // correlation 0.73
          c.dx[0] = f32(w), c.dx[1] = f32(0.8 * w), c.dy[0] = f32(-0.3 * w), c.dy[1] = f32(0.4 * w);
        } else {
          c.dx[0] = f32(w), c.dx[1] = 0, c.dy[0] = 0, c.dy[1] = f32(w * (0.5 + U(rng)));
        }
        // disk positions: inside, and near the square's edge
        const bool edge = out.size() % 3 == 2;
        c.x[0] = f32(edge ? 0.01 + 0.02 * U(rng) : 0.2 + 0.6 * U(rng));
        c.x[1] = f32(0.2 + 0.6 * U(rng));
        const double s = sig_cells * std::exp2(-lod);
        c.sigma[0] = f32(s), c.sigma[1] = f32(s * (0.5 + U(rng)));
        out.push_back(c);
      }
  return out;
}

}  // namespace

TEST(GlintKemppinen, CompensationIsTheBruteForceSumOfTheUnevaluatedCells) {
  auto cs = compensation_cases(false);
  auto out = run(1, comp_inputs(cs));
  double worst = 0, largest = 0;
  for (size_t i = 0; i < cs.size(); ++i) {
    const float* o = &out[i * kOut];
    const Brute b = brute_force(cs[i]);
    ASSERT_GT(b.spatial_total, 1 - 1e-9) << i;  // the window holds the whole spatial Gaussian
    const double err = std::fabs(o[0] - b.unevaluated);
    SCOPED_TRACE("case " + std::to_string(i) + " lod " + std::to_string(cs[i].lod));
    EXPECT_LE(err, 3e-6 + 1e-5 * b.unevaluated) << "GPU " << o[0] << " brute force " << b.unevaluated;
    EXPECT_NEAR(o[1], b.angular_square, 2e-6 + 1e-6 * b.angular_square);
    EXPECT_NEAR(o[2], b.angular_block, 2e-6 + 1e-6 * b.angular_block);
    EXPECT_NEAR(o[3], b.spatial_block, 2e-6 + 1e-6 * b.spatial_block);
    worst = std::max(worst, err);
    largest = std::max(largest, b.unevaluated);
  }
  std::printf("compensation, %zu axis-aligned footprints: largest |GPU - brute force| %.3g (terms up to %.3g)\n",
              cs.size(), worst, largest);
}

// The LOD of the authors' shadertoy (QueryLod): lambda = log2(sigma_max sqrt(N) filter) + 2^filter,
// sigma_max the footprint ellipse's major semi-axis (fp64 SVD of [dx dy] here), and without lod_offset
// the same less 2^filter. At that LOD the spatial Gaussian's standard deviation along the major axis
// is 2^-(2^filter) cells (0.32 at the default 0.7; twice that at the finer LOD of the pair), so the
// evaluated 2 x 2 spatial block holds most of the pixel filter: its mass, averaged over the vertex
// offset and weighted over the two LODs as the model blends them, is above 0.7 with the offset (0.77
// measured) and below 0.3 without (0.21: the rest is what the compensation turns into a smooth term).
TEST(GlintKemppinen, LodIsTheShadertoysAndKeepsThePixelFilterInTheBlock) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<float> in;
  std::vector<std::array<double, 6>> cases;  // dx, dy, res, filter
  for (int k = 0; k < 64; ++k) {
    const double w = std::exp2(-12 + 6 * U(rng)), res = std::exp2(8 + 4 * U(rng)), f = k % 2 ? 0.7 : 0.3 + U(rng);
    const double a = 2 * kPi * U(rng), e = 0.2 + 0.8 * U(rng), sh = U(rng) - 0.5;
    const std::array<double, 6> c{w * std::cos(a), w * std::sin(a), w * e * (-std::sin(a) + sh * std::cos(a)),
                                  w * e * (std::cos(a) + sh * std::sin(a)), res, f};
    for (int off = 0; off < 2; ++off) {
      std::vector<float> rec(kIn, 0.0f);
      for (int i = 0; i < 6; ++i) rec[size_t(i)] = float(c[size_t(i)]);
      rec[6] = float(off);
      in.insert(in.end(), rec.begin(), rec.end());
    }
    cases.push_back(c);
  }
  auto out = run(3, in);
  double worst = 0;
  for (size_t k = 0; k < cases.size(); ++k) {
    const auto& c = cases[k];
    const double A = c[0] * c[0] + c[2] * c[2], B = c[0] * c[1] + c[2] * c[3], D = c[1] * c[1] + c[3] * c[3];
    const double smax = std::sqrt(0.5 * (A + D) + std::sqrt(0.25 * (A - D) * (A - D) + B * B));
    const double lambda = std::log2(smax * c[4] * c[5]);
    const double with = std::clamp(lambda + std::exp2(c[5]), 0.0, 16.0), without = std::clamp(lambda, 0.0, 16.0);
    EXPECT_NEAR(out[2 * k * kOut], without, 2e-5) << k;
    EXPECT_NEAR(out[(2 * k + 1) * kOut], with, 2e-5) << k;
    worst = std::max(worst, std::fabs(out[(2 * k + 1) * kOut] - with));
  }
  // the block's mass at the default filter over the two blended LODs, with and without the offset
  auto block_mass = [&](bool offset) {
    std::vector<float> cin;
    std::vector<double> weight;
    const double f = 0.7, res = 1024, w = 1.0 / 4096;  // an isotropic footprint, 4 facets wide at f
    const double lambda = std::log2(w * res * f) + (offset ? std::exp2(f) : 0.0);
    for (int j = 0; j < 64; ++j)
      for (int m = 0; m < 2; ++m) {
        std::vector<float> rec(kIn, 0.0f);
        rec[0] = float(std::floor(lambda) + m);
        rec[1] = float((j + 0.5) / 64 / res * 37), rec[2] = float((j * 7 % 64 + 0.5) / 64 / res * 11);
        rec[3] = float(w), rec[6] = float(w), rec[7] = float(res), rec[8] = float(f);
        rec[9] = rec[10] = 0.5f, rec[11] = rec[12] = 0.01f;
        cin.insert(cin.end(), rec.begin(), rec.end());
        const double frac = lambda - std::floor(lambda);
        weight.push_back(m == 0 ? 1 - frac : frac);
      }
    auto o = run(1, cin);
    double sum = 0;
    for (size_t i = 0; i < weight.size(); ++i) sum += weight[i] * o[i * kOut + 3];
    return sum / 64;
  };
  const double with = block_mass(true), without = block_mass(false);
  std::printf("LOD: largest |GPU - fp64| %.2g levels; spatial block mass %.3f with the offset, %.3f without\n",
              worst, with, without);
  EXPECT_GT(with, 0.7);
  EXPECT_LT(without, 0.3);
}

// A sheared footprint (correlated spatial covariance): the GPU integrates the
// block mass of the correlated Gaussian by quadrature over one axis, the brute
// force sums its cells' 2D quadratures.
TEST(GlintKemppinen, CompensationOfAShearedFootprintIsTheBruteForceSum) {
  auto cs = compensation_cases(true);
  auto out = run(1, comp_inputs(cs));
  double worst = 0, worst_block = 0;
  for (size_t i = 0; i < cs.size(); ++i) {
    const float* o = &out[i * kOut];
    const Brute b = brute_force(cs[i]);
    EXPECT_NEAR(o[0], b.unevaluated, 2e-4) << i;
    EXPECT_NEAR(o[3], b.spatial_block, 1e-3) << i;  // the quadrature's error on a thin footprint
    worst = std::max(worst, std::fabs(o[0] - b.unevaluated));
    worst_block = std::max(worst_block, std::fabs(o[3] - b.spatial_block));
  }
  std::printf("compensation, %zu sheared footprints (correlations 0.73 and 0.995): largest |GPU - brute force| %.3g "
              "(spatial block mass %.3g)\n", cs.size(), worst, worst_block);
}

// ---------------------------------------------------------------- roulette

TEST(GlintKemppinen, RouletteMeanIsTheAverageOverTheRouletteNumber) {
  auto smoothstep = [](double a, double b, double x) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3 - 2 * t);
  };
  auto weight = [&](double r, double w) { return smoothstep(std::max(0.0, r - 0.1), std::min(1.0, r + 0.1), w); };
  std::vector<double> ws;
  for (int k = 0; k <= 256; ++k) ws.push_back(k / 256.0);
  std::mt19937_64 rng(0x726f756cull);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<float> in;
  std::vector<double> rs;
  for (double w : ws) {
    const double r = double(float(U(rng)));
    rs.push_back(r);
    std::vector<float> rec(kIn, 0.0f);
    rec[0] = float(w), rec[1] = float(r);
    in.insert(in.end(), rec.begin(), rec.end());
  }
  auto out = run(2, in);
  double worst = 0;
  for (size_t i = 0; i < ws.size(); ++i) {
    const double w = ws[i];
    // average over r in [0, 1): the integrand is smooth between the kinks at r = 0.1, 0.9 and w +- 0.1
    double mean = 0;
    for (double lo : {0.0, 0.1, 0.9}) {
      const double hi = lo == 0.0 ? 0.1 : lo == 0.1 ? 0.9 : 1.0;
      std::vector<double> cuts = {lo, hi};
      for (double k : {w - 0.1, w + 0.1})
        if (k > lo && k < hi) cuts.push_back(k);
      std::sort(cuts.begin(), cuts.end());
      for (size_t k = 0; k + 1 < cuts.size(); ++k)
        mean += integrate([&](double r) { return weight(r, w); }, cuts[k], cuts[k + 1], 64);
    }
    EXPECT_NEAR(out[i * kOut], mean, 2e-6) << "w " << w;
    EXPECT_NEAR(out[i * kOut + 1], weight(rs[i], w), 2e-6) << "w " << w << " r " << rs[i];
    worst = std::max(worst, std::fabs(out[i * kOut] - mean));
  }
  // the mean differs from w near the ends (why the compensation is weighted by it), and f(w) + f(1 - w) = 1
  EXPECT_LT(out[16 * kOut], 1.0 / 16 - 0.01);  // w = 1/16: f = 0.0454
  for (size_t i = 0; i < ws.size(); ++i) EXPECT_NEAR(out[i * kOut] + out[(ws.size() - 1 - i) * kOut], 1.0, 2e-6);
  std::printf("roulette mean: largest |GPU - average over r| %.3g over %zu weights\n", worst, ws.size());
}

// ---------------------------------------------------------------- the disk

// A midpoint grid over the hemisphere of h concentrated on the GGX lobe:
// tan(theta) = a tan(pi t / 2), t and phi uniform.
struct HemisphereGrid {
  int nt, np;
  double a;
  std::vector<double> weight;  // dw of each node
  std::vector<std::array<double, 3>> h;
  HemisphereGrid(int nt_, int np_, double a_) : nt(nt_), np(np_), a(a_) {
    for (int i = 0; i < nt; ++i) {
      const double t = (i + 0.5) / nt;
      const double s = a * std::tan(0.5 * kPi * t);
      const double theta = std::atan(s);
      const double dtheta = a * 0.5 * kPi / std::pow(std::cos(0.5 * kPi * t), 2) / (1 + s * s) / nt;
      for (int j = 0; j < np; ++j) {
        const double phi = 2 * kPi * (j + 0.5) / np;
        h.push_back({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
        weight.push_back(std::sin(theta) * dtheta * 2 * kPi / np);
      }
    }
  }
};

// The map (MODE 0) of every node of g, relative roughness 0.1.
std::vector<float> map_grid(const HemisphereGrid& g, const std::array<double, 2>& alpha, bool beckmann) {
  std::vector<float> in(g.h.size() * kIn, 0.0f);
  for (size_t i = 0; i < g.h.size(); ++i) {
    float* r = &in[i * kIn];
    r[0] = float(g.h[i][0]), r[1] = float(g.h[i][1]), r[2] = float(g.h[i][2]);
    r[3] = float(alpha[0]), r[4] = float(alpha[1]), r[5] = 0.1f, r[6] = 0.1f;
  }
  return run(0, in, beckmann);
}

double ggx_fp64(const std::array<double, 3>& h, double ax, double ay) {
  const double t = h[0] * h[0] / (ax * ax) + h[1] * h[1] / (ay * ay) + h[2] * h[2];
  return 1 / (kPi * ax * ay * t * t);
}

// GGX's projected-area measure D(h) h.z dw, carried to the disk by the map:
// the Lambert projection of the stretched h gives the density
// (2 / pi)(1 - |p|^2) on the unit disk p = 2x - 1 (the cosine-weighted
// hemisphere of the stretched configuration, whose Lambert area is half its
// solid angle). 8 rings of equal mass 1/8 (2 r^2 - r^4 = k / 8) times 4
// sectors: 32 bins of mass 1/32 each. A wrong stretch (alpha multiplied,
// axes swapped) or projection (orthographic) moves mass between them.
TEST(GlintKemppinen, LambertDiskOfTheStretchedHalfVectorCarriesGgx) {
  for (auto alpha : {std::array<double, 2>{0.3, 0.3}, std::array<double, 2>{0.5, 0.125}}) {
    HemisphereGrid g(512, 1024, std::sqrt(alpha[0] * alpha[1]));
    auto out = map_grid(g, alpha, false);
    std::array<double, 32> bins{};
    double mass_fp64 = 0, mass_gpu = 0, worst_rel = 0;
    for (size_t i = 0; i < g.h.size(); ++i) {
      const float* o = &out[i * kOut];
      const double D = ggx_fp64(g.h[i], alpha[0], alpha[1]);
      const double m = D * g.h[i][2] * g.weight[i];
      mass_fp64 += m;
      mass_gpu += o[2] * g.h[i][2] * g.weight[i];
      worst_rel = std::max(worst_rel, std::fabs(o[2] - D) / D);
      const double px = 2.0 * o[0] - 1.0, py = 2.0 * o[1] - 1.0, r2 = px * px + py * py;
      ASSERT_LE(r2, 1.0 + 1e-6) << i;  // on the disk
      const int ring = std::min(7, int(8 * (2 * r2 - r2 * r2)));
      double ang = std::atan2(py, px) + 2 * kPi;
      const int sector = int(std::fmod(ang + kPi / 4, 2 * kPi) / (kPi / 2)) % 4;
      bins[size_t(ring * 4 + sector)] += m;
    }
    SCOPED_TRACE("alpha " + std::to_string(alpha[0]) + " " + std::to_string(alpha[1]));
    EXPECT_NEAR(mass_fp64, 1.0, 1e-4);  // the quadrature itself
    EXPECT_NEAR(mass_gpu, 1.0, 1e-4);   // the factor d / pi integrates to 1
    EXPECT_LT(worst_rel, 5e-6);         // and is GGX: a uniform density 1 on the disk has the GGX mean
    double worst_bin = 0;
    for (double b : bins) worst_bin = std::max(worst_bin, std::fabs(b - 1.0 / 32));
    EXPECT_LT(worst_bin, 1.5e-3);
    std::printf("disk, alpha %.3g/%.3g: GGX mass %.6f (GPU factor %.6f, largest relative error %.2g), "
                "largest bin error %.2g of 1/32\n", alpha[0], alpha[1], mass_fp64, mass_gpu, worst_rel, worst_bin);
  }
}

double beckmann_fp64(const std::array<double, 3>& h, double ax, double ay) {
  const double c2 = h[2] * h[2], sx = h[0] / (ax * h[2]), sy = h[1] / (ay * h[2]);
  return std::exp(-(sx * sx + sy * sy)) / (kPi * ax * ay * c2 * c2);
}

// The Beckmann variant: its projected-area measure D(h) h.z dw, carried to
// the square by x = (1 + erf(h.xy / (h.z alpha))) / 2 per axis, is uniform:
// 4 x 8 equal bins of the square hold 1/32 of the mass each. A wrong stretch
// (alpha swapped or squared), a missing 1/sqrt(2) or a map of the slope
// instead of the stretched slope moves mass between them; the factor is
// Beckmann (d / pi = D_Beckmann) and integrates to 1.
TEST(GlintKemppinen, ErfSquareOfTheStretchedSlopeCarriesBeckmann) {
  for (auto alpha : {std::array<double, 2>{0.3, 0.3}, std::array<double, 2>{0.5, 0.125}}) {
    HemisphereGrid g(512, 1024, std::sqrt(alpha[0] * alpha[1]));
    auto out = map_grid(g, alpha, true);
    std::array<double, 32> bins{};
    double mass_fp64 = 0, mass_gpu = 0, worst_rel = 0;
    const double peak = 1 / (kPi * alpha[0] * alpha[1]);
    for (size_t i = 0; i < g.h.size(); ++i) {
      const float* o = &out[i * kOut];
      const double D = beckmann_fp64(g.h[i], alpha[0], alpha[1]);
      const double m = D * g.h[i][2] * g.weight[i];
      mass_fp64 += m;
      mass_gpu += o[2] * g.h[i][2] * g.weight[i];
      if (D > 1e-4 * peak) worst_rel = std::max(worst_rel, std::fabs(o[2] - D) / D);
      ASSERT_TRUE(o[0] >= 0 && o[0] <= 1 && o[1] >= 0 && o[1] <= 1) << i;  // on the square
      bins[size_t(std::min(3, int(4 * o[0])) * 8 + std::min(7, int(8 * o[1])))] += m;
    }
    SCOPED_TRACE("alpha " + std::to_string(alpha[0]) + " " + std::to_string(alpha[1]));
    EXPECT_NEAR(mass_fp64, 1.0, 1e-4);
    EXPECT_NEAR(mass_gpu, 1.0, 1e-4);
    EXPECT_LT(worst_rel, 2e-5);
    double worst_bin = 0;
    for (double b : bins) worst_bin = std::max(worst_bin, std::fabs(b - 1.0 / 32));
    EXPECT_LT(worst_bin, 1.5e-3);
    std::printf("square (Beckmann), alpha %.3g/%.3g: mass %.6f (GPU factor %.6f, largest relative error %.2g), "
                "largest bin error %.2g of 1/32\n", alpha[0], alpha[1], mass_fp64, mass_gpu, worst_rel, worst_bin);
  }
}

// The angular Gaussian's width: near the normal, a facet at the disk's centre
// is a Beckmann lobe of alpha_l = relative roughness x alpha_g in slope
// (a = alpha_l / 4 in the paper's units). Its NDF N_A(x(h) - c) d(h) / pi,
// relative to its peak, against exp(-s^2 / alpha_l^2) at slopes s up to
// 1.5 alpha_l.
// The Beckmann variant's facet has the standard deviation rel / sqrt(2) in
// the stretched slope, rel / sqrt(2 pi) on the square at the normal.
TEST(GlintKemppinen, AngularGaussianIsTheMicrodetailLobeNearTheNormal) {
  for (const bool beckmann : {false, true}) {
    SCOPED_TRACE(beckmann ? "kemppinen_beckmann" : "kemppinen");
    const double alpha = 0.3, rel = 0.05, al = alpha * rel;
    std::vector<double> slopes;
    for (int k = 0; k <= 12; ++k) slopes.push_back(1.5 * al * k / 12);
    std::vector<float> in;
    for (double s : slopes)
      for (int axis = 0; axis < 2; ++axis) {
        std::vector<float> rec(kIn, 0.0f);
        const double n = std::sqrt(1 + s * s);
        rec[0] = float(axis == 0 ? s / n : 0), rec[1] = float(axis == 1 ? s / n : 0), rec[2] = float(1 / n);
        rec[3] = rec[4] = float(alpha), rec[5] = rec[6] = float(rel);
        in.insert(in.end(), rec.begin(), rec.end());
      }
    auto out = run(0, in, beckmann);
    const double sigma0 = out[3];
    EXPECT_NEAR(sigma0, beckmann ? rel / std::sqrt(2 * kPi) : rel / 4, 1e-7);
    auto lobe = [&](size_t i) {
      const float* o = &out[i * kOut];
      const double dx = o[0] - 0.5, dy = o[1] - 0.5;
      return std::exp(-0.5 * (dx * dx + dy * dy) / (sigma0 * sigma0)) * o[2];
    };
    const double peak = lobe(0);
    double worst = 0;
    for (size_t k = 0; k < slopes.size(); ++k)
      for (size_t axis = 0; axis < 2; ++axis) {
        const double model = lobe(2 * k + axis) / peak;
        // Beckmann D_l(h) / D_l(n) = exp(-s^2 / alpha_l^2) / cos^4 = exp(-s^2 / alpha_l^2) (1 + s^2)^2
        const double s2 = slopes[k] * slopes[k];
        const double beckmann = std::exp(-s2 / (al * al)) * (1 + s2) * (1 + s2);
        worst = std::max(worst, std::fabs(model - beckmann));
        EXPECT_NEAR(model, beckmann, 4e-3) << "slope " << slopes[k];
      }
    std::printf("angular lobe (%s) vs Beckmann alpha_l %.3g: largest difference %.2g (of a peak of 1)\n",
                beckmann ? "kemppinen_beckmann" : "kemppinen", al, worst);
  }
}

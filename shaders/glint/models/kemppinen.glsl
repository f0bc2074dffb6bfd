// The `kemppinen` glint model: Kemppinen, Paulin, Thonat, Thiery, Lehtinen &
// Boubekeur 2025, "Evaluating and sampling glinty NDFs in constant time"
// (SIGGRAPH Asia 2025; the authors' reference shader is shadertoy tcdGDl).
// The facets form a 4D point process over (surface position, facet normal):
// the normal lives on a disk, the Lambert projection of the GGX-stretched
// half vector, so that a uniform density of facets on the disk has the GGX
// NDF as its mean. An implicit multiscale grid splits the 4D space into
// cells of equal volume, one random facet each; at level of detail l the
// spatial cells are 2^l microfacet spacings wide and the angular cells 2^-l
// of the disk's square. A query evaluates 2 LODs x 4 angular x 4 spatial
// cells, each facet a spatial Gaussian (the pixel filter, covariance
// filter^2 J J^T) times an angular Gaussian (the facet's roughness), chooses
// stochastically between the two LODs per cell, and adds the expected value
// of every cell it does not evaluate in closed form (the compensation term),
// so the cost per query is constant. No precomputation.
// Its smooth limit is GGX with alpha_g; its truth is the explicit
// microdetails of `grains`, whose mean is Beckmann with alpha_g: the same
// peak, but GGX's longer tails put more glints far from the specular
// direction than the truth has, so errors against the truth include that
// difference of distributions besides the glints' positions.
// glint_model truth=grains limit=ggx checks=finite,unbiased,limit,deterministic
// glint_parameter filter_width default=0.7 range=0.1,4
// glint_parameter lod_offset default=true type=bool
// filter_width: the standard deviation of the Gaussian pixel filter in pixels
// (the shadertoy's pixel_filter_size, default 0.7); it sets the spatial
// covariance and the LOD. lod_offset: true adds the shadertoy's 2^filter_width
// levels to the LOD (QueryLod: log2(max(s0, s1) filter) + pow(2, filter),
// +1.62 levels at 0.7), so that the evaluated 2 x 2 spatial cells hold most
// of the pixel filter (its standard deviation along the major axis is
// 2^-(2^filter) = 0.32 cells at the LOD; over the two blended LODs and the
// vertex offsets the block holds 0.77 of it); false leaves it out (an
// earlier glintlab rule: the block then holds 0.21 of the filter and the
// compensation turns the rest into a smooth term, fewer and weaker glints;
// tests/core/material/glint_kemppinen.cpp).
// The Beckmann variant is glint/models/kemppinen_beckmann.glsl (this file
// with KEMPPINEN_BECKMANN defined).
//
// Sources, step by step (the authors' shadertoy tcdGDl, functions named):
//  - the disk: ndf_to_disk_ggx (Lambert projection of the stretched h, the
//    factor d named jacobian_determinant there) -> kemppinen_disk;
//  - the LOD and its two levels: QueryLod, floor(lambda) + m, weights
//    1 - |lambda - l| -> kemppinen_lod, kemppinen_D;
//  - the cells of one level: 2 x 2 angular around round(x_a res_a) (clamped
//    to [1, res_a - 1]) times 2 x 2 spatial around round(x_s res_s), a facet
//    jittered uniformly in each, N(sigma_a) N(sigma_s) / N per facet,
//    sigma_a = d a^2 I, sigma_s = filter^2 J J^T (J the footprint ellipse's
//    axes, uv_ellipsoid) -> kemppinen_level, kemppinen_cells;
//  - the roulette: smoothstep(max(0, r - 0.1), min(1, r + 0.1), w) per facet
//    -> kemppinen_roulette;
//  - the compensation: the angular Gaussian's mass on the square minus that
//    on the evaluated angular cells (compensation) -> kemppinen_compensation,
//    here extended to the spatial cells (below);
//  - the output D_filter d / pi -> kemppinen_D.
//
// glintlab's common parameters:
//  - log_density: N = 10^log_density facets per unit uv area (the paper's
//    microfacet count per unit texture area), sqrt(N) spatial cells per uv
//    unit at LOD 0.
//  - alpha_g: the GGX roughness (u, v) of the stretch and of the limit; the
//    anisotropic stretch (h.x / alpha_u, h.y / alpha_v, h.z) generalises the
//    paper's isotropic one.
//  - relative_roughness: the angular Gaussian's width. The paper's facet
//    roughness a gives the variance d a^2 on the disk's square, with d the
//    GGX Jacobian below; near the normal a facet is then a Gaussian in slope
//    with standard deviation 2 sqrt(2) a per axis, which is a Beckmann lobe
//    of alpha_l = 4 a. So a = alpha_l / 4 per axis, alpha_l = relative
//    roughness x alpha_g (the paper's default a = 0.01 is relative roughness
//    0.04 / alpha_g). Away from the normal the lobe follows the paper's
//    sqrt(d) scaling, not a Beckmann lobe's shape (approximate).
//  - light_cone: enters through alpha_g and alpha_l, both widened by
//    sand/glint_roughness.glsl (a Beckmann convolution, approximate for GGX,
//    exact for the Beckmann variant).
//
// The Beckmann variant (KEMPPINEN_BECKMANN; the paper states that the method
// converges to GGX or Beckmann, and no public code of the Beckmann map was
// found, so this one is glintlab's): the square coordinate of each axis is
// x = (1 + erf(s)) / 2 of the stretched slope s = h.xy / (h.z alpha). The
// Beckmann projected-area measure D(h) h.z dw = P22 d(slope) is the product
// of two normal laws of variance 1/2 in s, which this map carries to the
// uniform measure on the square exactly, so a uniform density 1 of facets
// has the Beckmann NDF as its mean and the output is D_filter D_Beckmann(h)
// (d / pi = D_Beckmann in the GGX variant's terms). A facet is a Beckmann
// lobe of alpha_l in slope (standard deviation alpha_l / sqrt(2) per axis),
// i.e. rel / sqrt(2) in s and (rel / sqrt(2)) exp(-s^2) / sqrt(pi) on the
// square (dx / ds).
//
// Where this differs from the shadertoy (each keeps the mean at the smooth
// NDF; none is an option):
//  - the compensation covers the spatial cells outside the evaluated block
//    too, and is weighted by the roulette's exact mean instead of w (below);
//  - the LOD is clamped to [0, 16] (the shadertoy's clamp of the angular
//    index has min > max at l <= 0) and the angular block is kept inside the
//    square for the cells and the compensation alike;
//  - the alpha_g stretch is anisotropic (alpha_u, alpha_v).
#ifndef GLINTLAB_GLINT_MODELS_KEMPPINEN_GLSL
#define GLINTLAB_GLINT_MODELS_KEMPPINEN_GLSL

#include "glint/query.glsl"
#include "common/math.glsl"
#include "common/pcg3d.glsl"
#include "common/ggx.glsl"
#include "common/beckmann.glsl"
#include "common/wrapped_floor.glsl"
#include "sand/glint_footprint.glsl"

#define GLINT_KEMPPINEN_MAX_LOD 16           // angular cells 2^-16 wide: indices exact in fp32
#define GLINT_KEMPPINEN_ROULETTE 0.1         // half-width of the LOD roulette's smoothstep
#define GLINT_KEMPPINEN_MIN_SPACING 0.25     // smallest spatial filter: 1/4 facet spacing
#define GLINT_KEMPPINEN_MAX_CELLS 1e6        // footprint entries cut at 1e6 cells (no fp32 overflow)
#define GLINT_KEMPPINEN_MIN_SIGMA_A 1e-6     // smallest angular Gaussian (square units)
#define GLINT_KEMPPINEN_ANGULAR_SALT 0x510E527Fu
#define GLINT_KEMPPINEN_POSITION_SALT 0x9B05688Cu

// ---------------------------------------------------------------- the disk

// The half vector on the disk. m = normalize(h.x / alpha_u, h.y / alpha_v,
// h.z) is the GGX-stretched h (the configuration where GGX has alpha 1);
// its Lambert azimuthal projection m.xy / sqrt(1 + m.z) maps the upper
// hemisphere onto the unit disk, which x = (p + 1) / 2 places in the unit
// square [0, 1]^2 where the facets' angular coordinates live.
// d = 1 / (alpha_u alpha_v t^2), t = |(h.xy / alpha, h.z)|^2, is the factor
// the paper multiplies the facet density on the disk by: d / pi is GGX, so a
// uniform density 1 on the disk has the GGX NDF as its mean. (As a change of
// variables, the Lambert map carries GGX's projected-area measure
// D(h) h.z dw to the density (8 / pi) m.z on the square, not a uniform one:
// d is the Jacobian of the orthographic projection m.xy; a facet at m
// carries (8 / pi) m.z of the mean mass per facet. The mean is GGX either
// way: tests/core/material/glint_kemppinen.cpp.)
struct KemppinenDisk {
  vec2 x;       // position in the unit square
  float ndf;    // d / pi = ggx_D(h, alpha) (the Beckmann variant: beckmann_D)
  vec2 sigma;   // the angular Gaussian's standard deviation per axis (square units)
};

// h unit with h.z > 0; alpha > 0; rel = alpha_l / alpha_g per axis. The
// angular variance is d a^2 with a = rel alpha / 4 (see the parameters):
// sqrt(d) rel alpha / 4 = rel / (4 t) for each axis, since d alpha_u alpha_v = 1 / t^2.
KemppinenDisk kemppinen_disk(vec3 h, vec2 alpha, vec2 rel) {
  KemppinenDisk k;
#ifdef KEMPPINEN_BECKMANN
  // the Beckmann variant (see the top of the file): x = (1 + erf(s)) / 2 per
  // axis, from erfc of the non-negative argument so the tails keep digits
  vec2 st = clamp(h.xy / (alpha * max(h.z, 1e-30)), vec2(-1e4), vec2(1e4));
  vec2 tail = 0.5 * vec2(erfc_nonneg(abs(st.x)), erfc_nonneg(abs(st.y)));
  k.x = vec2(st.x >= 0.0 ? 1.0 - tail.x : tail.x, st.y >= 0.0 ? 1.0 - tail.y : tail.y);
  k.ndf = beckmann_D(h, vec2(0.0), alpha);
  k.sigma = max(rel * (0.70710678 * 0.56418958) * exp(-st * st), vec2(GLINT_KEMPPINEN_MIN_SIGMA_A));  // 1/sqrt(2), 1/sqrt(pi)
#else
  vec3 s = vec3(h.xy / alpha, h.z);
  float t = dot(s, s);  // in [h.z^2, 1 + 1e6] for alpha >= 1e-3
  vec3 m = s * inversesqrt(t);
  k.x = 0.5 + 0.5 * m.xy * inversesqrt(1.0 + max(m.z, 0.0));
  k.ndf = ggx_D(h, alpha);
  k.sigma = max(rel / (4.0 * t), vec2(GLINT_KEMPPINEN_MIN_SIGMA_A));
#endif
  return k;
}

// ---------------------------------------------------------------- Gaussian masses

// The mass of N(mu, sigma^2) on [lo, hi], from erfc in the tail where it is
// accurate (common/beckmann.glsl: relative error < 1.2e-7), so a mass near 0
// or near 1 keeps its digits. sigma > 0; the arguments are cut at +-1e4
// standard deviations (erfc is 0 there), so every input gives a finite mass
// in [0, 1].
float kemppinen_gauss_mass(float lo, float hi, float mu, float sigma) {
  const float INV_SQRT2 = 0.70710678118654752;
  float a = clamp((lo - mu) / sigma, -1e4, 1e4) * INV_SQRT2;
  float b = clamp((hi - mu) / sigma, -1e4, 1e4) * INV_SQRT2;
  if (!(b > a)) return 0.0;
  float m;
  if (a >= 0.0) m = 0.5 * (erfc_nonneg(a) - erfc_nonneg(b));
  else if (b <= 0.0) m = 0.5 * (erfc_nonneg(-b) - erfc_nonneg(-a));
  else m = 1.0 - 0.5 * (erfc_nonneg(-a) + erfc_nonneg(b));
  return clamp(m, 0.0, 1.0);
}

// ---------------------------------------------------------------- the LOD roulette

// The stochastic choice between the two LODs: a cell of a LOD of weight w
// is kept with the weight smoothstep(max(0, r - 0.1), min(1, r + 0.1), w),
// r uniform per cell (the paper's roulette: a smooth fade instead of a hard
// choice, 0 at w = 0 and 1 at w = 1 so nothing pops where the LOD pair
// changes). Its expectation over r is exactly w for w in [0.2, 0.8], not
// near the ends; the compensation of a LOD is weighted by this expectation
// f(w) instead of w, so that the evaluated cells and the compensation add up
// to the same mean. With delta = 0.1, for w <= 1/2:
//   f(w) = F(w) + 2 delta S(w / (2 delta)),
//   S(x) = x^3 - x^4 / 2 (x <= 1), x - 1/2 (x > 1): the symmetric windows, r in [delta, w + delta];
//   F(w) = the windows cut at 0 (r < delta), integral of smoothstep(0, r + delta, w) over r:
//     3 w^2 / (2 delta) - 3 w^3 / (4 delta^2)             (w <= delta)
//     3 w - delta - 3 w^2 / (2 delta) + w^3 / (4 delta^2)  (delta < w <= 2 delta)
//     delta                                                (w > 2 delta),
// and f(w) = 1 - f(1 - w) (the roulette is symmetric: f(w0) + f(w1) = 1 for
// the LOD pair, w0 + w1 = 1). f(w) = w for w in [2 delta, 1 - 2 delta].
float kemppinen_roulette(float r, float w) {
  const float d = GLINT_KEMPPINEN_ROULETTE;
  return smoothstep(max(0.0, r - d), min(1.0, r + d), w);
}

float kemppinen_roulette_mean(float w) {
  const float d = GLINT_KEMPPINEN_ROULETTE;
  w = clamp(w, 0.0, 1.0);
  bool upper = w > 0.5;
  float v = upper ? 1.0 - w : w;
  float x = v / (2.0 * d);
  float S = x <= 1.0 ? x * x * x - 0.5 * x * x * x * x : x - 0.5;
  float F;
  if (v <= d) F = 1.5 * v * v / d - 0.75 * v * v * v / (d * d);
  else if (v <= 2.0 * d) F = 3.0 * v - d - 1.5 * v * v / d + 0.25 * v * v * v / (d * d);
  else F = d;
  float f = F + 2.0 * d * S;
  return upper ? 1.0 - f : f;
}

// ---------------------------------------------------------------- one LOD

// Everything of one LOD, in cell units: the spatial grid has res_s =
// sqrt(N) 2^-l cells per uv unit, the angular grid res_a = 2^l cells per
// unit of the square, so a 4D cell has the volume 1 / N (one facet) at every
// LOD.
struct KemppinenLevel {
  float l;          // the LOD
  vec2 fs;          // uv relative to the spatial vertex nearest to it (cells, in [-1/2, 1/2])
  uvec2 ks;         // that vertex (wrapped); the evaluated spatial cells are ks - 1 and ks per axis
  vec3 cov;         // spatial covariance (cells^2): xx, yy, xy
  float det;        // its determinant
  vec2 fa;          // the disk position relative to the angular vertex (cells)
  uvec2 ka;         // that vertex, kept 1 cell inside the square; the cells ka - 1 and ka per axis
  float res_a;      // 2^l
  vec2 sigma_a;     // angular standard deviation (cells)
};

// The spatial filter: a Gaussian of covariance filter^2 J J^T, J = [dx dy]
// the footprint (the paper's spatial Gaussian), in cells: A = filter res_s J
// (entries cut at GLINT_KEMPPINEN_MAX_CELLS), cov = A A^T + e^2 I with e a
// quarter of a facet spacing (a zero footprint would make every facet a
// Dirac that a point query never hits). det(A A^T + e^2 I) =
// det(A)^2 + e^2 tr(A A^T) + e^4, formed without the cancellation of
// cov_xx cov_yy - cov_xy^2.
KemppinenLevel kemppinen_level(float l, vec2 uv, vec2 dx, vec2 dy, float res, float filter_width, KemppinenDisk k) {
  KemppinenLevel v;
  v.l = l;
  float res_s = res * exp2(-l);
  vec2 t = uv * res_s;
  vec2 base = floor(t + 0.5);
  v.fs = t - base;
  v.ks = wrapped_floor(base);
  const float C = GLINT_KEMPPINEN_MAX_CELLS;
  vec2 a = clamp(filter_width * res_s * dx, vec2(-C), vec2(C));  // first column of A
  vec2 b = clamp(filter_width * res_s * dy, vec2(-C), vec2(C));  // second column
  float e = GLINT_KEMPPINEN_MIN_SPACING * exp2(-l);
  float e2 = e * e;
  float m_xx = a.x * a.x + b.x * b.x, m_yy = a.y * a.y + b.y * b.y;
  v.cov = vec3(m_xx + e2, m_yy + e2, a.x * a.y + b.x * b.y);
  float detA = a.x * b.y - b.x * a.y;
  v.det = detA * detA + e2 * (m_xx + m_yy) + e2 * e2;
  v.res_a = exp2(l);
  vec2 ta = k.x * v.res_a;
  vec2 ba = clamp(floor(ta + 0.5), vec2(1.0), vec2(max(v.res_a - 1.0, 1.0)));
  v.fa = ta - ba;
  v.ka = uvec2(ba);  // in [1, 2^16]
  v.sigma_a = k.sigma * v.res_a;
  return v;
}

// The compensation term of one LOD: the expected value of every 4D cell
// the query does not evaluate. A cell's facet is uniform in it, so its
// expected contribution is the mass of the spatial Gaussian on its spatial
// cell times the mass of the angular Gaussian on its angular cell (the 1/N
// weight cancels the cell volume). Over all cells that is 1 x M_A(square)
// (the facets cover the whole uv plane and the whole square); the evaluated
// ones are the 2 x 2 spatial block [-1, 1]^2 around the vertex times the
// 2 x 2 angular block, so
//   C = M_A([0, 1]^2) - M_S(block) M_A(block ∩ square).
// M_A is a product of 1D masses (the angular covariance is diagonal), M_S
// that of the correlated spatial Gaussian (kemppinen_block_mass). (The
// paper's term compensates the angular cells; here the spatial cells
// outside the block are compensated too, so the mean is the same at every
// footprint.)
// The mass of N(mu, cov) on the spatial block [-1, 1]^2 (cells). A diagonal
// covariance (an axis-aligned footprint) factors into two 1D masses. A
// correlated one is integrated over the axis u of the larger variance, the
// other axis v conditionally: v | u ~ N(mu_v + k (u - mu_u), c^2) with
// k = cov_uv / cov_uu (|k| <= 1) and c^2 = det / cov_uu, so
//   M = integral over u in [-1, 1] of N(u; mu_u, cov_uu) M_v(u) du,
// by 16-point Gauss-Legendre on the part of [-1, 1] where both factors
// exceed 7 standard deviations' worth of 0 (u within 7 sqrt(cov_uu) of mu_u,
// and the conditional mean within 7 c of [-1, 1]), which keeps the nodes on
// the integrand's support when the footprint is long and thin. Its error is
// below 1e-4 for correlations to 0.99 and below 1e-3 for a footprint 20
// times longer than wide along the diagonal, where the conditional mass
// steps across the block's edges faster than 16 nodes resolve
// (tests/core/material/glint_kemppinen.cpp).
const float KEMPPINEN_GL16_X[8] = float[8](0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                                           0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                           0.9445750230732326, 0.9894009349916499);
const float KEMPPINEN_GL16_W[8] = float[8](0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                           0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                           0.0622535239386479, 0.0271524594117541);

float kemppinen_block_mass(vec2 mu, vec3 cov, float det) {
  if (cov.z == 0.0)
    return kemppinen_gauss_mass(-1.0, 1.0, mu.x, sqrt(cov.x)) * kemppinen_gauss_mass(-1.0, 1.0, mu.y, sqrt(cov.y));
  bool swap = cov.y > cov.x;
  float cuu = swap ? cov.y : cov.x;
  float mu_u = swap ? mu.y : mu.x, mu_v = swap ? mu.x : mu.y;
  float su = sqrt(cuu);
  float k = cov.z / cuu;
  float c = sqrt(det / cuu);
  float a = max(-1.0, mu_u - 7.0 * su), b = min(1.0, mu_u + 7.0 * su);
  if (abs(k) > 1e-20) {
    float u1 = mu_u + (-1.0 - 7.0 * c - mu_v) / k, u2 = mu_u + (1.0 + 7.0 * c - mu_v) / k;
    a = max(a, min(u1, u2));
    b = min(b, max(u1, u2));
  }
  if (!(b > a)) return 0.0;
  float mid = 0.5 * (a + b), half_width = 0.5 * (b - a);
  float sum = 0.0;
  for (int n = 0; n < 16; ++n) {
    float u = mid + (n < 8 ? -1.0 : 1.0) * half_width * KEMPPINEN_GL16_X[n & 7];
    float z = (u - mu_u) / su;
    sum += KEMPPINEN_GL16_W[n & 7] * exp(-0.5 * z * z) * kemppinen_gauss_mass(-1.0, 1.0, mu_v + k * (u - mu_u), c);
  }
  return clamp(half_width * sum * 0.39894228040143268 / su, 0.0, 1.0);  // 1 / sqrt(2 pi)
}

struct KemppinenCompensation {
  float square;   // M_A([0, 1]^2)
  float block_a;  // M_A of the evaluated angular cells
  float block_s;  // M_S of the evaluated spatial cells
  float value;    // C >= 0
};

KemppinenCompensation kemppinen_compensation(KemppinenLevel v) {
  KemppinenCompensation c;
  // in angular cells relative to ka: the square is [-ka, res_a - ka], the block [-1, 1] cut to it
  vec2 lo = -vec2(v.ka), hi = v.res_a - vec2(v.ka);
  c.square = kemppinen_gauss_mass(lo.x, hi.x, v.fa.x, v.sigma_a.x) * kemppinen_gauss_mass(lo.y, hi.y, v.fa.y, v.sigma_a.y);
  c.block_a = kemppinen_gauss_mass(-1.0, min(1.0, hi.x), v.fa.x, v.sigma_a.x) *
              kemppinen_gauss_mass(-1.0, min(1.0, hi.y), v.fa.y, v.sigma_a.y);
  c.block_s = kemppinen_block_mass(v.fs, v.cov, v.det);
  c.value = max(c.square - c.block_s * c.block_a, 0.0);
  return c;
}

// Density of N(0, cov) at d (cells^-2); the exponent is cut at 80 (no
// denormals).
float kemppinen_spatial_gauss(vec2 d, vec3 cov, float det) {
  float q = max(cov.y * d.x * d.x - 2.0 * cov.z * d.x * d.y + cov.x * d.y * d.y, 0.0) / det;
  return q < 160.0 ? exp(-0.5 * q) / (TWO_PI * sqrt(det)) : 0.0;
}

float kemppinen_angular_gauss(vec2 d, vec2 sigma) {
  vec2 z = d / sigma;
  float q = dot(z, z);
  return q < 160.0 ? exp(-0.5 * q) / (TWO_PI * sigma.x * sigma.y) : 0.0;
}

// The 16 cells of one LOD, each kept with the roulette weight of w. The
// facet of a 4D cell sits at a uniform position in its spatial cell and in
// its angular cell, drawn from pcg3d of the cell's indices and the LOD (the
// same cell gives the same facet in every query: deterministic per uv cell
// and h cell, no frame or pixel enters); its contribution is
// (1 / N) N_S(uv - g_s) N_A(x - g_a) in uv and square units, which in cell
// units is N_S N_A (res_s^2 res_a^2 = N). `visited` counts the cells kept.
float kemppinen_cells(KemppinenLevel v, float w, inout float visited) {
  float sum = 0.0;
  for (int ja = 0; ja < 4; ++ja) {
    ivec2 oa = ivec2(ja & 1, ja >> 1) - 1;  // angular cell ka + oa covers [oa, oa + 1] (cells)
    uvec2 ia = v.ka + uvec2(oa);            // ka >= 1, so ia >= 0
    if (float(ia.x) >= v.res_a || float(ia.y) >= v.res_a) continue;  // outside the square (LOD 0)
    uvec3 ha = pcg3d(uvec3(ia, floatBitsToUint(v.l) ^ GLINT_KEMPPINEN_ANGULAR_SALT));
    for (int js = 0; js < 4; ++js) {
      ivec2 os = ivec2(js & 1, js >> 1) - 1;
      uvec3 hs = pcg3d(uvec3(v.ks + uvec2(os), ha.x));
      uvec3 hg = pcg3d(hs ^ uvec3(ha.y, ha.z, GLINT_KEMPPINEN_POSITION_SALT));
      vec3 us = pcg3d_unit(hs), ug = pcg3d_unit(hg);
      float keep = kemppinen_roulette(us.z, w);
      if (!(keep > 0.0)) continue;
      visited += 1.0;
      vec2 ds = v.fs - (vec2(os) + us.xy);
      vec2 da = v.fa - (vec2(oa) + ug.xy);
      sum += keep * kemppinen_spatial_gauss(ds, v.cov, v.det) * kemppinen_angular_gauss(da, v.sigma_a);
    }
  }
  return sum;
}

// ---------------------------------------------------------------- the NDF

// The LOD (QueryLod): lambda = log2(sigma_max sqrt(N) filter) + 2^filter,
// sigma_max the footprint ellipse's major semi-axis (the shadertoy's
// max(|s0|, |s1|) of the uv_ellipsoid axes), in facet spacings; without
// lod_offset, no 2^filter. Clamped to [0, GLINT_KEMPPINEN_MAX_LOD]; the pair
// floor(lambda), floor(lambda) + 1 with the linear weights 1 - |lambda - l|.
float kemppinen_lod(vec2 dx, vec2 dy, float res, float filter_width, bool lod_offset) {
  float j = glint_ellipse_axes(dx, dy).x;
  if (!(j > 0.0)) return 0.0;
  float offset = lod_offset ? exp2(filter_width) : 0.0;
  return clamp(log2(j) + log2(res * filter_width) + offset, 0.0, float(GLINT_KEMPPINEN_MAX_LOD));
}

struct KemppinenResult {
  float D;        // the NDF at h
  float visited;  // cells kept by the roulette, both LODs
};

KemppinenResult kemppinen_D(vec2 uv, vec2 dx, vec2 dy, vec3 h, vec2 alpha, vec2 rel, float density, float filter_width,
                            bool lod_offset) {
  KemppinenResult r;
  r.D = 0.0;
  r.visited = 0.0;
  if (!(h.z > 0.0)) return r;
  alpha = max(alpha, vec2(1e-4));
  KemppinenDisk k = kemppinen_disk(h, alpha, clamp(rel, vec2(0.0), vec2(1.0)));
  if (!(k.ndf > 0.0)) return r;
  uv = glint_clamp_uv(uv);
  dx = glint_clamp_derivative(dx);
  dy = glint_clamp_derivative(dy);
  float res = sqrt(max(density, 1e-30));
  float lambda = kemppinen_lod(dx, dy, res, filter_width, lod_offset);
  float l0 = floor(lambda);
  float w1 = l0 < float(GLINT_KEMPPINEN_MAX_LOD) ? lambda - l0 : 0.0;
  float density_on_disk = 0.0;  // the filtered facet density at (uv, x): mean M_A(square) ~ 1
  for (int m = 0; m < 2; ++m) {
    float w = m == 0 ? 1.0 - w1 : w1;
    if (!(w > 0.0)) continue;
    KemppinenLevel v = kemppinen_level(l0 + float(m), uv, dx, dy, res, filter_width, k);
    density_on_disk += kemppinen_cells(v, w, r.visited);
    density_on_disk += kemppinen_roulette_mean(w) * kemppinen_compensation(v).value;
  }
  r.D = density_on_disk * k.ndf;
  return r;
}

vec3 glint_D(GlintQuery q) {
  KemppinenResult r = kemppinen_D(q.uv, q.duv_dx, q.duv_dy, q.h, q.alpha_g, q.alpha_l / max(q.alpha_g, vec2(1e-30)),
                                  q.density, q.filter_width, q.lod_offset > 0.5);
  glint_cells_visited = r.visited;
  return vec3(r.D);
}

#endif  // GLINTLAB_GLINT_MODELS_KEMPPINEN_GLSL

// The `chermain` glint model: Chermain, Sauvage, Dischler & Dachsbacher 2020,
// "Procedural Physically based BRDF for Real-Time Rendering of Glints"
// (Pacific Graphics 2020), Alg. 1-3: the pixel footprint is an ellipse in
// uv; on the two grid levels around its minor axis every cell under it gets
// a random slope distribution (P-SDF), the product of two 1D marginals drawn
// from a multiscale dictionary, scaled from the dictionary's roughness to
// alpha and randomly rotated; the cells are averaged with elliptical weights
// and D = P22 / cos^4(theta_h) (eq. 6). Where a cell holds more microfacets
// than the dictionary's last level describes (log4 of the count, jittered,
// reaches L = 16), its P-SDF is Beckmann: the model converges to
// Cook-Torrance with Beckmann alpha_g.
// With ggaa: Chermain, Sauvage, Dischler & Dachsbacher 2021, "Real-time
// Geometric Glint Anti-Aliasing with Normal Map Filtering" (I3D 2021),
// contribution 1: each marginal is read from a MIP-mapped dictionary at the
// level that the footprint of the half vector's slope selects (textureGrad).
// glint_model truth=grains limit=beckmann checks=finite,deterministic fails=unbiased,limit
// glint_table size=393216
// glint_parameter microfacet_relative_area default=1 range=0.01,1
// glint_parameter max_anisotropy default=8 range=1,16
// glint_parameter ggaa default=false type=bool
// glint_parameter ggaa_kernel default=0.5 range=0,2
// microfacet_relative_area: the share of cells that hold microfacets (Alg. 3
// line 4; the others are discarded); max_anisotropy: the largest major /
// minor ratio of the footprint ellipse (Alg. 1 line 4); ggaa: the 2021
// dictionary filtering; ggaa_kernel: its "kernel size", the factor on the
// slope footprint (0.5 in the 2021 renderer). Defaults: the 2020 renderer's
// (relative area 1, max anisotropy 8; the 2021 one uses 0.025 and 4).
//
// Mapping of glintlab's common parameters onto the method:
//  - alpha_g -> (alpha_x, alpha_y): the Beckmann roughness the P-SDFs are
//    scaled to (Alg. 3 line 16) and the Beckmann P-SDF of the coarsest level.
//    It includes the light cone (sand/glint_roughness.glsl), so the light
//    widens every glint lobe in proportion, not by the cone itself.
//  - log_density -> the paper's logarithmic microfacet density: glintlab's
//    density is 10^log_density per unit uv area, the paper's exp(LMD) per
//    unit uv area (a level-(L-1) cell is one uv unit wide, Alg. 3 line 5), so
//    LMD = ln(10) log_density.
//  - relative_roughness (alpha_l / alpha_g) is not used: one microfacet's
//    lobe is fixed by the dictionary, a Gaussian of standard deviation 0.02
//    in the dictionary's slope units against its sigma = 0.5 / sqrt(2), i.e.
//    alpha_l / alpha_g = 0.0566 always.
//  - light_cone: only through alpha_g (above).
//
// What a viewer counts, against the truth (`grains`, n microfacets of lobe
// width relative_roughness alpha_g, 0.1 alpha_g by default): a cell of n
// microfacets draws its P-SDF at level k = log4 n (jittered), and a level-k
// marginal holds 2^k mirrored pairs of lobes, 2^(k+1) lobes; the P-SDF is
// the product of two marginals, so a cell shows (2^(k+1))^2 = 4 n lobes of
// weight 1 / (4 n) each (the reference code does the same: the generator's
// two mirrored lobes per mean, P22_theta_alpha's product P_i P_j), not
// n lobes of weight 1 / n. With the lobe width 0.057 alpha_g against the
// truth's 0.1 alpha_g, the expected number of lobes covering a half vector
// is 4 n 0.057^2 against n 0.1^2, 1.3 times the truth's, and a hit lobe's
// peak is (1 / (4 n 0.057^2)) / (1 / (n 0.1^2)) = 0.77 of a truth lobe's:
// the method shows more, dimmer glints than `grains` at the same
// log_density (the density sweep of glint-methods measures the effect).
//
// Sources, step by step (Chermain et al. 2020; reference code
// ASTex-ICube/real_time_glint, shader/glint.frag.glsl):
//  - the footprint ellipse, its anisotropy clamp, the LOD and two levels:
//    Alg. 1 (glint.frag.glsl: f_P) -> glint_D;
//  - the cells under the ellipse with EWA weights, at most 100 a level:
//    Alg. 2 (P22__P_, after pbrt's MIPMap::EWA) -> chermain_level;
//  - per cell: the coherent hash (eq. 8), the relative-area discard, the
//    microfacet count, the jittered distribution level, the rotation and the
//    product of two dictionary marginals scaled to alpha (eq. 11): Alg. 3
//    (P22_theta_alpha) -> chermain_cell_p22;
//  - D = P22 / cos^4 theta_h: eq. 6 -> glint_D;
//  - the dictionary: sec. 5.1 and the generator (below) -> glint_table_entry;
//  - ggaa: Chermain et al. 2021 sec. 4 (the MIP level of the slope
//    footprint, textureGrad) -> chermain_marginal, chermain_slope_derivatives.
//
// The dictionary (Chermain et al. 2020 sec. 5.1 and their generator,
// defaults "-nlevels 16 -N 192 -distreso 64 -alpha_dict 0.5
// -std_dev_lobe 0.02"): N = 192 multiscale marginals; marginal d at level k
// (k = 0 .. L-1, L = 16) is the mixture of 2^k pairs of Gaussian lobes of
// standard deviation s = 0.02 at +-mu_i, mu_i (i < 2^k) drawn from
// N(0, sigma_dict^2), sigma_dict = alpha_dict / sqrt(2), alpha_dict = 0.5;
// the means of level k are the first 2^k of the same list for every k. It is
// even, tabulated on |slope| in [0, 4 sigma_dict) with 64 bins and
// normalised to integrate to 1 over the line. Differences from the published
// generator: the means come from an integer hash and the normal quantile
// instead of std::default_random_engine; bin b holds the density at its
// centre (b + 1/2) Delta (where the OpenGL sampler of the published renderer
// reads it; the generator evaluates it at b Delta); the interpolation is
// linear between bin centres, mirrored at slope 0 and constant in the last
// half bin, whose integral over a side is exactly the midpoint sum
// Delta sum_b f_b, and that is what is normalised to 1/2.
// For ggaa the table also holds each marginal's prefiltered levels
// m = 1 .. 6 (32 .. 1 bins), each bin the box average of the two finer ones
// (glGenerateMipmap's filter, which the 2021 renderer uses).
// Layout: entry ((k N + d) 128 + offset(m) + j), offset(m) = 128 - (128 >> m)
// (64 + 32 + ... + 1 = 127 entries and one unused), 16 x 192 x 128 floats =
// 1.5 MiB.
#ifndef GLINTLAB_GLINT_MODELS_CHERMAIN_GLSL
#define GLINTLAB_GLINT_MODELS_CHERMAIN_GLSL

#include "common/math.glsl"
#include "common/pcg3d.glsl"
#include "common/beckmann.glsl"
#include "common/normal_quantile.glsl"
#include "common/wrapped_floor.glsl"
#include "sand/glint_footprint.glsl"

#define CHERMAIN_LEVELS 16              // L, dictionary levels
#define CHERMAIN_DISTS 192u             // N, marginals per level
#define CHERMAIN_BINS 64                // bins of one marginal (finest MIP level)
#define CHERMAIN_MIPS 7                 // 64, 32, ..., 1 bins
#define CHERMAIN_BLOCK 128u             // floats per (level, marginal)
#define CHERMAIN_ALPHA_DICT 0.5         // alpha_dict
#define CHERMAIN_SIGMA_DICT 0.35355339  // alpha_dict / sqrt(2)
#define CHERMAIN_SLOPE_MAX 1.41421356   // 4 sigma_dict: the tabulated range of |slope|
#define CHERMAIN_LOBE_STD 0.02          // s, one microfacet's lobe (dictionary slope units)
#define CHERMAIN_CELL_SALT_A 0x85EBCA6Bu
#define CHERMAIN_CELL_SALT_B 0xC2B2AE35u
#define CHERMAIN_MAX_CELLS 100          // Alg. 2's guardrail: cells of the ellipse's box per level
#define CHERMAIN_MAX_LEVEL 30.0         // coarsest grid level (cells 2^15 uv wide)
#define CHERMAIN_LOD_STD 2.0            // zeta, the std. dev. of the distribution-LOD jitter (Alg. 3 line 8)

// Width of one bin in dictionary slope units: 4 sigma_dict / 64.
const float CHERMAIN_BIN = CHERMAIN_SLOPE_MAX / float(CHERMAIN_BINS);

// The 24-bit key of mean t of marginal d (d < 192, t < 2^15): Wellons'
// "lowbias32" integer hash (two multiply-xorshift rounds) of d 2^15 + t; the
// mean is mu = sigma_dict Phi^-1(u), u = (key + 1/2) 2^-24, and keys k and
// 2^24 - 1 - k give -+mu (1 - u is exact). One 32-bit hash per lobe: the
// generator visits every lobe of a marginal for each of its 127 entries.
uint chermain_mean_key(uint d, uint t) {
  uint x = ((d << 15u) | t) ^ 0x9E3779B9u;  // salted: key(0, 0) is not 0
  x ^= x >> 16u;
  x *= 0x7FEB352Du;
  x ^= x >> 15u;
  x *= 0x846CA68Bu;
  x ^= x >> 16u;
  return x >> 8u;
}

// The folded key max(k, 2^24 - 1 - k) at or above which |mu| >= z (z >= 0):
// (key + 1/2) 2^-24 >= Phi(z / sigma_dict) (erfc of common/beckmann.glsl).
float chermain_key_at(float z) {
  return (1.0 - 0.5 * erfc_nonneg(max(z, 0.0) * (0.70710678 / CHERMAIN_SIGMA_DICT))) * 16777216.0 - 0.5;
}

// Sum over the base bins b in [b_lo, b_hi] of the lobe N(c, s^2) at the bin
// centres (b + 1/2) Delta; only bins within 7 s of c (at most 14) are visited.
float chermain_lobe_bins(float c, int b_lo, int b_hi) {
  const float r = 7.0 * CHERMAIN_LOBE_STD;
  int lo = max(b_lo, int(ceil((c - r) / CHERMAIN_BIN - 0.5)));
  int hi = min(b_hi, int(floor((c + r) / CHERMAIN_BIN - 0.5)));
  float sum = 0.0;
  for (int t = 0; t < 14; ++t) {
    int b = lo + t;
    if (b > hi) break;
    float z = ((float(b) + 0.5) * CHERMAIN_BIN - c) / CHERMAIN_LOBE_STD;
    sum += exp(-0.5 * z * z);
  }
  return sum * (0.39894228 / CHERMAIN_LOBE_STD);  // 1 / (s sqrt(2 pi))
}

// Entry i of the dictionary (the layout above): the normalised marginal d of
// level k, averaged over the 2^m base bins of bin j of MIP level m.
//   f(x) = (1 / (2 M)) sum_{i<M} [g(x - mu_i) + g(x + mu_i)] / mass, M = 2^k,
//   mass = (1 / M) sum_i Delta sum_{b=-64}^{63} g((b + 1/2) Delta - mu_i),
// the generator's mixture (each facet "has a twin facet that has an inverted
// slope"), normalised as the generator does: to a unit integral of the
// interpolated marginal over the tabulated range.
float glint_table_entry(uint i) {
  uint block = i / CHERMAIN_BLOCK, e = i % CHERMAIN_BLOCK;
  uint d = block % CHERMAIN_DISTS;
  int k = int(block / CHERMAIN_DISTS);
  if (e >= CHERMAIN_BLOCK - 1u || k >= CHERMAIN_LEVELS) return 0.0;
  int m = 0;
  while (m < CHERMAIN_MIPS - 1 && e >= CHERMAIN_BLOCK - (CHERMAIN_BLOCK >> uint(m + 1))) ++m;
  int j = int(e - (CHERMAIN_BLOCK - (CHERMAIN_BLOCK >> uint(m))));
  int width = 1 << m;
  int b_lo = j * width, b_hi = b_lo + width - 1;
  uint M = 1u << uint(k);
  // A lobe pair +-mu reaches the bins only if |mu| lies within 7 s (7.5 s
  // here, a margin for rounding) of their slope range: a range of folded
  // keys, since Phi is monotone. The others are skipped before the quantile.
  float x_lo = float(b_lo) * CHERMAIN_BIN - 7.5 * CHERMAIN_LOBE_STD;
  float x_hi = float(b_hi + 1) * CHERMAIN_BIN + 7.5 * CHERMAIN_LOBE_STD;
  float k_lo = chermain_key_at(x_lo), k_hi = x_hi < 6.0 * CHERMAIN_SIGMA_DICT ? chermain_key_at(x_hi) : 3e7;
  // The normalisation: the midpoint sum of the interpolant, 2 Delta sum_b f_b
  // over the 64 bins of each side (the integral of the interpolant, see the
  // layout above). A lobe farther than 7.5 s from the range's ends adds
  // Delta sum_b g((b + 1/2) Delta - mu) = 1 to within 1e-7 (the midpoint rule
  // of a Gaussian sampled at 1.1 s); one nearer to an end is summed.
  float k_edge = chermain_key_at(CHERMAIN_SLOPE_MAX - 7.5 * CHERMAIN_LOBE_STD);
  float sum = 0.0, mass = float(M);
  float x_b = (float(b_lo) + 0.5) * CHERMAIN_BIN;
  for (uint t = 0u; t < 32768u; ++t) {
    if (t >= M) break;
    uint key = chermain_mean_key(d, t);
    float kf = float(max(key, 16777215u - key));
    bool reach = kf >= k_lo && kf <= k_hi;
    bool edge = kf > k_edge;
    if (!reach && !edge) continue;
    float mu = CHERMAIN_SIGMA_DICT * normal_quantile((float(key) + 0.5) * (1.0 / 16777216.0));
    if (reach) {
      if (width == 1) {  // one bin (half of the entries): both lobes directly
        vec2 z = (x_b - vec2(mu, -mu)) * (1.0 / CHERMAIN_LOBE_STD);
        z = min(z * z, vec2(98.0));  // beyond 7 s: < 2e-21 of the peak
        sum += (exp(-0.5 * z.x) + exp(-0.5 * z.y)) * (0.39894228 / CHERMAIN_LOBE_STD);
      } else {
        sum += chermain_lobe_bins(mu, b_lo, b_hi) + chermain_lobe_bins(-mu, b_lo, b_hi);
      }
    }
    if (edge) mass -= 1.0 - CHERMAIN_BIN * chermain_lobe_bins(mu, -CHERMAIN_BINS, CHERMAIN_BINS - 1);
  }
  // (sum / (2 M)) / (mass / M) / width
  return mass > 0.0 ? sum / (2.0 * mass * float(width)) : 0.0;
}

// Marginal d of level k at |slope| x (dictionary units, x < 4 sigma_dict),
// linearly interpolated between bin centres on MIP level m: mirrored at 0
// (the marginal is even), constant in the last half bin.
float chermain_marginal_mip(uint d, int k, int m, float x) {
  int n = CHERMAIN_BINS >> m;
  float t = x / (CHERMAIN_BIN * float(1 << m)) - 0.5;  // bin-centre coordinates
  float t0 = floor(t);
  float f = t - t0;
  int b0 = int(clamp(t0, -1.0, float(n - 1)));
  int b1 = min(b0 + 1, n - 1);
  b0 = b0 < 0 ? 0 : b0;  // bin -1 mirrors bin 0
  uint base = (uint(k) * CHERMAIN_DISTS + d) * CHERMAIN_BLOCK + (CHERMAIN_BLOCK - (CHERMAIN_BLOCK >> uint(m)));
  return mix(glint_table[base + uint(b0)], glint_table[base + uint(b1)], f);
}

// The marginal at x filtered over a slope footprint w (dictionary units; 0:
// no filtering), as a trilinear textureGrad: MIP level log2(w / Delta),
// clamped to [0, 6], the two levels around it blended linearly.
float chermain_marginal(uint d, int k, float x, float w) {
  float lod = w > CHERMAIN_BIN ? min(log2(w / CHERMAIN_BIN), float(CHERMAIN_MIPS - 1)) : 0.0;
  int m0 = int(floor(lod));
  float fm = lod - float(m0);
  float v = chermain_marginal_mip(d, k, m0, x);
  if (fm > 0.0) v = mix(v, chermain_marginal_mip(d, k, min(m0 + 1, CHERMAIN_MIPS - 1), x), fm);
  return v;
}

// The half vector's slope footprint for ggaa: the screen derivatives of its
// slope s = h.xy / h.z, ds = (dh.xy h.z - h.xy dh.z) / h.z^2, from those of h
// in the query (0 where unknown: no filtering; NaN or Inf: none either).
void chermain_slope_derivatives(GlintQuery q, out vec2 dx, out vec2 dy) {
  float z = q.h.z;
  vec4 g = vec4(q.dh_dx.xy * z - q.h.xy * q.dh_dx.z, q.dh_dy.xy * z - q.h.xy * q.dh_dy.z) / (z * z);
  bool ok = all(lessThan(abs(g), vec4(1e30)));
  dx = ok ? g.xy : vec2(0.0);
  dy = ok ? g.zw : vec2(0.0);
}

// What every cell of a query shares.
struct ChermainPixel {
  vec2 slope;       // slope of h (eq. 1)
  vec2 alpha;       // (alpha_x, alpha_y)
  vec2 sdx, sdy;    // slope footprint of ggaa (0 without)
  float lmd_log4;   // log4 of the microfacets per uv area: ln(density) / ln(4)
  float area;       // microfacet relative area
};

// uniforms of a cell from its coherent index: x area, y LOD jitter, z rotation;
// w.x, w.y the two marginals.
struct ChermainCellRandom { vec3 u; vec2 w; };

ChermainCellRandom chermain_cell_random(uvec2 index) {
  ChermainCellRandom r;
  r.u = (vec3(pcg3d(uvec3(index, CHERMAIN_CELL_SALT_A)) >> 8u) + 0.5) * (1.0 / 16777216.0);
  r.w = pcg3d_unit(pcg3d(uvec3(index, CHERMAIN_CELL_SALT_B))).xy;
  return r;
}

// Alg. 3: the P-SDF of cell `cell` (wrapped integer coordinates) of grid level l.
float chermain_cell_p22(ChermainPixel px, uvec2 cell, int l) {
  // Eq. 8, Alg. 3 lines 1-2: the coherent index, the cell's corner on level 0,
  // so cells of every level that share that corner share their random numbers.
  ChermainCellRandom r = chermain_cell_random(cell << uint(l));
  if (r.u.x > px.area) return 0.0;  // line 4
  // lines 5-6: n = 2^(2l - 2(L-1)) exp(LMD) microfacets; l_dist = log4(n)
  float l_dist = float(l - (CHERMAIN_LEVELS - 1)) + px.lmd_log4;
  // lines 8-9: l_dist ~ N(l_dist, zeta^2), rounded, clamped to [0, L]
  l_dist = clamp(l_dist + CHERMAIN_LOD_STD * normal_quantile(r.u.y), 0.0, float(CHERMAIN_LEVELS));
  int k = int(round(l_dist));
  if (k >= CHERMAIN_LEVELS) return beckmann_p22(px.slope, px.alpha);  // line 10
  // lines 13-16: random rotation theta, the slope scaled to the dictionary's
  // roughness and rotated by -theta (Jacobian 1 / (scale_x scale_y))
  float theta = TWO_PI * r.u.z;
  float c = cos(theta), s = sin(theta);
  vec2 inv_scale = CHERMAIN_ALPHA_DICT / px.alpha;
  vec2 p = px.slope * inv_scale;
  vec2 so = vec2(c * p.x + s * p.y, -s * p.x + c * p.y);
  vec2 a = abs(so);
  if (!(max(a.x, a.y) < CHERMAIN_SLOPE_MAX)) return 0.0;  // beyond 4 sigma_dict
  // lines 17-18: two marginals of level k
  uint di = min(uint(r.w.x * float(CHERMAIN_DISTS)), CHERMAIN_DISTS - 1u);
  uint dj = min(uint(r.w.y * float(CHERMAIN_DISTS)), CHERMAIN_DISTS - 1u);
  // ggaa (2021, the kernel transformed as the slope is): the
  // footprint of each coordinate is the larger of its two screen derivatives
  // (textureGrad's rho for a 1D texture).
  vec2 gx = px.sdx * inv_scale, gy = px.sdy * inv_scale;
  vec2 dx = vec2(c * gx.x + s * gx.y, -s * gx.x + c * gx.y);
  vec2 dy = vec2(c * gy.x + s * gy.y, -s * gy.x + c * gy.y);
  float wx = max(abs(dx.x), abs(dy.x)), wy = max(abs(dx.y), abs(dy.y));
  // line 19 / eq. 11
  return chermain_marginal(di, k, a.x, wx) * chermain_marginal(dj, k, a.y, wy) * inv_scale.x * inv_scale.y;
}

// Alg. 2: the P-SDF of one grid level, the elliptically weighted average of
// the cells under the footprint (Heckbert's EWA as in pbrt-v3's
// MIPMap::EWA: the ellipse of the derivatives widened by one cell, Gaussian
// weights exp(-2 r^2) - exp(-2)). Cells of level l are 2^(l - (L-1)) uv
// wide. At most CHERMAIN_MAX_CELLS cells of the ellipse's bounding box are
// visited, row by row, as the published guardrail does. Cell coordinates
// are wrapped integers (common/wrapped_floor.glsl) relative to the cell of
// the footprint's centre, so no out-of-range value is converted to int.
float chermain_level(ChermainPixel px, int l, vec2 uv, vec2 d0, vec2 d1) {
  float size = exp2(float(CHERMAIN_LEVELS - 1 - l));  // cells per uv unit
  vec2 st = uv * size - 0.5;                           // cell centres at integers
  d0 *= size;
  d1 *= size;
  float A = d0.y * d0.y + d1.y * d1.y + 1.0;
  float B = -2.0 * (d0.x * d0.y + d1.x * d1.y);
  float C = d0.x * d0.x + d1.x * d1.x + 1.0;
  float F = A * C - 0.25 * B * B;  // >= A + C - 1 >= 1
  A /= F;
  B /= F;
  C /= F;
  // Half extents of the ellipse's bounding box: 2 sqrt(C / det), 2 sqrt(A / det)
  // with det = 4 A C - B^2 = 4 / F (after the division) -> sqrt(C F), sqrt(A F).
  float hu = min(sqrt(C * F), 64.0), hv = min(sqrt(A * F), 64.0);
  vec2 base = floor(st);
  vec2 fr = st - base;  // in [0, 1)
  uvec2 cell0 = wrapped_floor(st);
  int s0 = int(ceil(fr.x - hu)), s1 = int(floor(fr.x + hu));
  int t0 = int(ceil(fr.y - hv)), t1 = int(floor(fr.y + hv));
  int cols = max(s1 - s0 + 1, 1);
  int cells = cols * max(t1 - t0 + 1, 1);
  float sum = 0.0, wsum = 0.0;
  for (int it = 0; it < CHERMAIN_MAX_CELLS; ++it) {
    if (it >= cells) break;
    int ds = s0 + it % cols, dt = t0 + it / cols;
    float ss = float(ds) - fr.x, tt = float(dt) - fr.y;
    float r2 = A * ss * ss + B * ss * tt + C * tt * tt;
    if (!(r2 < 1.0)) continue;
    float w = exp(-2.0 * r2) - exp(-2.0);
    glint_cells_visited += 1.0;
    sum += w * chermain_cell_p22(px, cell0 + uvec2(ivec2(ds, dt)), l);
    wsum += w;
  }
  return wsum > 0.0 ? sum / wsum : 0.0;
}

// Alg. 1: the footprint ellipse, its eccentricity clamp, the LOD and the
// blend of two levels, D = P22 / cos^4 theta_h (eq. 6).
vec3 glint_D(GlintQuery q) {
  vec3 h = q.h;
  // slopes beyond 1e6 reflect nothing at any alpha <= 1 (and h.z^4 stays normal)
  if (!(h.z > 1e-6)) return vec3(0.0);
  ChermainPixel px;
  px.slope = h.xy / h.z;
  px.alpha = max(q.alpha_g, vec2(1e-6));
  px.lmd_log4 = log(max(q.density, 1e-30)) * 0.72134752;  // 1 / ln 4
  px.area = q.microfacet_relative_area;
  px.sdx = vec2(0.0);
  px.sdy = vec2(0.0);
  if (q.ggaa > 0.5) {
    vec2 sdx, sdy;
    chermain_slope_derivatives(q, sdx, sdy);
    px.sdx = q.ggaa_kernel * sdx;
    px.sdy = q.ggaa_kernel * sdy;
  }
  // Alg. 1 lines 3-5: the longer derivative is the major axis; the minor one
  // is lengthened to at least major / max_anisotropy. Lengths are formed
  // after dividing by the largest component (no overflow of the squares).
  vec2 d0 = glint_clamp_derivative(q.duv_dx), d1 = glint_clamp_derivative(q.duv_dy);
  float mx = max(max(abs(d0.x), abs(d0.y)), max(abs(d1.x), abs(d1.y)));
  float major = 0.0, minor = 0.0;
  if (mx > 0.0) {
    float l0 = mx * length(d0 / mx), l1 = mx * length(d1 / mx);
    if (l0 < l1) {
      vec2 t = d0; d0 = d1; d1 = t;
      float tl = l0; l0 = l1; l1 = tl;
    }
    major = l0;
    minor = l1;
  }
  float aniso = max(q.max_anisotropy, 1.0);
  if (minor > 0.0 && minor * aniso < major) {
    float scale = major / (minor * aniso);
    d1 *= scale;
    minor *= scale;
  }
  float z2 = h.z * h.z;
  // "Without footprint, we evaluate the Cook Torrance BRDF"
  if (!(minor > 0.0)) return vec3(beckmann_p22(px.slope, px.alpha) / (z2 * z2));
  // Alg. 1 lines 6-8: l = max(0, L - 1 + log2(minor)), two levels blended.
  float l = clamp(float(CHERMAIN_LEVELS - 1) + log2(minor), 0.0, CHERMAIN_MAX_LEVEL);
  float lf = floor(l);
  int il = int(lf);
  float w = l - lf;
  vec2 uv = glint_clamp_uv(q.uv);
  float p22 = (1.0 - w) * chermain_level(px, il, uv, d0, d1);
  if (w > 0.0) p22 += w * chermain_level(px, il + 1, uv, d0, d1);
  return vec3(p22 / (z2 * z2));
}

#endif  // GLINTLAB_GLINT_MODELS_CHERMAIN_GLSL

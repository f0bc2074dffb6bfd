// The `zirr` glint model: Zirr & Kaplanyan 2016, "Real-time Rendering of
// Procedural Multiscale Materials", Listing 1 as a whole: the expected
// number of reflecting microdetails of every grid cell under the pixel
// footprint, drawn from a binomial distribution seeded per cell and per
// quantised half vector, filtered over two grid levels. Its truth is the
// explicit microstructure it filters, `grains`, supersampled.
// glint_model truth=grains limit=beckmann checks=finite,unbiased,limit,deterministic
// glint_parameter color_saturation default=0 range=0,1
// glint_parameter size_variation default=0 range=0,2
// glint_parameter half_vector_blend default=false type=bool
// color_saturation: coloured glints (sec. 4.5), 0 = white, 1 = the full colour
// wheel. size_variation: std. dev. of the per-cell microdetail-size factor
// (sec. 4.3, Listing 1 line 16). half_vector_blend (a glintlab extension; off:
// Listing 1 exactly): a cell's reflectance is the bilinear blend of its counts
// in the four half-vector bins nearest to h instead of the count of the one
// bin h falls in, so a glint fades as h moves across a bin boundary instead of
// being redrawn; the expectation per cell is unchanged.
#ifndef GLINTLAB_GLINT_MODELS_ZIRR_GLSL
#define GLINTLAB_GLINT_MODELS_ZIRR_GLSL

#include "glint/query.glsl"
#include "common/math.glsl"
#include "common/pcg3d.glsl"
#include "common/beckmann.glsl"
#include "common/normal_quantile.glsl"
#include "common/wrapped_floor.glsl"
#include "common/binomial.glsl"
#include "sand/glint_color.glsl"
#include "sand/glint_footprint.glsl"
#include "sand/glint_roughness.glsl"

#define GLINT_ZIRR_OFFSET_SALT 0x3C6EF372u  // rand(C) of Listing 1 line 12
#define GLINT_ZIRR_HALF_SALT 0xA54FF53Au    // seeds the quantised half vector (Hidx)

// Minimum of the per-cell size factor |gauss(1, size_variation)| (a factor
// near 0 would make one microdetail cover the cell at a huge reflectance).
#define GLINT_MIN_SIZE_FACTOR 1e-3

// Uniform in (0, 1) from the top 24 bits: (k + 0.5) 2^-24, so 1 - u is exact.
vec3 glint_open_unit(uvec3 h) { return (vec3(h >> 8u) + 0.5) * (1.0 / 16777216.0); }

// The paraboloid map of Listing 1 line 2: h.xy / (1 + h.z), "keeps the
// density of half vectors approximately uniform in solid angle" (sec. 4.3).
vec2 paraboloid_map(vec3 h) { return h.xy / (1.0 + max(h.z, 0.0)); }

// What Listing 1 computes once per pixel.
struct GlintZirrPixel {
  float pmf;  // eq. 7: P(h) = D_g(h) / D_l(0), line 6 (slope domain)
  float m0;   // D_l(0) = 1 / (pi alpha_l,u alpha_l,v), line 4
  vec2 hp;    // paraboloid half vector, line 2
};

GlintZirrPixel glint_zirr_pixel(vec3 h, GlintRoughness r) {
  GlintZirrPixel px;
  px.m0 = INV_PI / (r.alpha_l.x * r.alpha_l.y);
  // P22_g(x_h) / P22_l(0) <= (alpha_l / alpha_g)^2 <= 1 (alpha_l <= alpha_g)
  px.pmf = h.z > 0.0 ? clamp(beckmann_p22(h.xy / h.z, r.alpha_g) * PI * r.alpha_l.x * r.alpha_l.y, 0.0, 1.0) : 0.0;
  px.hp = paraboloid_map(h);
  return px;
}

// One cell C, Listing 1 lines 11-20: seed = the coherent seed of the cell
// (sec. 4.1); n_cell = area(C) density (line 14). Returns the cell
// reflectance Cr = rn m0 / Cn (line 20) times the colour tint (sec. 4.5).
//  - line 12: Hidx = quantize(Hp + m0 rand(C)): the half-vector cell of
//    Hp / h_cell, offset per cell by a uniform in [0, 1)^2 cells, so the
//    quantisation boundaries of neighbouring cells do not coincide (the
//    printed m0 rand(C) is read as "one quantisation cell times rand(C)";
//    m0 = D_l(0) itself is no offset in paraboloid units);
//  - line 16: Cn = n_cell |gauss(rand(Hidx + C), 1, size_variation)|, at
//    least GLINT_MIN_SIZE_FACTOR n_cell;
//  - line 18: rn = binomial(rand(Hidx + C), Cn, pmf) (common/binomial.glsl).
// rand(Hidx + C) is pcg3d of (seed, pcg3d(Hidx)): x the binomial's uniform,
// y the size factor's, z the rounding of a non-integer Cn; the hue comes
// from rand(C) ("a random albedo from the color wheel in each cell").
// E[Cr] = pmf m0 = D_g(h) in the slope domain for every cell (eq. 7), so
// any normalised weighting of cells converges to beckmann.
// The reflectance of cell `seed` in half-vector bin `hidx` (lines 16-20);
// `hue` = rand(C).z.
vec3 glint_zirr_bin(uvec2 seed, uvec2 hidx, float n_cell, BinomialSetup level, GlintZirrPixel px,
                    float size_variation, float saturation, float hue) {
  uvec3 hh = pcg3d(uvec3(seed, pcg3d(uvec3(hidx, GLINT_ZIRR_HALF_SALT)).x));
  vec3 u = glint_open_unit(hh);
  float Cn = n_cell;
  float rn;
  if (size_variation > 0.0) {
    Cn *= max(abs(1.0 + size_variation * normal_quantile(u.y)), GLINT_MIN_SIZE_FACTOR);
    rn = binomial_draw(Cn, px.pmf, u.x, u.z);
  } else {
    rn = binomial_draw(level, u.x, u.z);  // every cell of the level: the same n and P
  }
  if (!(rn > 0.0)) return vec3(0.0);
  return (rn * px.m0 / Cn) * glint_tint(hue, saturation, rn);
}

// hv_blend (the parameter half_vector_blend):
// instead of the one bin h falls in, the bilinear blend of the four bins
// whose centres surround it (bin k's centre at k + 1/2 in units of h_cell),
// so a glint fades in and out as h moves instead of being redrawn at a bin
// boundary. Each bin's expectation is P(h) m0, hence the blend's too.
vec3 glint_zirr_cell(uvec2 seed, float n_cell, BinomialSetup level, GlintZirrPixel px, GlintRoughness r,
                     float size_variation, float saturation, bool hv_blend) {
  vec3 uc = pcg3d_unit(pcg3d(uvec3(seed, GLINT_ZIRR_OFFSET_SALT)));
  vec2 harg = px.hp / r.h_cell + uc.xy;
  if (!hv_blend)
    return glint_zirr_bin(seed, wrapped_floor(harg), n_cell, level, px, size_variation, saturation, uc.z);
  vec2 q = harg - 0.5;
  vec2 f = q - floor(q);
  uvec2 b = wrapped_floor(q);
  vec3 acc = vec3(0.0);
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 d = uvec2(k & 1u, k >> 1u);
    float w = (d.x == 1u ? f.x : 1.0 - f.x) * (d.y == 1u ? f.y : 1.0 - f.y);
    if (w > 0.0) acc += w * glint_zirr_bin(seed, b + d, n_cell, level, px, size_variation, saturation, uc.z);
  }
  return acc;
}

// The estimate of one pixel: Listing 1 lines 7-24.
struct GlintZirr {
  vec3 D;       // NDF estimate at h per colour (P(h) m0 filtered, / h.z^4: slope domain -> directions)
  float cells;  // cells visited (weight > 0), both levels: the Fig. 9 visualisation
};

// uv: surface coordinates of the shading point (pixel centre); dx, dy: their
// screen derivatives (the footprint, sec. 4.2); h: the local half vector.
// Per level (line 9), the walk of sand/glint_footprint.glsl runs in the
// stretched uv of sec. 4.4 ("we stretch both the texture coordinates of the
// pixel center and the pixel footprint ... after footprint estimation and
// grid level selection"); a level-k cell is s_ref 2^k wide there and covers
// 4^k / (stretch.x stretch.y) reference areas, i.e. that many microdetails
// (line 14). Each level's cells are averaged with their coverage weights,
// "we normalize by the total weight afterwards", and the levels blended by
// mipWeight (line 24).
GlintZirr glint_zirr(vec2 uv, vec2 dx, vec2 dy, vec3 h, GlintRoughness r, float size_variation, float saturation,
                     bool hv_blend) {
  GlintZirr z;
  z.D = vec3(0.0);
  z.cells = 0.0;
  if (!(h.z > 0.0)) return z;
  GlintZirrPixel px = glint_zirr_pixel(h, r);
  if (!(px.pmf > 0.0)) return z;  // no microdetail can reflect (and h.z^4 may underflow)
  GlintFootprint fp = glint_footprint(dx, dy, r.s_ref);
  vec2 st_uv = glint_clamp_uv(uv) * r.stretch;
  vec2 st_dx = glint_clamp_derivative(dx) * r.stretch, st_dy = glint_clamp_derivative(dy) * r.stretch;
  vec3 reflectance = vec3(0.0);
  for (int g = 0; g < 2; ++g) {
    float mip_weight = g == 0 ? fp.weight0 : fp.weight1;
    if (!(mip_weight > 0.0)) continue;
    int level = g == 0 ? fp.level0 : fp.level1;
    float cell = r.s_ref * exp2(float(level));
    float n_cell = exp2(2.0 * float(level)) / (r.stretch.x * r.stretch.y);
    BinomialSetup level_draws = binomial_setup(n_cell, px.pmf);  // common/binomial.glsl: once per level
    GlintWalk w = glint_walk(st_uv, st_dx, st_dy, cell);
    vec3 acc = vec3(0.0);
    float wsum = 0.0;
    for (int col = 0; col < w.columns; ++col) {
      for (int row = 0; row < 2; ++row) {
        GlintCell c = glint_walk_cell(w, col, row);
        if (!(c.weight > 0.0)) continue;
        z.cells += 1.0;
        acc += c.weight * glint_zirr_cell(glint_coherent_seed(c.index, level), n_cell, level_draws, px, r,
                                          size_variation, saturation, hv_blend);
        wsum += c.weight;
      }
    }
    if (wsum > 0.0) reflectance += mip_weight * acc / wsum;
  }
  float z2 = h.z * h.z;
  z.D = reflectance / (z2 * z2);
  return z;
}

vec3 glint_D(GlintQuery q) {
  GlintZirr z = glint_zirr(q.uv, q.duv_dx, q.duv_dy, q.h, q.rough, q.size_variation, q.color_saturation,
                           q.half_vector_blend > 0.5);
  glint_cells_visited = z.cells;
  return z.D;
}

#endif  // GLINTLAB_GLINT_MODELS_ZIRR_GLSL

// The `deliot` glint model: Deliot & Belcour 2023, "Real-Time Rendering of
// Glinty Appearances using Distributed Binomial Laws on Anisotropic Grids"
// (Computer Graphics Forum, HPG 2023, doi:10.1111/cgf.14866), after the authors' published
// HLSL (SampleGlints2023NDF and its noise generator). The pixel footprint is
// the exact ellipse of the uv derivatives; the surface is covered by
// triangular (simplex) grids rotated to the ellipse's orientation, stretched
// by its power-of-two anisotropy and scaled to its power-of-two size, and the
// four grids of the tetrahedron around (orientation, anisotropy, size) are
// blended with barycentric weights. A grid vertex stands for a cell of N
// microfacets (N = cell area x a log-normally jittered density); each of the
// n = N w of them (w the grid's blend weight) reflects h with probability
// p = R D(h) / D_max, and the count of reflecting ones, drawn from an
// "at least one" gate and a Gaussian for the rest (the distributed binomial
// law), is read per half-vector texel of a 64 x 64 noise texture indexed by
// |h.xy| / R, bilinearly. The estimate sum(count / N) / R, clamped to 20,
// times D_max is the NDF. Its truth is the explicit microstructure `grains`.
// glint_model truth=grains limit=beckmann checks=finite,limit,deterministic fails=unbiased
// glint_parameter screen_space_scale default=1.5 range=1,8
// glint_parameter density_randomization default=2 range=0,5
// glint_parameter noise_size default=64 range=64,512
// glint_parameter floor_levels default=false type=bool
// screen_space_scale: the published _ScreenSpaceScale, "the minimal allowed
// size of a glint in pixels" (1 aliases; 1.5 is the authors' recommendation):
// the size LOD is lod = log2(sigma_min screen_space_scale / 2), sigma_min the
// ellipse's minor semi-axis (SampleGlints2023NDF, "MANUAL LOD COMPENSATION").
// density_randomization: the published _DensityRandomization, the standard
// deviation of the natural log of the density from vertex to vertex (the
// port's default, 2). noise_size: the side of the noise texture in texels
// (rounded to an integer): 64 as the published shader's texture and the
// port, 512 the default of the authors' standalone generator
// (Glints2023.cs). floor_levels: false (published) blends the grid levels
// (int)lod and (int)lod + 1 of SampleGlints2023NDF, a truncation toward zero:
// the LOD is negative in every real case, so the blended levels are
// floor(lod) + 1 and floor(lod) + 2, cells 0.75-1.5 px wide at the default
// scale; true blends floor(lod) and floor(lod) + 1 instead (cells half as
// wide, a quarter of the microfacets per vertex: an earlier glintlab rule,
// kept to measure what the level choice does).
//
// glintlab's common parameters:
//  - log_density: the method's exp(_LogMicrofacetDensity) is microfacets per
//    unit uv area, as glintlab's density 10^log_density is: the method's log
//    density is ln(q.density) (exact; a vertex of the triangular grid counts
//    the microfacets of one unit cell of the grid, 2/sqrt(3) times the area
//    that the vertex owns, as published);
//  - alpha_g (widened by the light cone): the target NDF D = beckmann_D with
//    q.alpha_g, D_max = D(n) = 1 / (pi alpha_u alpha_v);
//  - relative_roughness and light_cone: the published microfacet roughness R
//    (_MicrofacetRoughness, "the ad-hoc R ratio ... simulating a microfacet
//    roughness") is the microdetail lobe width sqrt(alpha_l,u alpha_l,v),
//    alpha_l = relative_roughness alpha_g widened by the light cone: one
//    noise texel spans R in h.xy (one microfacet's reflection lobe) and the
//    hit probability is R D / D_max. Approximate: R is one number (the
//    published method has no anisotropic texels), and R D / D_max is the
//    method's ad-hoc probability, not the solid-angle fraction
//    alpha_l^2 P22(h) that explicit microfacets of width alpha_l would have;
//    the expectation, R D / D_max / R D_max = D, does not depend on it.
//
// Sources, step by step (the published HLSL's functions; the port
// Glints2023.hlsli has the same names):
//  - the footprint ellipse: GetGradientEllipse -> deliot_footprint;
//  - the size LOD, the power-of-two ratio, the rotation bins and the
//    tetrahedron of the four blended grids: SampleGlints2023NDF ("MANUAL LOD
//    / ANISOTROPY RATIO / ANISOTROPY ROTATION COMPENSATION"),
//    GetAnisoCorrectingGridTetrahedron, GetBarycentricWeightsTetrahedron ->
//    deliot_grids;
//  - one grid: the skewed simplex cell, a random vector per vertex, the
//    jittered log density, the count N and the binomial's properties:
//    SampleGlintGridSimplex -> deliot_grid, deliot_binomial;
//  - the noise read at |h.xy| / R + a random offset: CustomRand4Texture ->
//    deliot_texel_count, deliot_noise (the generator: Glints2023.cs);
//  - the gate and the floored Gaussian, bilinearly:
//    GenerateAngularBinomialValueForSurfaceCell -> deliot_count,
//    deliot_texel_count;
//  - min(sum / R, 20) D_max: SampleGlints2023NDF -> glint_D.
//
// Where this differs from the published HLSL (none changes the expectation):
//  - the noise texture is not stored (no glint_table): each texel is a hash
//    of its index (deliot_noise), as the published generator's texels are (a
//    hash of the texel index drives a uniform and a Gaussian, independent
//    from texel to texel), so evaluating it where it is read gives the same
//    statistics without a table to generate, cache and bind; fp16 storage is
//    not emulated. Its cost: 3.4 of 15.1 ms per frame (160 x 90, llvmpipe),
//    the most a table could save;
//  - the four grids of the tetrahedron come from a staircase split of the
//    prism (triangle of orientation x anisotropy) x size, with every grid
//    keyed by integers (size level, log2 anisotropy, orientation bin) and the
//    orientation taken modulo 180 degrees; the published split differs inside
//    the prism, not at its faces, and its fourth grid samples the first
//    grid's rotation (a typo fixed here, as in Kneiphof's derived code);
//  - n - 1 < 0 gives no Gaussian part (the published sqrt of a negative is
//    NaN); P(at least one) = 1 - (1 - p)^n is formed without cancellation;
//  - the log density is clamped to [-50, 50] (published [0, 50], which would
//    raise log_density < 0 to one microfacet per unit area), the anisotropy
//    to 2^16 and the size level to [-40, 40] (finite grids for any input).
//
// The conformance check "unbiased" fails by what the published method does
// (fails=unbiased; `glintlab glint-test deliot`: 23.8 standard errors at
// the published levels, 39.6 with floor_levels, bound 5: the mean over uv is
// not D_g; worst at alpha 0.05 / 0.0125, log_density 8, view 0, h at the
// normal, a footprint of one microdetail: mean 297 against D_g 509). Three
// causes, each measured by removing it (llvmpipe, with floor_levels):
//  - the output clamp min(sum / R, 20): a footprint of one microdetail holds
//    a vertex of N < 1 microfacets whose one hit is 1 / (N R) >> 20; worst
//    -64 % (alpha 0.05 / 0.0125, log_density 8, view 60 deg, h at the
//    normal: mean 183.3 against D_g 509.3); without the clamp 12.2 errors;
//  - the Gaussian part: 1 + floor of the normal of Binomial(n - 1, p) has the
//    mean n p + 1/2 - p for n p >> 1, +1/2 count (+10 % at alpha 0.5 over
//    256 microdetails, density_randomization 0: 71 standard errors; the
//    unfloored normal is worse, +1 - p, 156);
//  - the 64 x 64 texture: at a fixed h every vertex reads the same bilinear
//    mix of texels, so the mean over uv is over its 4096 gates, whose share
//    below P1 differs from P1 by ~ sqrt(P1 / 4096) (with the exact binomial
//    per texel and no clamp: 7.5 errors, -6 % at alpha 0.05 / 0.0125,
//    log_density 1, view 85 deg; 4.95 with the default density
//    randomisation, which spreads P1); noise_size 512 reads 262144 gates
//    (21.0 errors with the other defaults).
// "limit" passes at 0.85 % (bound 3; 2.98 % with floor_levels): the noise of
// vertices whose jittered density is e^-6 of the mean, four times as many
// microfacets a vertex at the published levels (0.53 % with floor_levels
// and density_randomization 0).
#ifndef GLINTLAB_GLINT_MODELS_DELIOT_GLSL
#define GLINTLAB_GLINT_MODELS_DELIOT_GLSL

#include "glint/query.glsl"
#include "common/math.glsl"
#include "common/pcg3d.glsl"
#include "common/beckmann.glsl"
#include "common/normal_quantile.glsl"
#include "common/wrapped_floor.glsl"
#include "sand/glint_footprint.glsl"

#define DELIOT_NOISE_SALT 0x510E527Fu  // decorrelates the texel hash from the grids'
#define DELIOT_GRID_SALT 0x9B05688Cu
#define DELIOT_MAX_OUTPUT 20.0         // the published clamp of sum / R ("grazing angle extremities")
#define DELIOT_MIN_COUNT 1e-8          // the published floor of a vertex's microfacet count
#define DELIOT_MAX_LN_COUNT 69.0       // N <= e^69 ~ 1e30: finite in fp32 with all it is multiplied by
#define DELIOT_MAX_LN_DENSITY 50.0     // the published clamp of the jittered log density
#define DELIOT_MAX_LEVEL 40.0          // grid cells 2^-40 .. 2^40 uv wide
#define DELIOT_MAX_RATIO_EXP 16        // anisotropy up to 2^16

// ---------------------------------------------------------------- noise texture

// Texel t of the noise texture (wrapped to size x size): x a uniform in (0, 1)
// (the gate), y a standard normal (the Gaussian's draw). The published
// generator hashes the texel index (Wang hash, then xorshift) into one
// uniform and one normal (erfinv of a second uniform) per texel, independent
// from texel to texel; here pcg3d of the index, 24-bit uniforms
// (k + 0.5) 2^-24 and normal_quantile (the same erfinv approximation).
vec2 deliot_noise(uvec2 t, uint size) {
  uvec3 h = pcg3d(uvec3(t % size, DELIOT_NOISE_SALT));
  vec2 u = (vec2(h.xy >> 8u) + 0.5) * (1.0 / 16777216.0);
  return vec2(u.x, normal_quantile(u.y));
}

// ---------------------------------------------------------------- distributed binomial law

// The count of reflecting microfacets among n, each reflecting with
// probability p, as the method draws it: a gate "at least one reflects"
// with the exact probability 1 - (1 - p)^n, and given one, 1 + the
// remaining n - 1 drawn from the Gaussian of Binomial(n - 1, p) (mean
// (n - 1) p, variance (n - 1) p (1 - p)), floored and clamped to [0, n].
// The gate is smoothed by a linear ramp of half-width
// 0.1 min(1, 10 P1) min(1, 10 (1 - P1)) around P1, which keeps
// E[gate] = P1 (the ramp stays inside [0, 1]).
struct DeliotBinomial {
  float n;      // microfacets (real)
  float p1;     // P(at least one reflects)
  float ramp;   // half-width of the gate's ramp
  float mean;   // of the Gaussian part
  float sd;
};

DeliotBinomial deliot_binomial(float n, float p) {
  DeliotBinomial b;
  b.n = max(n, 0.0);
  p = clamp(p, 0.0, 1.0);
  // x = n ln(1 - p) <= 0; P1 = -expm1(x), by its series where 1 - exp(x) would cancel
  float x = b.n * safe_log1p(-p);
  b.p1 = x > -1e-3 ? -x * (1.0 + x * (0.5 + x * (1.0 / 6.0))) : 1.0 - exp(max(x, -88.0));
  b.p1 = clamp(b.p1, 0.0, 1.0);
  b.ramp = 0.1 * clamp(10.0 * b.p1, 0.0, 1.0) * clamp(10.0 * (1.0 - b.p1), 0.0, 1.0);
  float rest = max(b.n - 1.0, 0.0);
  b.mean = rest * p;
  b.sd = sqrt(b.mean * (1.0 - p));
  return b;
}

// One draw from the texel's uniform u (gate) and normal g.
float deliot_count(DeliotBinomial b, float u, float g) {
  float gate = b.ramp > 1e-7 ? saturate((b.p1 + b.ramp - u) / (2.0 * b.ramp)) : (u < b.p1 ? 1.0 : 0.0);
  float more = clamp(floor(g * b.sd + b.mean), 0.0, b.n);
  return gate * (1.0 + more);
}

// The counts of the four texels around |h.xy| / R, offset per vertex by
// `offset` (in [0, 1)^2, times the texture size), bilinearly interpolated
// (SampleGlintGridSimplex: the texture read at slope / R + random offset).
float deliot_texel_count(DeliotBinomial b, vec2 slope_r, vec2 offset, uint size) {
  vec2 s = slope_r + offset * float(size);  // >= 0 and < 1e4 + 512: uint() is defined
  vec2 f = fract(s);
  uvec2 t = uvec2(floor(s)) % size;
  vec2 n00 = deliot_noise(t, size), n10 = deliot_noise(t + uvec2(1u, 0u), size);
  vec2 n01 = deliot_noise(t + uvec2(0u, 1u), size), n11 = deliot_noise(t + uvec2(1u, 1u), size);
  float c0 = mix(deliot_count(b, n00.x, n00.y), deliot_count(b, n10.x, n10.y), f.x);
  float c1 = mix(deliot_count(b, n01.x, n01.y), deliot_count(b, n11.x, n11.y), f.x);
  return mix(c0, c1, f.y);
}

// ---------------------------------------------------------------- the footprint's grids

// One of the blended grids: size level L (cells 2^L uv wide across), ratio
// exponent e (cells 2^e times longer along the ellipse's major axis),
// orientation bin k (angle k pi / 2^(max(e, 1) + 2) from the v axis; e = 0
// is unrotated), and its blend weight.
struct DeliotGrid {
  int level;
  int e;
  uint k;
  float weight;
};

// The orientation bin width of a ratio exponent: pi/4 / max(2^e, 2), as
// published (90 degrees / max(ratio, 2), halved).
float deliot_bin_width(int e) { return (0.25 * PI) / exp2(float(max(e, 1))); }
uint deliot_bin_count(int e) { return 4u << uint(max(e, 1)); }

// The footprint: the ellipse that M = [dx dy] maps the unit pixel disk to
// (GetGradientEllipse), its semi-axes from glint_ellipse_axes; the major
// axis is the eigenvector of the larger eigenvalue of M M^T = [a b; b d],
// at the angle 0.5 atan2(2b, a - d) from the u axis (SampleGlints2023NDF
// measures theta from the v axis). M is divided by its largest entry before
// the products (no overflow).
struct DeliotFootprint {
  float lod;    // log2(sigma_min screen_space_scale / 2), in [-40, 40]
  float ratio;  // sigma_max / sigma_min, in [1, 2^16]
  float psi;    // angle of the major axis from the v axis, in [0, pi)
};

DeliotFootprint deliot_footprint(vec2 dx, vec2 dy, float screen_space_scale) {
  DeliotFootprint f;
  f.lod = -DELIOT_MAX_LEVEL;
  f.ratio = 1.0;
  f.psi = 0.0;
  vec2 axes = glint_ellipse_axes(dx, dy);
  if (!(axes.x > 0.0)) return f;  // no footprint: the finest cells, unrotated
  float smin = max(axes.y, axes.x * exp2(-float(DELIOT_MAX_RATIO_EXP)));
  f.ratio = clamp(axes.x / smin, 1.0, exp2(float(DELIOT_MAX_RATIO_EXP)));
  f.lod = clamp(log2(smin * 0.5 * screen_space_scale), -DELIOT_MAX_LEVEL, DELIOT_MAX_LEVEL);
  dx = glint_clamp_derivative(dx);
  dy = glint_clamp_derivative(dy);
  float m = max(max(abs(dx.x), abs(dx.y)), max(abs(dy.x), abs(dy.y)));
  dx /= m;
  dy /= m;
  float b = dx.x * dx.y + dy.x * dy.y;
  float h = 0.5 * ((dx.x * dx.x + dy.x * dy.x) - (dx.y * dx.y + dy.y * dy.y));
  // a circle has no major axis
  float from_u = (h == 0.0 && b == 0.0) ? 0.5 * PI : 0.5 * atan(2.0 * b, 2.0 * h);
  float psi = from_u - 0.5 * PI;
  psi -= PI * floor(psi / PI);
  f.psi = psi < PI ? psi : 0.0;
  return f;
}

// The blended grids of the footprint (at most 4 with weight > 0). The
// parameter space (orientation x, anisotropy y, size z) is cut into prisms:
// per anisotropy octave [2^e0, 2^e1], e1 = e0 + 1, the bottom row has the
// orientation bins of e0 (x = 0 and 1), the top row those of e1, twice as
// fine (x = 0, 1/2, 1), triangulated as (b a c), (b d c), (d c e) with b, d
// the bottom and a, c, e the top vertices; e0 = 0 has one unrotated bottom
// vertex and the top vertices at x = 0, 1. The vertices of the triangle
// around (x, y) get barycentric weights lambda; times the two size levels
// (z = fract(lod)), the prism is split into three tetrahedra by the
// staircase rule: ordering the triangle's vertices globally (by e, then x),
// the weight of (vertex i, level j) is the overlap of the i-th interval of
// the cumulative lambdas with the j-th of (1 - z, z). Neighbouring prisms
// order their shared vertices alike, so the weights are continuous in
// (orientation, anisotropy, size) and sum to 1. The two size levels are
// those of SampleGlints2023NDF (trunc(lod) and the next; with floor_levels,
// floor(lod) and the next): the published levels jump by one where lod
// crosses an integer < 0 (at that integer only) or 0, as published.
void deliot_grids(DeliotFootprint f, bool floor_levels, out DeliotGrid g[4]) {
  float e0f = min(floor(log2(f.ratio)), float(DELIOT_MAX_RATIO_EXP));
  int e0 = int(e0f), e1 = e0 + 1;
  float y = clamp(f.ratio / exp2(e0f) - 1.0, 0.0, 1.0);
  float q = f.psi / deliot_bin_width(e0);
  float kf = floor(q);
  float x = clamp(q - kf, 0.0, 1.0);
  uint k0 = uint(clamp(kf, 0.0, float(deliot_bin_count(e0) - 1u)));
  int ve[3];
  uint vk[3];
  float lam[3];
  if (e0 == 0) {
    ve[0] = 0; vk[0] = 0u; lam[0] = 1.0 - y;  // the unrotated isotropic grid
    ve[1] = e1; vk[1] = k0; lam[1] = y * (1.0 - x);
    ve[2] = e1; vk[2] = k0 + 1u; lam[2] = y * x;
  } else if (2.0 * x <= y) {  // (b a c)
    ve[0] = e0; vk[0] = k0; lam[0] = 1.0 - y;
    ve[1] = e1; vk[1] = 2u * k0; lam[1] = y - 2.0 * x;
    ve[2] = e1; vk[2] = 2u * k0 + 1u; lam[2] = 2.0 * x;
  } else if (2.0 * (1.0 - x) <= y) {  // (d c e)
    ve[0] = e0; vk[0] = k0 + 1u; lam[0] = 1.0 - y;
    ve[1] = e1; vk[1] = 2u * k0 + 1u; lam[1] = 2.0 * (1.0 - x);
    ve[2] = e1; vk[2] = 2u * k0 + 2u; lam[2] = y - 2.0 * (1.0 - x);
  } else {  // (b d c)
    ve[0] = e0; vk[0] = k0; lam[0] = 1.0 - x - 0.5 * y;
    ve[1] = e0; vk[1] = k0 + 1u; lam[1] = x - 0.5 * y;
    ve[2] = e1; vk[2] = 2u * k0 + 1u; lam[2] = y;
  }
  // SampleGlints2023NDF: lod0 = (int)lod (toward zero), lodLerp = frac(lod) = lod - floor(lod)
  float L0 = floor_levels ? floor(f.lod) : trunc(f.lod);
  float z = f.lod - floor(f.lod);
  float F[3] = float[3](max(lam[0], 0.0), max(lam[0], 0.0) + max(lam[1], 0.0), 1.0);
  float G0 = 1.0 - z;
  int i = 0, j = 0;
  float prev = 0.0;
  for (int s = 0; s < 4; ++s) {
    float end = j == 0 ? min(F[i], G0) : F[i];
    g[s].level = int(L0) + j;
    g[s].e = ve[i];
    g[s].k = vk[i] % deliot_bin_count(ve[i]);
    g[s].weight = max(end - prev, 0.0);
    prev = max(prev, end);
    if (j == 0 && (i == 2 || G0 <= F[i])) j = 1;
    else i = min(i + 1, 2);
  }
}

// ---------------------------------------------------------------- one grid

// The estimate of one grid: the triangle of its simplex lattice around uv,
// per vertex sum(count) / N, interpolated with the triangle's barycentric
// weights. Grid coordinates: uv rotated by -phi (phi the bin's angle from
// the v axis, so the grid's long axis follows the ellipse's major axis),
// divided by 2^L across and 2^(L + e) along; the triangular lattice is the
// integer lattice of the skewed coordinates (x - y / sqrt(3), 2 y / sqrt(3)).
// A vertex's cell (one unit cell of the grid) is 4^L 2^e uv in area.
float deliot_grid(DeliotGrid g, vec2 uv, vec2 slope_r, float p, float ln_density, float density_sd, uint noise_size,
                  inout float cells) {
  float phi = float(g.k) * deliot_bin_width(g.e);
  if (g.e == 0) phi = 0.0;
  float c = cos(phi), s = sin(phi);
  vec2 r = vec2(c * uv.x + s * uv.y, c * uv.y - s * uv.x);
  vec2 gp = r * exp2(-float(g.level)) * vec2(1.0, exp2(-float(g.e)));
  vec2 sk = vec2(gp.x - 0.57735027 * gp.y, 1.15470054 * gp.y);
  uvec2 base = wrapped_floor(sk);
  vec2 fr = clamp(sk - floor(sk), 0.0, 1.0);
  bool upper = fr.x + fr.y > 1.0;
  uvec2 v[3];
  float bw[3];
  if (upper) {
    v[0] = base + uvec2(1u, 1u); bw[0] = fr.x + fr.y - 1.0;
    v[1] = base + uvec2(1u, 0u); bw[1] = 1.0 - fr.y;
    v[2] = base + uvec2(0u, 1u); bw[2] = 1.0 - fr.x;
  } else {
    v[0] = base; bw[0] = 1.0 - fr.x - fr.y;
    v[1] = base + uvec2(0u, 1u); bw[1] = fr.y;
    v[2] = base + uvec2(1u, 0u); bw[2] = fr.x;
  }
  uint seed = pcg3d(uvec3(uint(g.level + 64), (uint(g.e) << 24u) | g.k, DELIOT_GRID_SALT)).x;
  float ln_area = (2.0 * float(g.level) + float(g.e)) * 0.69314718;
  float acc = 0.0;
  for (int t = 0; t < 3; ++t) {
    if (!(bw[t] > 0.0)) continue;
    cells += 1.0;
    vec3 u = (vec3(pcg3d(uvec3(v[t], seed)) >> 8u) + 0.5) * (1.0 / 16777216.0);
    float ld = clamp(ln_density + density_sd * normal_quantile(u.x), -DELIOT_MAX_LN_DENSITY, DELIOT_MAX_LN_DENSITY);
    float N = exp(clamp(ln_area + ld, log(DELIOT_MIN_COUNT), DELIOT_MAX_LN_COUNT));
    DeliotBinomial b = deliot_binomial(N * g.weight, p);
    acc += bw[t] * deliot_texel_count(b, slope_r, u.yz, noise_size) / N;
  }
  return acc;
}

// ---------------------------------------------------------------- the NDF

vec3 glint_D(GlintQuery q) {
  glint_cells_visited = 0.0;
  if (!(q.h.z > 0.0)) return vec3(0.0);
  float D_max = INV_PI / (q.alpha_g.x * q.alpha_g.y);
  float D = beckmann_D(q.h, vec2(0.0), q.alpha_g);
  float R = clamp(sqrt(q.alpha_l.x * q.alpha_l.y), 1e-4, 1.0);
  float p = clamp(R * (D / D_max), 0.0, 1.0);
  if (!(p > 0.0)) return vec3(0.0);
  DeliotFootprint f = deliot_footprint(q.duv_dx, q.duv_dy, max(q.screen_space_scale, 1.0));
  DeliotGrid g[4];
  deliot_grids(f, q.floor_levels > 0.5, g);
  vec2 uv = glint_clamp_uv(q.uv);
  vec2 slope_r = abs(q.h.xy) / R;  // orthographic slope grid, as published
  float ln_density = log(max(q.density, 1e-30));
  float sd = clamp(q.density_randomization, 0.0, 5.0);
  uint noise_size = uint(clamp(round(q.noise_size), 64.0, 512.0));
  float cells = 0.0;
  float sum = 0.0;
  for (int i = 0; i < 4; ++i)
    if (g[i].weight > 0.0) sum += deliot_grid(g[i], uv, slope_r, p, ln_density, sd, noise_size, cells);
  glint_cells_visited = cells;
  return vec3(min(sum / R, DELIOT_MAX_OUTPUT) * D_max);
}

#endif  // GLINTLAB_GLINT_MODELS_DELIOT_GLSL

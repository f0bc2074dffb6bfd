// Pixel footprint, grid levels, the walk over the covered cells and the
// coherent cell seeds of the zirr glint model (Zirr & Kaplanyan 2016
// sec. 4.1-4.2, Fig. 3, 4, 6; Listing 1 lines 7, 10, 22, 24).
#ifndef GLINTLAB_SAND_GLINT_FOOTPRINT_GLSL
#define GLINTLAB_SAND_GLINT_FOOTPRINT_GLSL

#include "common/math.glsl"
#include "common/wrapped_floor.glsl"

#define GLINT_K_A 16.0          // sec. 4.2: maximum anisotropy K_a
#define GLINT_MAX_LEVEL 28      // coarsest grid level (cells 2^28 reference cells wide; see glint_coherent_seed)
#define GLINT_MAX_COLUMNS 40    // bound of the walk (reached only by footprints beyond level 28)

// uv coordinates are clamped to +-1e20 (cell coordinates stay finite in fp32;
// NaN reads as 0).
vec2 glint_clamp_uv(vec2 uv) {
  return clamp(vec2(isnan(uv.x) ? 0.0 : uv.x, isnan(uv.y) ? 0.0 : uv.y), vec2(-1e20), vec2(1e20));
}

// Derivatives are sanitised: NaN -> 0, |x| clamped to 1e20 (an infinite
// footprint covers everything; its cells stay finite).
vec2 glint_clamp_derivative(vec2 d) {
  return clamp(vec2(isnan(d.x) ? 0.0 : d.x, isnan(d.y) ? 0.0 : d.y), vec2(-1e20), vec2(1e20));
}

// The semi-axes (sigma_max, sigma_min) of the pixel footprint's ellipse, the
// image of the unit pixel disk under M = [dx dy] (the ellipse of Heckbert's
// EWA, which Deliot & Belcour 2023 and Kemppinen et al. 2025 filter over):
// the singular values of M, the square roots of the eigenvalues of
// M M^T = [a b; b d], a = dx.x^2 + dy.x^2, b = dx.x dx.y + dy.x dy.y,
// d = dx.y^2 + dy.y^2. M is divided by its largest entry first (no
// overflow), and sigma_min is |det M| / sigma_max (no cancellation). (0, 0)
// where the footprint is zero or below 1e-30.
vec2 glint_ellipse_axes(vec2 dx, vec2 dy) {
  dx = glint_clamp_derivative(dx);
  dy = glint_clamp_derivative(dy);
  float m = max(max(abs(dx.x), abs(dx.y)), max(abs(dy.x), abs(dy.y)));
  if (!(m > 1e-30)) return vec2(0.0);
  dx /= m;
  dy /= m;
  float a = dx.x * dx.x + dy.x * dy.x, b = dx.x * dx.y + dy.x * dy.y, d = dx.y * dx.y + dy.y * dy.y;
  float h = 0.5 * (a - d);
  float smax = sqrt(0.5 * (a + d) + sqrt(h * h + b * b));  // >= 1/sqrt(2): some entry is 1
  return m * vec2(smax, abs(dx.x * dy.y - dx.y * dy.x) / smax);
}

struct GlintFootprint {
  float s_c;      // cell size of sec. 4.2 after the K_a clamp (uv)
  float level_f;  // log2(s_c / s_ref); -1 for a zero footprint
  int level0;     // the finer grid level (0 = reference: one microdetail per cell)
  int level1;     // the coarser one (= level0 + 1, or level0 when clamped)
  float weight0;  // mipWeight of level0 (Listing 1 line 24): linear in log2
  float weight1;  // of level1; weight0 + weight1 = 1
};

// Listing 1 line 7 "find grids G[0], G[1] in footprint(P)". The footprint is
// the parallelogram spanned by dx = d(uv)/dx and dy = d(uv)/dy (Fig. 6).
// sec. 4.2: s_c = 1 / ||M^-1||_max with M = [dx dy] and ||.||_max the largest
// absolute entry, i.e. s_c = |det M| / max|M_ij|: the shorter distance
// between parallel edges, measured along the texture axes. "We limit the
// anisotropy to a factor of K_a by enforcing ||M||_max / K_a as a lower
// bound for the cell size". M is divided by max|M_ij| before the determinant
// (no overflow). Fig. 3: the cell size is rounded to the powers of two below
// and above, relative to the reference cell s_ref; levels below 0 are not
// used (a footprint smaller than one microdetail sees the microdetail itself,
// as grains does) and levels above GLINT_MAX_LEVEL are clamped.
GlintFootprint glint_footprint(vec2 dx, vec2 dy, float s_ref) {
  dx = glint_clamp_derivative(dx);
  dy = glint_clamp_derivative(dy);
  GlintFootprint f;
  float m = max(max(abs(dx.x), abs(dx.y)), max(abs(dy.x), abs(dy.y)));
  if (m > 0.0) {
    vec2 a = dx / m, b = dy / m;
    f.s_c = max(m * abs(a.x * b.y - a.y * b.x), m / GLINT_K_A);
    f.level_f = log2(f.s_c / s_ref);
  } else {
    f.s_c = 0.0;
    f.level_f = -1.0;
  }
  if (!(f.level_f > 0.0)) {
    f.level0 = 0; f.level1 = 0; f.weight0 = 1.0; f.weight1 = 0.0;
  } else if (f.level_f >= float(GLINT_MAX_LEVEL)) {
    f.level0 = GLINT_MAX_LEVEL; f.level1 = GLINT_MAX_LEVEL; f.weight0 = 1.0; f.weight1 = 0.0;
  } else {
    float k = floor(f.level_f);
    f.level0 = int(k);  // in [0, 27]
    f.level1 = f.level0 + 1;
    f.weight1 = f.level_f - k;
    f.weight0 = 1.0 - f.weight1;
  }
  return f;
}

// The walk over one grid (sec. 4.2, Fig. 6), in units of that grid's cells
// (integer cell corners, cell (i, j) centred at (i + 0.5, j + 0.5)):
// "we step along the longer median of the pixel parallelogram" (the median
// parallel to the longer of dx, dy in the max-norm); along its dominant axis
// j the steps are one cell apart, "the first and last steps are offset
// towards the pixel center by half a cell size each". Here the steps are
// continuous: column n (the cells with j-coordinate n) gets the tent
// (bilinear) weight of its centre n + 0.5 integrated over the walked range
// [t_lo, t_hi] of the j coordinate, so a moving footprint changes the weights
// continuously; at the median's point with j = n + 0.5 (clamped to the range)
// the two nearest cells along the other axis get bilinear weights (Fig. 6's
// distances from the cell centres). A median shorter than a cell is a single
// bilinear tap at the centre.
struct GlintWalk {
  vec2 c;         // footprint centre (cells)
  int j;          // walked axis: 0 = u, 1 = v
  float slope;    // d(other axis) / d(walked axis) along the median
  float t_lo;     // walked range of the j coordinate (cells)
  float t_hi;
  float first;    // first column (integer-valued)
  int columns;    // columns to visit, each with up to 2 cells
};

// uv, dx, dy in stretched uv (sec. 4.4), `cell` the grid's cell size there.
// uv is clamped to +-1e20 and the derivatives as above, so every quantity is
// finite. The walked range is cut to GLINT_MAX_COLUMNS - 2 cells around the
// centre (only a footprint wider than 2^28 reference cells gets there).
GlintWalk glint_walk(vec2 uv, vec2 dx, vec2 dy, float cell) {
  GlintWalk w;
  w.c = glint_clamp_uv(uv) / cell;
  vec2 a = glint_clamp_derivative(dx) / cell, b = glint_clamp_derivative(dy) / cell;
  vec2 A = max(abs(a.x), abs(a.y)) >= max(abs(b.x), abs(b.y)) ? a : b;  // the longer median
  w.j = abs(A.x) >= abs(A.y) ? 0 : 1;
  float Aj = w.j == 0 ? A.x : A.y, Ai = w.j == 0 ? A.y : A.x;
  w.slope = Aj != 0.0 ? Ai / Aj : 0.0;  // |slope| <= 1
  float half_len = clamp(0.5 * abs(Aj) - 0.5, 0.0, 0.5 * float(GLINT_MAX_COLUMNS - 2));
  float cj = w.j == 0 ? w.c.x : w.c.y;
  w.t_lo = cj - half_len;
  w.t_hi = cj + half_len;
  // columns n with |t - (n + 0.5)| < 1 for some t in [t_lo, t_hi]
  w.first = floor(w.t_lo - 0.5);
  float last = ceil(w.t_hi + 0.5) - 1.0;
  w.columns = int(clamp(last - w.first + 1.0, 1.0, float(GLINT_MAX_COLUMNS + 2)));
  return w;
}

// Integral of the unit tent max(0, 1 - |x|) from -inf to x.
float glint_tent_integral(float x) {
  if (x <= -1.0) return 0.0;
  if (x <= 0.0) return 0.5 * (x + 1.0) * (x + 1.0);
  if (x < 1.0) return 1.0 - 0.5 * (1.0 - x) * (1.0 - x);
  return 1.0;
}

struct GlintCell {
  uvec2 index;   // cell coordinates on its grid, wrapped to uint (common/wrapped_floor.glsl)
  float weight;  // approximate coverage, Listing 1 line 22 (0: not covered)
};

// Cell `row` (0 or 1) of column `column` (0 .. columns - 1) of the walk.
GlintCell glint_walk_cell(GlintWalk w, int column, int row) {
  float n = w.first + float(column);
  float len = w.t_hi - w.t_lo;
  float wc;
  if (len > 1e-3) {
    wc = (glint_tent_integral(w.t_hi - n - 0.5) - glint_tent_integral(w.t_lo - n - 0.5)) / len;
  } else {
    wc = max(0.0, 1.0 - abs(0.5 * (w.t_lo + w.t_hi) - n - 0.5));
  }
  float t = clamp(n + 0.5, w.t_lo, w.t_hi);
  float ci = w.j == 0 ? w.c.y : w.c.x, cj = w.j == 0 ? w.c.x : w.c.y;
  float x = ci + (t - cj) * w.slope - 0.5;
  float m = floor(x);
  float f = x - m;
  GlintCell c;
  c.weight = max(wc, 0.0) * (row == 0 ? 1.0 - f : f);
  uint col_index = wrapped_floor(n);
  uint row_index = wrapped_floor(m) + uint(row);
  c.index = w.j == 0 ? uvec2(col_index, row_index) : uvec2(row_index, col_index);
  return c;
}

// Coherent multilevel seeds (sec. 4.1, Fig. 4): a cell of level k and its
// child with even coordinates on level k - 1 must get the same seed. The
// cell coordinates are offset by a constant uv offset (O_u, O_v) =
// (0x50000000, 0x30000000) reference cells, i.e. (O >> k) cells on level k
// (exact: O is a multiple of 2^28, hence GLINT_MAX_LEVEL) -- "we decorrelate
// the results by adding an arbitrary constant coordinate offset at every
// level" -- then both coordinates are shifted right by their common
// trailing zeros ("i >> trailingZeros(i)", taken jointly in 2D so that
// (2i, j) and (i, j) stay distinct): (2i, 2j) on level k - 1 reduces to the
// same pair as (i, j) on level k. With the offset, the index range of any
// level spans less than a factor 2, so no two cells of one level share a
// seed (up to 2^28 reference cells from the origin).
uvec2 glint_coherent_seed(uvec2 cell, int level) {
  uvec2 c = cell + (uvec2(0x50000000u, 0x30000000u) >> uint(level));
  int tz = min(c.x == 0u ? 32 : findLSB(c.x), c.y == 0u ? 32 : findLSB(c.y));
  return tz >= 32 ? uvec2(0u) : c >> uint(tz);
}

#endif  // GLINTLAB_SAND_GLINT_FOOTPRINT_GLSL

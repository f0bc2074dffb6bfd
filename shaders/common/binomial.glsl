// The number of reflecting microdetails in a cell: a binomial draw
// B(xi, n, P) (Zirr & Kaplanyan 2016 sec. 4.3 "Sampling the Binomial
// Distribution", Listing 1 line 18), deterministic for a given seed.
#ifndef GLINTLAB_COMMON_BINOMIAL_GLSL
#define GLINTLAB_COMMON_BINOMIAL_GLSL

#include "common/math.glsl"
#include "common/normal_quantile.glsl"

// Means up to BINOMIAL_EXACT_MEAN are drawn by inverting the exact CDF
// ("we only compute the exact distribution for small expected numbers"),
// at most BINOMIAL_MAX_ITERATIONS steps, then the exponential tail of
// sec. 4.3; larger means by the Gaussian fit. P(N > 48) < 6e-6 at mean 24,
// so the tail is rare.
#define BINOMIAL_EXACT_MEAN 24.0
#define BINOMIAL_MAX_ITERATIONS 48

// The tail of sec. 4.3 after i iterations, for a draw u beyond F(i) = P(N <= i):
//   N = i + 1 + log_q(1 - C (u - F(i)) / (1 - F(i))),  C = 1 - q^(n - i - 1),
// truncated to an integer count (floor), which lies in [i + 1, n - 1] for the
// exact values; q in (0, 0.5] (the ratio of the geometric tail; the paper
// writes p, here the smaller of p and 1 - p, see binomial_draw), n an integer
// > i + 1, passed as lnq = ln q < 0. log_q x = ln x / ln q, with ln(1 - y)
// from safe_log1p.
float binomial_tail(float i, float n, float lnq, float u, float F_i) {
  float C = 1.0 - exp((n - i - 1.0) * lnq);  // in [1/2, 1): n - i - 1 >= 1, lnq <= -ln 2
  float v = clamp((u - F_i) / max(1.0 - F_i, 1e-30), 0.0, 1.0);
  float t = safe_log1p(-min(C * v, 1.0 - 5.96e-8)) / lnq;
  return min(i + 1.0 + floor(max(t, 0.0)), n);
}

// Draws N ~ Binomial(n, p) from uniforms u in (0, 1) (the count) and
// u_round in [0, 1). Listing 1 line 16 makes n real (a cell's expected number
// of microdetails); a non-integer n is rounded up with probability frac(n)
// (randomised rounding: E[N] = n p stays exact). By symmetry, p > 1/2 draws
// n - Binomial(n, 1 - p), so the inverted tail is the short one and q <= 1/2.
//  - mean n q <= 24: inversion of the exact CDF from N = 0 by the recurrence
//    P(k+1) = P(k) (n - k) / (k + 1) q / (1 - q), P(0) = exp(n ln(1 - q))
//    (safe_log1p: q = 1e-12, n = 1e12 gives P(0) = 1/e, not 1);
//  - larger means (variance > 12): the Gaussian of the paper, fitted to the
//    first two moments (mean n q, variance n q (1 - q)), here with the
//    Cornish-Fisher terms of the third and fourth cumulants added
//    (z' = z + g (z^2 - 1)/6 + k (z^3 - 3z)/24 - g^2 (2z^3 - 5z)/36,
//    g = (1 - 2q)/sigma, k = (1 - 6 q (1 - q))/sigma^2), so the draw matches
//    the binomial to ~1e-3 in the CDF where the plain Gaussian is off by
//    up to 1.3e-2; rounded to the nearest count and clamped to [0, n].
// The result is an integer-valued float (counts up to 1e12 and beyond are
// never converted to int; beyond 2^24 they are the fp32 value nearest to the
// draw); finite and in [0, n] for any input (n is clamped to [0, 1e30], p to
// [0, 1], NaN read as 0).
//
// The draw is split in two: binomial_setup(n, p) computes everything that
// depends on n and p alone, for both counts the rounding can give (floor(n)
// and floor(n) + 1): P(0), ln q and the Gaussian's sigma and cumulant terms.
// Every cell of one grid level under one pixel draws from the same n and p
// (glint/models/zirr.glsl), so it sets up once and draws per cell with only
// the loop, the tail and the quantile left. On llvmpipe, which runs every
// branch for every lane, the zirr variant of the default experiment's frame 4
// (320x180) went from 47.1, 42.9, 43.8 to 43.0, 41.0, 40.7 ms (interleaved
// runs), with bit-identical images. binomial_draw(n, p, u, u_round) is one draw:
// it sets up only the count its rounding gives. The split changes no value
// (the same fp32 operations on the same operands).
struct BinomialSetup {
  float n_floor;  // floor(n) of the clamped n
  float n_frac;   // n - floor(n): a draw rounds up where u_round < n_frac
  bool flip;      // p > 1/2: the count of 1 - p is inverted
  float p;        // p clamped to [0, 1]
  float q;        // min(p, 1 - p)
  float ratio;    // q / (1 - q)
  float lnq;      // ln q (the tail)
  // for the count rounded down (x) and up (y):
  vec2 mean;      // n q
  vec2 p0;        // P(N = 0) = exp(n ln(1 - q)) (exact inversion)
  vec2 sigma;     // sqrt(n q (1 - q)) (Gaussian)
  vec2 skew;      // g = (1 - 2 p')/sigma, p' = p when flipped, else q
  vec2 kurt;      // k = (1 - 6 q (1 - q))/sigma^2
};

// What does not depend on the count.
BinomialSetup binomial_setup_shared(float n_real, float p) {
  BinomialSetup s;
  float n = n_real > 0.0 ? min(n_real, 1e30) : 0.0;
  s.p = p > 0.0 ? min(p, 1.0) : 0.0;
  s.n_floor = floor(n);
  s.n_frac = n - s.n_floor;
  s.flip = s.p > 0.5;
  s.q = s.flip ? 1.0 - s.p : s.p;  // exact for p >= 1/2 (Sterbenz)
  s.ratio = s.q / (1.0 - s.q);
  s.lnq = log(max(s.q, 1.17549435e-38));  // < 0; used only where q > 0
  return s;
}

// The distribution of the count n_int (floor(n) or floor(n) + 1).
void binomial_setup_count(BinomialSetup s, float n_int, float ln_miss, out float mean, out float p0,
                          out float sigma, out float skew, out float kurt) {
  float pp = s.flip ? s.p : s.q;
  mean = n_int * s.q;
  p0 = exp(n_int * ln_miss);
  sigma = sqrt(mean * (1.0 - s.q));
  // Used only where mean > 24 (sigma > 3.4); the floor keeps the unused ones finite.
  float sg = max(sigma, 1e-10);
  skew = (1.0 - 2.0 * pp) / sg;
  kurt = (1.0 - 6.0 * s.q * (1.0 - s.q)) / (sg * sg);
}

BinomialSetup binomial_setup(float n_real, float p) {
  BinomialSetup s = binomial_setup_shared(n_real, p);
  float ln_miss = safe_log1p(-s.q);
  binomial_setup_count(s, s.n_floor, ln_miss, s.mean.x, s.p0.x, s.sigma.x, s.skew.x, s.kurt.x);
  binomial_setup_count(s, s.n_floor + 1.0, ln_miss, s.mean.y, s.p0.y, s.sigma.y, s.skew.y, s.kurt.y);
  return s;
}

float binomial_draw(BinomialSetup s, float u, float u_round) {
  bool up = u_round < s.n_frac;
  float n_int = up ? s.n_floor + 1.0 : s.n_floor;
  float q = s.q;
  if (n_int == 0.0 || q == 0.0) return s.flip ? n_int : 0.0;
  if ((up ? s.mean.y : s.mean.x) <= BINOMIAL_EXACT_MEAN) {
    float pk = up ? s.p0.y : s.p0.x;
    float F = pk;
    float i = 0.0;
    int last = int(min(n_int, float(BINOMIAL_MAX_ITERATIONS)));
    for (int it = 0; it < last && u >= F; ++it) {
      pk *= (n_int - i) / (i + 1.0) * s.ratio;
      i += 1.0;
      F += pk;
    }
    float k = (u < F || i >= n_int) ? i : binomial_tail(i, n_int, s.lnq, u, F);
    return s.flip ? n_int - k : k;
  }
  // The Gaussian is drawn for the count of p itself (mean n p, skew (1 - 2p)/sigma)
  // at z(1 - u) when flipped: the same draw as n - Binomial(n, q) at z(u), rounded
  // once (n - k rounds twice in fp32 beyond 2^24, which skews the counts by ties).
  float sigma = up ? s.sigma.y : s.sigma.x;
  float z = normal_quantile(s.flip ? 1.0 - u : u);
  float pp = s.flip ? s.p : q;
  float g = up ? s.skew.y : s.skew.x;
  float kk = up ? s.kurt.y : s.kurt.x;
  float z2 = z * z;
  float zc = z + g * (z2 - 1.0) / 6.0 + kk * z * (z2 - 3.0) / 24.0 - g * g * z * (2.0 * z2 - 5.0) / 36.0;
  // n p + (sigma z' + 1/2) in one rounding: beyond 2^24 a separately rounded
  // n p would shift every count by up to half an fp32 step (sigma may be less)
  return clamp(floor(mul_add_once(n_int, pp, sigma * zc + 0.5)), 0.0, n_int);
}

// One draw: the rounding is decided first, so only the count it gives is set up (in the .x
// fields), and drawn with u_round = 0 against n_frac = 0: not rounded again, the .y fields unread.
float binomial_draw(float n_real, float p, float u, float u_round) {
  BinomialSetup s = binomial_setup_shared(n_real, p);
  if (u_round < s.n_frac) s.n_floor += 1.0;
  s.n_frac = 0.0;
  binomial_setup_count(s, s.n_floor, safe_log1p(-s.q), s.mean.x, s.p0.x, s.sigma.x, s.skew.x, s.kurt.x);
  return binomial_draw(s, u, 0.0);
}

#endif  // GLINTLAB_COMMON_BINOMIAL_GLSL

#include "metrics/vector_math.h"

#include <cmath>
#include <type_traits>
#include <vector>

#if defined(__x86_64__) && defined(GLINTLAB_HAVE_LIBMVEC)
#include <emmintrin.h>
#include <xmmintrin.h>

// glibc's libmvec, vector ABI names (x86_64 "b" variants: SSE registers, 2 doubles or 4 floats).
extern "C" __m128d _ZGVbN2v_log2(__m128d);
extern "C" __m128d _ZGVbN2v_exp2(__m128d);
extern "C" __m128d _ZGVbN2v_exp(__m128d);
extern "C" __m128d _ZGVbN2v_sin(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
extern "C" __m128d _ZGVbN2vv_atan2(__m128d, __m128d);
extern "C" __m128d _ZGVbN2v_cbrt(__m128d);
extern "C" __m128 _ZGVbN4v_log2f(__m128);
extern "C" __m128 _ZGVbN4v_exp2f(__m128);
#define GLINTLAB_LIBMVEC 1
#endif

namespace glintlab::metrics {

namespace {
#ifdef GLINTLAB_LIBMVEC
// F over n values, two doubles or four floats per call; the last partial vector through the same
// vector code (padded with copies), so that n does not change any result.
template <typename V, typename T, V (*F)(V)>
void apply(const T* x, T* out, std::size_t n) {
  constexpr std::size_t L = sizeof(V) / sizeof(T);
  auto load = [](const T* p) {
    if constexpr (L == 2) return _mm_loadu_pd(p);
    else return _mm_loadu_ps(p);
  };
  auto store = [](T* p, V v) {
    if constexpr (L == 2) _mm_storeu_pd(p, v);
    else _mm_storeu_ps(p, v);
  };
  std::size_t i = 0;
  for (; i + L <= n; i += L) store(out + i, F(load(x + i)));
  if (i < n) {
    T in[L], res[L];
    for (std::size_t k = 0; k < L; ++k) in[k] = x[i + k < n ? i + k : i];
    store(res, F(load(in)));
    for (std::size_t k = 0; i + k < n; ++k) out[i + k] = res[k];
  }
}

// F(y[i], x[i]) over n pairs of doubles, two per call, the tail padded as above.
template <__m128d (*F)(__m128d, __m128d)>
void apply2(const double* y, const double* x, double* out, std::size_t n) {
  std::size_t i = 0;
  for (; i + 2 <= n; i += 2) _mm_storeu_pd(out + i, F(_mm_loadu_pd(y + i), _mm_loadu_pd(x + i)));
  if (i < n) {
    const double yy[2] = {y[i], y[i]}, xx[2] = {x[i], x[i]};
    double res[2];
    _mm_storeu_pd(res, F(_mm_loadu_pd(yy), _mm_loadu_pd(xx)));
    out[i] = res[0];
  }
}
#endif

enum class Op { kLog2, kExp2 };

template <typename T>
void elementwise(Op op, const T* x, T* out, std::size_t n) {
#ifdef GLINTLAB_LIBMVEC
  if constexpr (std::is_same_v<T, double>) {
    if (op == Op::kLog2) apply<__m128d, double, _ZGVbN2v_log2>(x, out, n);
    else apply<__m128d, double, _ZGVbN2v_exp2>(x, out, n);
  } else {
    if (op == Op::kLog2) apply<__m128, float, _ZGVbN4v_log2f>(x, out, n);
    else apply<__m128, float, _ZGVbN4v_exp2f>(x, out, n);
  }
#else
  for (std::size_t i = 0; i < n; ++i) out[i] = op == Op::kLog2 ? std::log2(x[i]) : std::exp2(x[i]);
#endif
}
}  // namespace

void log2_n(const double* x, double* out, std::size_t n) { elementwise(Op::kLog2, x, out, n); }
void exp2_n(const double* x, double* out, std::size_t n) { elementwise(Op::kExp2, x, out, n); }
void log2_n(const float* x, float* out, std::size_t n) { elementwise(Op::kLog2, x, out, n); }
void exp2_n(const float* x, float* out, std::size_t n) { elementwise(Op::kExp2, x, out, n); }

#ifdef GLINTLAB_LIBMVEC
void exp_n(const double* x, double* out, std::size_t n) { apply<__m128d, double, _ZGVbN2v_exp>(x, out, n); }
void sin_n(const double* x, double* out, std::size_t n) { apply<__m128d, double, _ZGVbN2v_sin>(x, out, n); }
void cos_n(const double* x, double* out, std::size_t n) { apply<__m128d, double, _ZGVbN2v_cos>(x, out, n); }
void atan2_n(const double* y, const double* x, double* out, std::size_t n) { apply2<_ZGVbN2vv_atan2>(y, x, out, n); }
void cbrt_n(const double* x, double* out, std::size_t n) { apply<__m128d, double, _ZGVbN2v_cbrt>(x, out, n); }
#else
void exp_n(const double* x, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::exp(x[i]);
}
void sin_n(const double* x, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::sin(x[i]);
}
void cos_n(const double* x, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::cos(x[i]);
}
void atan2_n(const double* y, const double* x, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::atan2(y[i], x[i]);
}
void cbrt_n(const double* x, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::cbrt(x[i]);
}
#endif

void pow_n(const double* x, double p, double* out, std::size_t n) {
  log2_n(x, out, n);  // 0 -> -inf, +inf -> +inf, negative and NaN -> NaN
  for (std::size_t i = 0; i < n; ++i) out[i] *= p;
  exp2_n(out, out, n);  // -inf -> 0
}

void pow_n(const float* x, const float* p, float* out, std::size_t n) {
  std::vector<float> l(n);
  log2_n(x, l.data(), n);  // 0 -> -inf, NaN -> NaN
  for (std::size_t i = 0; i < n; ++i) l[i] = p[i] == 0.0f ? 0.0f : p[i] * l[i];  // x^0 = 1, also for x = 0
  exp2_n(l.data(), out, n);
}

}  // namespace glintlab::metrics

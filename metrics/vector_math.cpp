#include "metrics/vector_math.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#if defined(__x86_64__) && defined(GLINTLAB_HAVE_LIBMVEC)
#include <immintrin.h>

// glibc's libmvec, vector ABI names: the x86_64 "b" variants (SSE registers: 2 doubles or 4 floats a
// call, every x86-64 CPU) and the "d" variants (AVX2 registers: 4 doubles or 8 floats).
extern "C" {
__m128d _ZGVbN2v_log2(__m128d);
__m128d _ZGVbN2v_exp2(__m128d);
__m128d _ZGVbN2v_exp(__m128d);
__m128d _ZGVbN2v_sin(__m128d);
__m128d _ZGVbN2v_cos(__m128d);
__m128d _ZGVbN2v_cbrt(__m128d);
__m128d _ZGVbN2vv_atan2(__m128d, __m128d);
__m128 _ZGVbN4v_log2f(__m128);
__m128 _ZGVbN4v_exp2f(__m128);
__m256d _ZGVdN4v_log2(__m256d);
__m256d _ZGVdN4v_exp2(__m256d);
__m256d _ZGVdN4v_exp(__m256d);
__m256d _ZGVdN4v_sin(__m256d);
__m256d _ZGVdN4v_cos(__m256d);
__m256d _ZGVdN4v_cbrt(__m256d);
__m256d _ZGVdN4vv_atan2(__m256d, __m256d);
__m256 _ZGVdN8v_log2f(__m256);
__m256 _ZGVdN8v_exp2f(__m256);
}
#define GLINTLAB_LIBMVEC 1
#endif

namespace glintlab::metrics {

namespace {
#ifdef GLINTLAB_LIBMVEC
// The body of every array function: CALL (of vectors `a`, from y, and `b`, from x where given) over
// n values, one vector V of them a call; the last partial vector through the same vector code (padded
// with copies of its first value), so that n does not change any result. Loads and stores by memcpy
// (unaligned moves). A macro, not a template taking the call: the call must be compiled inside the
// function that carries the AVX2 target, or the "d" variants would get their vectors the wrong way.
#define GLINTLAB_LANES(V, T, CALL)                                                          \
  constexpr std::size_t L = sizeof(V) / sizeof(T);                                          \
  std::size_t i = 0;                                                                        \
  V a, b{};                                                                                 \
  for (; i + L <= n; i += L) {                                                              \
    std::memcpy(&a, y + i, sizeof a);                                                       \
    if (x) std::memcpy(&b, x + i, sizeof b);                                                \
    a = CALL;                                                                               \
    std::memcpy(out + i, &a, sizeof a);                                                     \
  }                                                                                         \
  if (i < n) {                                                                              \
    T py[L], px[L];                                                                         \
    for (std::size_t k = 0; k < L; ++k) {                                                   \
      py[k] = y[i + k < n ? i + k : i];                                                     \
      px[k] = x ? x[i + k < n ? i + k : i] : T(0);                                          \
    }                                                                                       \
    std::memcpy(&a, py, sizeof a);                                                          \
    std::memcpy(&b, px, sizeof b);                                                          \
    a = CALL;                                                                               \
    std::memcpy(py, &a, sizeof a);                                                          \
    for (std::size_t k = 0; i + k < n; ++k) out[i + k] = py[k];                             \
  }

template <typename V, typename T, V (*F)(V)>
void sse(const T* y, T* out, std::size_t n) {
  const T* x = nullptr;
  GLINTLAB_LANES(V, T, F(a))
}
template <typename V, typename T, V (*F)(V)>
__attribute__((target("avx2,fma"))) void avx2(const T* y, T* out, std::size_t n) {
  const T* x = nullptr;
  GLINTLAB_LANES(V, T, F(a))
}
template <__m128d (*F)(__m128d, __m128d)>
void sse2(const double* y, const double* x, double* out, std::size_t n) {
  GLINTLAB_LANES(__m128d, double, F(a, b))
}
template <__m256d (*F)(__m256d, __m256d)>
__attribute__((target("avx2,fma"))) void avx2_2(const double* y, const double* x, double* out, std::size_t n) {
  GLINTLAB_LANES(__m256d, double, F(a, b))
}
#undef GLINTLAB_LANES

bool avx2_chosen() {
  static bool chosen = [] {
    const char* env = std::getenv("GLINTLAB_VECTOR_MATH");
    if (env && std::string(env) == "sse") return false;
    return bool(__builtin_cpu_supports("avx2")) && bool(__builtin_cpu_supports("fma"));
  }();
  return chosen;
}
bool& avx2_on() {
  static bool on = avx2_chosen();
  return on;
}
#endif
}  // namespace

#ifdef GLINTLAB_LIBMVEC
#define GLINTLAB_VM1(T, V2, F2, V4, F4)                    \
  if (avx2_on()) avx2<V4, T, F4>(x, out, n);               \
  else sse<V2, T, F2>(x, out, n)
void log2_n(const double* x, double* out, std::size_t n) { GLINTLAB_VM1(double, __m128d, _ZGVbN2v_log2, __m256d, _ZGVdN4v_log2); }
void exp2_n(const double* x, double* out, std::size_t n) { GLINTLAB_VM1(double, __m128d, _ZGVbN2v_exp2, __m256d, _ZGVdN4v_exp2); }
void log2_n(const float* x, float* out, std::size_t n) { GLINTLAB_VM1(float, __m128, _ZGVbN4v_log2f, __m256, _ZGVdN8v_log2f); }
void exp2_n(const float* x, float* out, std::size_t n) { GLINTLAB_VM1(float, __m128, _ZGVbN4v_exp2f, __m256, _ZGVdN8v_exp2f); }
void exp_n(const double* x, double* out, std::size_t n) { GLINTLAB_VM1(double, __m128d, _ZGVbN2v_exp, __m256d, _ZGVdN4v_exp); }
void sin_n(const double* x, double* out, std::size_t n) { GLINTLAB_VM1(double, __m128d, _ZGVbN2v_sin, __m256d, _ZGVdN4v_sin); }
void cos_n(const double* x, double* out, std::size_t n) { GLINTLAB_VM1(double, __m128d, _ZGVbN2v_cos, __m256d, _ZGVdN4v_cos); }
void cbrt_n(const double* x, double* out, std::size_t n) { GLINTLAB_VM1(double, __m128d, _ZGVbN2v_cbrt, __m256d, _ZGVdN4v_cbrt); }
#undef GLINTLAB_VM1
void atan2_n(const double* y, const double* x, double* out, std::size_t n) {
  if (avx2_on()) avx2_2<_ZGVdN4vv_atan2>(y, x, out, n);
  else sse2<_ZGVbN2vv_atan2>(y, x, out, n);
}

const char* vector_math_isa() { return avx2_on() ? "avx2" : "sse"; }
bool use_vector_math_isa(const std::string& isa) {
  if (isa == "sse") return !(avx2_on() = false);
  if (isa == "avx2" && avx2_chosen()) return avx2_on() = true;
  return false;
}
#else
#define GLINTLAB_LIBM1(name, f) \
  void name(const double* x, double* out, std::size_t n) { for (std::size_t i = 0; i < n; ++i) out[i] = f(x[i]); }
GLINTLAB_LIBM1(log2_n, std::log2)
GLINTLAB_LIBM1(exp2_n, std::exp2)
GLINTLAB_LIBM1(exp_n, std::exp)
GLINTLAB_LIBM1(sin_n, std::sin)
GLINTLAB_LIBM1(cos_n, std::cos)
GLINTLAB_LIBM1(cbrt_n, std::cbrt)
#undef GLINTLAB_LIBM1
void log2_n(const float* x, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::log2(x[i]);
}
void exp2_n(const float* x, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::exp2(x[i]);
}
void atan2_n(const double* y, const double* x, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = std::atan2(y[i], x[i]);
}
const char* vector_math_isa() { return "libm"; }
bool use_vector_math_isa(const std::string& isa) { return isa == "libm"; }
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

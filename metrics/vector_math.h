// Element-wise transcendental functions over arrays of doubles and floats, for the per-pixel loops whose
// time is mostly such functions: log2, exp2 and powers (the PQ curve of ΔE_ITP and of the flicker metric,
// FLIP's powers), exp, sin, cos, atan2 and cbrt (CIEDE2000 and its L*a*b*). On x86-64 they go through
// glibc's vector math library, libmvec (most of these since glibc 2.35): its AVX2 variants, four doubles
// or eight floats a call, where the CPU has AVX2 and FMA, else its SSE variants (two or four), which
// every x86-64 CPU can run. Measured on the development machine (loops over 4M doubles, SSE variants):
// log2 3.8 ns instead of 5.8, exp2 2.0 ns instead of 4.7, so a power as exp2(p log2 x) about 5.8 ns
// against std::pow's 16.3; the AVX2 variants took `glintlab measure` of a 1080p sequence from 37-39 to
// 31 CPU-s for 36 frames (tests/bench/README.md). Accuracy: libmvec's documented bound of 4 ulp per
// function (tests/metrics/vector_math.cpp compares both variants with <cmath>). Without libmvec, loops
// over <cmath>.
#pragma once

#include <cstddef>
#include <string>

namespace glintlab::metrics {

void log2_n(const double* x, double* out, std::size_t n);  // log2(x[i]); in-place allowed
void exp2_n(const double* x, double* out, std::size_t n);  // exp2(x[i]); in-place allowed
// The functions of CIEDE2000's hue terms (metrics/ciede2000.cpp), likewise: exp, sin, cos and
// atan2(y[i], x[i]) with atan2's signed zeros and quadrants. In-place allowed.
void exp_n(const double* x, double* out, std::size_t n);
void sin_n(const double* x, double* out, std::size_t n);
void cos_n(const double* x, double* out, std::size_t n);
void atan2_n(const double* y, const double* x, double* out, std::size_t n);
// cbrt(x[i]) (negative x too: the cube root of -x is minus that of x), for L*a*b* (ciede2000.cpp).
void cbrt_n(const double* x, double* out, std::size_t n);

// x[i]^p as exp2(p log2 x[i]) for p > 0: 0 -> 0, +inf -> +inf, NaN and negative x -> NaN.
// In-place allowed.
void pow_n(const double* x, double p, double* out, std::size_t n);

// Single precision, four floats per call (FLIP's colour pipeline, which FLIP itself computes in float).
void log2_n(const float* x, float* out, std::size_t n);
void exp2_n(const float* x, float* out, std::size_t n);
// x[i]^p[i] as exp2(p[i] log2 x[i]) for x >= 0 and finite p: 0^p = 0 for p > 0 and 1 for p = 0 (as
// std::pow), NaN x -> NaN. Within 8 ulp of std::pow(float, float) for results above 2^-20 (the error of
// log2 scaled by p). In-place allowed (out may be x or p).
void pow_n(const float* x, const float* p, float* out, std::size_t n);

// Which of libmvec's variants the functions above call: "avx2" (4 doubles or 8 floats a call) where
// the CPU has AVX2 and FMA, else "sse" (2 or 4); "libm" where glibc's libmvec is not used. The two
// variants may differ in the last bit (each within libmvec's 4 ulp), so results can differ between
// CPUs in the last bits. GLINTLAB_VECTOR_MATH=sse keeps the SSE variants. use_vector_math_isa
// switches for the process (the tests run both); false where `isa` is not available.
const char* vector_math_isa();
bool use_vector_math_isa(const std::string& isa);

}  // namespace glintlab::metrics

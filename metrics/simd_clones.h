// GLINTLAB_AVX2_CLONES before a function definition: GCC compiles the function twice, for AVX2 and for
// every x86-64 CPU (SSE2), and the loader picks one at start-up (function multiversioning,
// target_clones). Only the vector width differs: AVX2 here does not bring FMA, and ISO C++ mode
// contracts nothing, so both clones compute the same bits. For the per-pixel loops of the metrics
// (plane-wise arithmetic around libmvec's calls, separable filters, gathers): measured with every
// metric loop built for AVX2 this way, `glintlab measure` of the bench's 1080p half sequence took
// 14.1-14.7 CPU-s for 36 frames instead of 17.2, with records.jsonl identical to the last bit.
// Elsewhere (another compiler, another architecture) the one plain function.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GLINTLAB_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GLINTLAB_AVX2_CLONES
#endif

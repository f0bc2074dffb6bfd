// Process-wide allocator settings for rendering on lavapipe. llvmpipe
// allocates large buffers for every draw (vertex and binning data); glibc
// serves allocations above its mmap threshold with fresh mmap'ed pages, so
// every draw pays page faults and zeroing in the kernel: measured on the
// geometry-bound reference case (16x9 at 576 samples) that was a quarter of
// the frame. Raising the thresholds keeps freed memory in the heap for reuse.
// Call once at the start of main().
#pragma once

#include <cstddef>

namespace glintlab {

void tune_allocator_for_rendering();

// For the CPU pipelines that decode frames on one thread and free them on
// another (`glintlab measure`): every thread allocates from the one main heap.
// With glibc's per-thread arenas each decoded 1080p frame came in fresh pages
// of the decoding thread's arena and went back to the kernel when freed, so
// every frame paid its page faults again (measured on 1080p half EXR, the same
// binary: 414k minor faults for 12 frames with per-thread arenas, 231k with
// one; with one arena 36 frames take 242k: only the first touch of the
// working set). Call before the threads start.
void share_one_heap_between_threads();

// Lets the kernel back the next `bytes` of the heap with 2 MiB pages (madvise
// MADV_HUGEPAGE over a block that is then freed and stays in the heap, as
// tune_allocator_for_rendering keeps it): the first touch of a large working
// set then takes one page fault per 2 MiB instead of one per 4 KiB. Nothing
// is used until touched. Call after tune_allocator_for_rendering, with less
// than 1 GiB; false (and no harm) where the kernel refuses. Measured on
// `glintlab measure`: see tests/bench/README.md.
bool reserve_heap_in_huge_pages(std::size_t bytes);
constexpr std::size_t kMaxHugeReservation = (std::size_t(1) << 30) - (std::size_t(4) << 20);

}  // namespace glintlab

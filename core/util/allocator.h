// Process-wide allocator settings for rendering on lavapipe. llvmpipe
// allocates large buffers for every draw (vertex and binning data); glibc
// serves allocations above its mmap threshold with fresh mmap'ed pages, so
// every draw pays page faults and zeroing in the kernel: measured on the
// geometry-bound reference case (16x9 at 576 samples) that was a quarter of
// the frame. Raising the thresholds keeps freed memory in the heap for reuse.
// Call once at the start of main().
#pragma once

namespace glintlab {

void tune_allocator_for_rendering();

}  // namespace glintlab

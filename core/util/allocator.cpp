#include "core/util/allocator.h"

#include <malloc.h>

namespace glintlab {

void tune_allocator_for_rendering() {
  mallopt(M_MMAP_THRESHOLD, 1 << 30);  // serve blocks up to 1 GiB from the heap, not fresh mmaps
  mallopt(M_TRIM_THRESHOLD, 1 << 30);  // and keep what is freed for the next draw
  mallopt(M_TOP_PAD, 256 << 20);       // grow the heap in large steps
}

void share_one_heap_between_threads() { mallopt(M_ARENA_MAX, 1); }

}  // namespace glintlab

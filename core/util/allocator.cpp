#include "core/util/allocator.h"

#include <malloc.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>

namespace glintlab {

void tune_allocator_for_rendering() {
  mallopt(M_MMAP_THRESHOLD, 1 << 30);  // serve blocks up to 1 GiB from the heap, not fresh mmaps
  mallopt(M_TRIM_THRESHOLD, 1 << 30);  // and keep what is freed for the next draw
  mallopt(M_TOP_PAD, 256 << 20);       // grow the heap in large steps
}

void share_one_heap_between_threads() { mallopt(M_ARENA_MAX, 1); }

bool reserve_heap_in_huge_pages(std::size_t bytes) {
  constexpr std::size_t kHuge = std::size_t(2) << 20;
  if (bytes < 4 * kHuge || bytes >= (std::size_t(1) << 30)) return false;  // below the mmap threshold set above
  void* block = std::malloc(bytes);
  if (!block) return false;
  const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(block);
  const std::uintptr_t lo = (a + kHuge - 1) / kHuge * kHuge, hi = (a + bytes) / kHuge * kHuge;
  const bool ok = hi > lo && ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE) == 0;
  std::free(block);  // back to the top of the heap, untouched: no memory is used until it is
  return ok;
}

}  // namespace glintlab

// The allocator settings of core/util/allocator.h do what they say to the process's heap.
#include "core/util/allocator.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace {

// The VmFlags of the mapping of /proc/self/smaps that holds address a ("" if none).
std::string vm_flags_at(const void* a) {
  std::ifstream in("/proc/self/smaps");
  std::string line;
  bool inside = false;
  const auto addr = reinterpret_cast<std::uintptr_t>(a);
  while (std::getline(in, line)) {
    unsigned long lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find('-') < line.find(' ')) {
      inside = addr >= lo && addr < hi;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

}  // namespace

// After the reservation, a large block from the heap lies in memory the kernel may back with huge
// pages (VmFlags "hg"), and it works as memory; where the kernel refuses, the call says so.
TEST(Allocator, HugePageReservationCoversTheNextLargeBlocks) {
  const size_t bytes = size_t(64) << 20;
  if (!glintlab::reserve_heap_in_huge_pages(bytes)) {
    std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(thp, mode);
    EXPECT_TRUE(mode.empty() || mode.find("[never]") != std::string::npos)
        << "refused where transparent huge pages are '" << mode << "'";
    GTEST_SKIP() << "no transparent huge pages here: " << mode;
  }
  void* p = std::malloc(bytes / 2);
  ASSERT_NE(p, nullptr);
  std::memset(p, 0x5a, bytes / 2);
  EXPECT_EQ(static_cast<unsigned char*>(p)[bytes / 2 - 1], 0x5a);
  const std::string flags = vm_flags_at(static_cast<char*>(p) + bytes / 4);
  EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
  std::free(p);
  EXPECT_FALSE(glintlab::reserve_heap_in_huge_pages(size_t(1) << 30));  // at the mmap threshold: not from the heap
  EXPECT_FALSE(glintlab::reserve_heap_in_huge_pages(4096));
}

// core/large_buffer.h (issue 19, convert speed): the buffers are what std::vector<float>(n) gives
// (n zeros), and on Linux with transparent huge pages available the kernel records the advice on
// the buffer's 2 MiB-aligned interior (VmFlags "hg" in /proc/self/smaps for the mapping holding
// it; with THP "never" the advice is refused and the buffer is the same).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "core/large_buffer.h"

namespace nph {
namespace {

// The VmFlags line of the mapping in /proc/self/smaps that contains `address` ("" if none).
std::string vmFlagsAt(std::uintptr_t address) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (line.find(':') == std::string::npos || line.find('-') < line.find(' ')) {
      if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
        inside = address >= lo && address < hi;
        continue;
      }
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

std::string transparentHugePagesMode() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(f, s);
  return s;
}

TEST(LargeBuffer, HoldsZerosLikeAPlainVector) {
  for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(1000), std::size_t(3) << 20}) {
    const std::vector<float> v = hugePageFloats(n);
    ASSERT_EQ(v.size(), n);
    EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](float x) { return x == 0.0f; })) << n;
  }
  adviseHugePages(nullptr, std::size_t(64) << 20);  // no-ops
  float small[16] = {};
  adviseHugePages(small, sizeof small);
}

TEST(LargeBuffer, AdvisesTheKernelOnItsAlignedInterior) {
  constexpr std::size_t kFloats = std::size_t(16) << 20;  // 64 MiB: 31 whole 2 MiB pages at least
  std::vector<float> v = hugePageFloats(kFloats);
  constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
  const std::uintptr_t inner = (reinterpret_cast<std::uintptr_t>(v.data()) + kHugePage - 1) & ~(kHugePage - 1);
  const std::string flags = vmFlagsAt(inner + kHugePage / 2);
  const std::string mode = transparentHugePagesMode();
  std::printf("[ thp ] mode \"%s\"; the buffer's mapping: %s\n", mode.c_str(), flags.c_str());
#if defined(__linux__)
  ASSERT_FALSE(flags.empty()) << "the buffer's mapping must be in /proc/self/smaps";
  if (mode.find("[never]") == std::string::npos && !mode.empty()) {
    EXPECT_NE(flags.find(" hg"), std::string::npos) << "MADV_HUGEPAGE not recorded: " << flags;
  }
#endif
}

// reserveHugePageHeap (issue 19, convert speed): with every large block from the heap, the blocks
// malloc hands out after the reserve lie in memory the kernel has been advised to back with huge
// pages, and the reserve itself is not resident (it is never touched). Under another allocator
// (the sanitizer build's) the reserve is a no-op, checked as such.
TEST(LargeBuffer, ReservesTheHeapAboveItsTopForHugePages) {
#if defined(__GLIBC__) && defined(__linux__)
  if (!reuseFreedMemoryForLargeBlocks()) {
    // Another allocator than glibc's (the sanitizers' replace malloc and refuse mallopt): the
    // reserve must then do nothing — its block would be a fresh mmap, unmapped again by free().
    EXPECT_EQ(reserveHugePageHeap(std::size_t(256) << 20), 0u);
    return;
  }
  auto resident_kb = [] {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    }
    return 0L;
  };
  const long before_kb = resident_kb();
  constexpr std::size_t kReserve = std::size_t(256) << 20;
  ASSERT_EQ(reserveHugePageHeap(kReserve), kReserve);
  EXPECT_LT(resident_kb() - before_kb, 8 * 1024) << "the reserve must not be touched";
  EXPECT_EQ(reserveHugePageHeap(std::size_t(1) << 40), kHugePageHeapReserveBytes);  // capped
  // A 64 MiB block now comes from the advised heap, as the model fields of `nephele convert` do.
  void* block = std::malloc(std::size_t(64) << 20);
  ASSERT_NE(block, nullptr);
  constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
  const std::uintptr_t inner = (reinterpret_cast<std::uintptr_t>(block) + kHugePage - 1) & ~(kHugePage - 1);
  const std::string flags = vmFlagsAt(inner + kHugePage / 2);
  const std::string mode = transparentHugePagesMode();
  std::printf("[ thp ] mode \"%s\"; the block's mapping: %s\n", mode.c_str(), flags.c_str());
  ASSERT_FALSE(flags.empty());
  if (mode.find("[never]") == std::string::npos && !mode.empty()) {
    EXPECT_NE(flags.find(" hg"), std::string::npos) << "the block is not in the advised heap: " << flags;
  }
  std::free(block);
#else
  EXPECT_EQ(reserveHugePageHeap(std::size_t(256) << 20), 0u);
#endif
}

}  // namespace
}  // namespace nph

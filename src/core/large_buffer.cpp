#include "core/large_buffer.h"

#include <algorithm>
#include <atomic>
#include <climits>
#include <cstdint>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace nph {

void adviseHugePages(void* data, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (data == nullptr || bytes < kHugePageAdviceMinBytes) return;
  constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;  // x86-64 and arm64 (4 KiB base pages)
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHugePage - 1);
  if (last <= first) return;
  // The result is ignored on purpose: EINVAL where THP is not built in, and the buffer works the same.
  (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

namespace {
/// Whether reuseFreedMemoryForLargeBlocks has applied (reserveHugePageHeap needs it).
std::atomic<bool> g_large_blocks_from_heap{false};
}  // namespace

bool reuseFreedMemoryForLargeBlocks() noexcept {
#if defined(__GLIBC__)
  // mallopt is glibc's; a replaced allocator (the sanitizers') refuses it with 0.
  const bool applied = mallopt(M_MMAP_MAX, 0) == 1 && mallopt(M_TRIM_THRESHOLD, INT_MAX) == 1;
  if (applied) g_large_blocks_from_heap = true;
  return applied;
#else
  return false;
#endif
}

std::size_t reserveHugePageHeap(std::size_t bytes) noexcept {
#if defined(__GLIBC__) && defined(__linux__)
  // Without it the block would be a fresh mmap, unmapped again by free(): nothing to gain.
  if (!g_large_blocks_from_heap) return 0;
  bytes = std::min(bytes, kHugePageHeapReserveBytes);
  if (bytes < kHugePageAdviceMinBytes) return 0;
  void* block = std::malloc(bytes);  // a raw block on purpose: never touched
  if (block == nullptr) return 0;
  adviseHugePages(block, bytes);
  std::free(block);
  return bytes;
#else
  (void)bytes;
  return 0;
#endif
}

bool releaseFreedMemory() noexcept {
#if defined(__GLIBC__)
  return malloc_trim(0) == 1;
#else
  return false;
#endif
}

}  // namespace nph

#pragma once
// Large float buffers backed by transparent huge pages (issue 19, convert speed). A fresh buffer of
// hundreds of MB (one model field of the demo storm: 500 × 500 × 60 floats = 60 MB) costs one page
// fault per 4 KiB page on first touch — 15 000 per field, ~250 000 per timestep — each a trip into
// the kernel that zeroes the page. madvise(MADV_HUGEPAGE) on the buffer's 2 MiB-aligned interior
// lets the kernel back it with 2 MiB pages: 512× fewer faults. It is advice: where transparent huge
// pages are off (/sys/kernel/mm/transparent_hugepage/enabled = never) nothing changes but speed;
// with "madvise" (Debian's default) or "always" it applies. Same effect as glibc's
// GLIBC_TUNABLES=glibc.malloc.hugetlb=1, for these buffers only and without an environment variable.
#include <cstddef>
#include <vector>

namespace nph {

/// Below this size a buffer is left to malloc's own pages (less than two huge pages would cover
/// no aligned 2 MiB page reliably).
inline constexpr std::size_t kHugePageAdviceMinBytes = std::size_t(4) << 20;

/// Advises the kernel to back [data, data + bytes) with transparent huge pages where it holds
/// whole 2 MiB-aligned pages. No-op for small ranges, on error, or where madvise is missing.
void adviseHugePages(void* data, std::size_t bytes) noexcept;

/// `n` values, value-initialised (0) as std::vector does, the storage advised for huge pages
/// before the zero-fill first touches it (reserve, advise, resize). For the large buffers a frame
/// allocates fresh: the `.nph` chunk and its codes, the cached basemap, the read-back images (on
/// this VM a first-touch page fault costs more than the zero-fill itself: docs/benchmarks.md).
template <class T>
std::vector<T> hugePageVector(std::size_t n) {
  std::vector<T> v;
  v.reserve(n);
  adviseHugePages(v.data(), n * sizeof(T));
  v.resize(n);
  return v;
}
inline std::vector<float> hugePageFloats(std::size_t n) { return hugePageVector<float>(n); }

/// For batch commands that allocate and free the same large buffers over and over (`nephele
/// convert`: per timestep, the model fields, and per variable HDF5's chunk and inflate buffers):
/// glibc's malloc then serves every block from the heap instead of a fresh mmap (M_MMAP_MAX = 0)
/// and keeps freed memory (M_TRIM_THRESHOLD at its maximum), so a block freed by one read is
/// reused, already faulted in, by the next instead of being unmapped and faulted in page by page
/// again. Costs some peak memory to the heap's fragmentation (+4.5 % on the demo storm's convert:
/// docs/benchmarks.md, "convert against a raw read"). No-op without glibc. Returns whether it
/// applied.
bool reuseFreedMemoryForLargeBlocks() noexcept;

/// Largest heap reserve reserveHugePageHeap makes: freed, it must stay below M_TRIM_THRESHOLD
/// (INT_MAX once reuseFreedMemoryForLargeBlocks has run), or free() would hand it back at once.
inline constexpr std::size_t kHugePageHeapReserveBytes = std::size_t(1536) << 20;

/// After reuseFreedMemoryForLargeBlocks (every large block then comes from the heap): grows the
/// heap by up to `bytes` above what it holds free (malloc of one block, which glibc takes from the
/// heap's top without touching it), advises the block for huge pages (adviseHugePages) and frees
/// it again — it stays in the heap, untouched (no resident memory), and the blocks malloc hands out
/// from it next (the model fields, HDF5's chunk and inflate buffers) are faulted in 2 MiB at a
/// time. This is what GLIBC_TUNABLES=glibc.malloc.hugetlb=1 does for the whole heap, from inside
/// the process: on `nephele convert` of the demo storm 198 k → 20 k page faults and 10–15 % less
/// CPU (docs/benchmarks.md, "convert against a raw read"). Called again, it covers what the heap
/// has grown since. At most kHugePageHeapReserveBytes; nothing unless reuseFreedMemoryForLargeBlocks
/// has applied (glibc's own allocator; not under the sanitizers), nor where malloc refuses the
/// block. Returns the bytes advised.
std::size_t reserveHugePageHeap(std::size_t bytes) noexcept;

/// Hands the heap's free pages back to the kernel (glibc's malloc_trim(0)): memory freed by a
/// phase that allocated hundreds of MB in pieces (the basemap's decode and reprojection through
/// GDAL, the .nph chunk) stays resident in malloc's heap otherwise, and is counted again under the
/// next phase's peak (issue 19, docs/benchmarks.md "Memory": `nephele render` calls it between
/// phases). No-op without glibc. Returns whether memory was released.
bool releaseFreedMemory() noexcept;

}  // namespace nph

#pragma once
// The process's resident memory now and at its peak (issue 19, docs/benchmarks.md "Memory"): on
// llvmpipe every GL texture is process memory, so these count the CPU copies and the textures
// together. `nephele render` logs them after each phase at NEPHELE_LOG=debug (logPhase), which
// tools/memory.sh breaks the peak down by.
#include <cstddef>
#include <string_view>

namespace nph {

struct ResidentMemory {
  std::size_t now_bytes = 0;   ///< VmRSS
  std::size_t peak_bytes = 0;  ///< VmHWM: the most resident since the process started
};

/// From /proc/self/status (Linux); zeros where it cannot be read.
ResidentMemory residentMemory() noexcept;

/// log::debug "memory after <phase>: resident N MB, peak P MB" (nothing is read unless the log
/// threshold is debug).
void logMemoryPhase(std::string_view phase);

}  // namespace nph

#include "core/process_memory.h"

#include <cstdio>
#include <cstring>

#include "core/log.h"

namespace nph {

ResidentMemory residentMemory() noexcept {
  ResidentMemory m;
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return m;
  char line[256];
  while (std::fgets(line, sizeof line, f) != nullptr) {
    unsigned long long kb = 0;
    if (std::sscanf(line, "VmRSS: %llu kB", &kb) == 1) m.now_bytes = std::size_t(kb) * 1024;
    if (std::sscanf(line, "VmHWM: %llu kB", &kb) == 1) m.peak_bytes = std::size_t(kb) * 1024;
  }
  std::fclose(f);
  return m;
}

void logMemoryPhase(std::string_view phase) {
  if (log::threshold() < log::Level::Debug) return;
  const ResidentMemory m = residentMemory();
  log::debug("memory after {}: resident {:.1f} MB, peak {:.1f} MB", phase, double(m.now_bytes) / 1e6,
             double(m.peak_bytes) / 1e6);
}

}  // namespace nph

#include "core/temp_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <set>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"

namespace nph::temp_files {

Created createExclusive(const std::filesystem::path& final_path, const std::string& prefix, const std::string& marker,
                        const std::string& suffix) {
  const std::filesystem::path dir =
      final_path.has_parent_path() ? final_path.parent_path() : std::filesystem::path(".");
  std::string templ = (dir / fmt::format("{}{}{}-XXXXXX{}", prefix, marker, ::getpid(), suffix)).string();
  const int fd = ::mkstemps(templ.data(), static_cast<int>(suffix.size()));
  if (fd < 0) {
    throw IoError(fmt::format("{}: cannot create a temporary file in {}: {}", final_path.string(), dir.string(),
                              std::generic_category().message(errno)));
  }
  ::fchmod(fd, 0644);
  return {fd, templ};
}

int removeStale(const std::filesystem::path& dir, const std::string& marker) {
  static std::mutex mutex;
  static std::set<std::pair<std::string, std::string>> scanned;
  {
    std::error_code ec;
    const std::string key = std::filesystem::weakly_canonical(dir, ec).string();
    const std::lock_guard lock(mutex);
    if (!scanned.emplace(key, marker).second) return 0;
  }
  int removed = 0;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const auto at = name.find(marker);
    if (at == std::string::npos) continue;
    std::size_t p = at + marker.size();
    long long pid = 0;
    const std::size_t digits_from = p;
    while (p < name.size() && name[p] >= '0' && name[p] <= '9' && p - digits_from < 10)
      pid = pid * 10 + (name[p++] - '0');
    if (p == digits_from || p >= name.size() || name[p] != '-' || pid <= 0) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to judge)
    std::error_code rm;
    if (it->is_symlink(rm) || it->is_regular_file(rm)) {
      if (std::filesystem::remove(it->path(), rm)) {
        ++removed;
        log::info("removed {}, left behind by process {} which no longer runs", it->path().string(), pid);
      }
    }
  }
  return removed;
}

namespace {

constexpr int kCleanupSlots = 64;
constexpr std::size_t kCleanupPathBytes = 4096;
struct CleanupSlot {
  std::atomic<bool> used{false};  ///< set (release) after `path` is written; read in the handler
  char path[kCleanupPathBytes] = {};
};
CleanupSlot g_cleanup[kCleanupSlots];
std::mutex g_cleanup_mutex;  // registration only; the handler reads the atomics

extern "C" void unlinkTemporariesAndReraise(int sig) {
  for (CleanupSlot& s : g_cleanup) {
    if (s.used.load(std::memory_order_acquire)) ::unlink(s.path);  // async-signal-safe
  }
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

int registerForCleanup(const std::filesystem::path& path) {
  const std::string p = path.string();
  if (p.size() + 1 > kCleanupPathBytes) return -1;
  const std::lock_guard lock(g_cleanup_mutex);
  for (int i = 0; i < kCleanupSlots; ++i) {
    CleanupSlot& s = g_cleanup[i];
    if (s.used.load(std::memory_order_relaxed)) continue;
    std::memcpy(s.path, p.c_str(), p.size() + 1);
    s.used.store(true, std::memory_order_release);
    return i;
  }
  return -1;
}

void unregisterForCleanup(int slot) {
  if (slot < 0 || slot >= kCleanupSlots) return;
  const std::lock_guard lock(g_cleanup_mutex);
  g_cleanup[slot].used.store(false, std::memory_order_release);
}

void installSignalCleanup() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) != 0 || current.sa_handler != SIG_DFL) continue;
    struct sigaction action {};
    action.sa_handler = unlinkTemporariesAndReraise;
    sigemptyset(&action.sa_mask);
    ::sigaction(sig, &action, nullptr);
  }
}

namespace {

/// true when a process with this pid exists (kill(pid, 0) succeeds or is refused for permission).
bool processExists(long long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH); }

}  // namespace

bool Claim::tryAcquire(const std::filesystem::path& path) {
  release();
  holder_ = 0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) {
      const std::string pid = std::to_string(::getpid());
      const bool written = ::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
      ::close(fd);
      if (!written) {
        std::error_code ec;
        std::filesystem::remove(path, ec);
        return false;
      }
      path_ = path;
      held_ = true;
      return true;
    }
    if (errno != EEXIST) return false;
    // Held: by whom? An unreadable or empty claim (being written right now) counts as live.
    char text[32] = {};
    const int rd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    ssize_t n = 0;
    if (rd >= 0) {
      n = ::read(rd, text, sizeof(text) - 1);
      ::close(rd);
    }
    holder_ = n > 0 ? std::atoll(text) : 0;
    if (holder_ <= 0 || processExists(holder_)) return false;
    log::info("{}: taking over the claim of process {}, which no longer runs", path.string(), holder_);
    std::error_code ec;
    std::filesystem::remove(path, ec);  // then retry the exclusive create once
  }
  return false;
}

void Claim::release() {
  if (!held_) return;
  std::error_code ec;
  std::filesystem::remove(path_, ec);
  held_ = false;
}

}  // namespace nph::temp_files

#pragma once
// Temporary files next to their final name (issue #18). Every output is written under a
// temporary name and renamed, so readers never see a partial file. The temporary is created
// exclusively with an unpredictable name (mkstemps: O_CREAT|O_EXCL, which never follows a
// symbolic link), so a link planted in a shared output folder cannot redirect the write, and it
// carries the writer's pid, so the next run removes what a killed run left behind.
#include <filesystem>
#include <string>

namespace nph::temp_files {

struct Created {
  int fd = -1;                 ///< open for writing (the caller closes it)
  std::filesystem::path path;  ///< <dir>/<prefix><marker><pid>-XXXXXX<suffix>
};

/// Creates <dir>/<prefix><marker><pid>-XXXXXX<suffix> exclusively, mode 0644. IoError naming
/// `final_path` when it cannot. `marker` is ".partial-" or ".tmp-" (what removeStale looks for).
Created createExclusive(const std::filesystem::path& final_path, const std::string& prefix, const std::string& marker,
                        const std::string& suffix);

/// Removes the files of `dir` whose name holds `marker` followed by "<pid>-" where no process
/// <pid> exists any more (kill(pid, 0) fails with ESRCH): leftovers of killed runs. Scans each
/// (dir, marker) once per process; returns how many files it removed. Temporaries of live
/// processes (this one, or a concurrent run) are kept. On a folder shared between machines a pid
/// may belong to another host: such files are only removed when the pid is free here too.
int removeStale(const std::filesystem::path& dir, const std::string& marker);

/// Temporaries to unlink if the process is stopped by SIGINT, SIGTERM or SIGHUP. register
/// returns a slot (-1 when all 64 are taken: the next run's removeStale then cleans up);
/// unregister frees it. Registration is cheap and always allowed; the handlers only exist once
/// installSignalCleanup() ran (the CLI does; a library inside a plugin host leaves the host's
/// signal handling alone).
int registerForCleanup(const std::filesystem::path& path);
void unregisterForCleanup(int slot);
/// registerForCleanup for the lifetime of a scope.
class CleanupRegistration {
 public:
  explicit CleanupRegistration(const std::filesystem::path& path) : slot_(registerForCleanup(path)) {}
  ~CleanupRegistration() { unregisterForCleanup(slot_); }
  CleanupRegistration(const CleanupRegistration&) = delete;
  CleanupRegistration& operator=(const CleanupRegistration&) = delete;

 private:
  int slot_;
};
/// Installs the SIGINT/SIGTERM/SIGHUP handlers (where the disposition is still the default):
/// they unlink the registered temporaries and re-raise the signal with its default action.
void installSignalCleanup();

/// A claim on a unit of work shared between processes (a frame of `nephele animate`): the file
/// <path> created exclusively, holding the claimant's pid, removed when the claim is destroyed.
/// Two runs on one output folder then render disjoint frames instead of both rendering all.
class Claim {
 public:
  /// Tries to claim `path`: true when this process holds it now. A claim whose process no longer
  /// runs (a killed run) is taken over; one held by a live process (including this one) is not.
  bool tryAcquire(const std::filesystem::path& path);
  /// The pid recorded in the claim that tryAcquire found held (0 if none).
  long long holder() const { return holder_; }
  void release();
  Claim() = default;
  Claim(const Claim&) = delete;
  Claim& operator=(const Claim&) = delete;
  ~Claim() { release(); }

 private:
  std::filesystem::path path_;
  bool held_ = false;
  long long holder_ = 0;
};

}  // namespace nph::temp_files

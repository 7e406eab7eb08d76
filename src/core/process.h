#pragma once
// Running external tools (gnuplot, ffmpeg, nephele's own helpers) without a shell (issue #18):
// the program gets an argument vector through posix_spawn, so no file name can inject a command
// (`nephele-bench accuracy -o "x';touch PWNED;'"` ran `touch` through std::system before).
// Tool paths can be pinned with an environment variable instead of trusting PATH.
//
// posix_spawn, not fork: nephele runs inside multithreaded processes (llvmpipe's threads, plugin
// hosts, Python). A forked child is a copy of the whole address space with one thread, and any lock
// another thread held at the fork stays held in the child forever; fork also runs the
// pthread_atfork handlers of every library loaded (PROJ's closes its sqlite database in the child,
// which frees memory). Under AddressSanitizer that child deadlocked on the allocator's lock (issue
// #18, session 10). glibc's posix_spawn clones with CLONE_VM | CLONE_VFORK and calls exec at once:
// no atfork handler runs and nothing of the parent's heap is touched in between.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nph::process {

/// Runs argv[0] with `argv` (no shell, PATH lookup only when argv[0] has no '/') and waits.
/// Returns its exit status; 127 when it could not be executed, -1 when it could not be started
/// or ended by a signal.
int run(const std::vector<std::string>& argv);

/// How a child started by runWithin ended.
struct Ending {
  enum class How { Exited, Signalled, TimedOut } how = How::Exited;
  int code = 0;  ///< the exit status (Exited) or the signal (Signalled)
};

/// Runs the executable at the absolute path argv[0] (no PATH lookup, no shell) and waits for it
/// at most `timeout_s` seconds; a child still running then is killed (SIGKILL) and reaped
/// (TimedOut). The wait is a poll(2) on a pipe whose write end only the child holds (as fd 3, so
/// a child that hands fd 3 to processes of its own is waited for until they end too): no clock is
/// read, no sleep. std::nullopt when the program could not be started (missing, not executable,
/// no process to spare).
std::optional<Ending> runWithin(const std::vector<std::string>& argv, std::uint64_t timeout_s);

/// The program to run for a tool: the value of `env_name` (e.g. NEPHELE_GNUPLOT) when set, which
/// must then be an absolute path to an executable file (UsageError otherwise), else `default_name`
/// looked up in PATH.
std::string toolPath(const char* env_name, const char* default_name);

/// `text` as a single-quoted gnuplot string: gnuplot writes a quote inside '...' as two quotes,
/// and interprets no other escapes there.
std::string gnuplotQuoted(const std::string& text);

}  // namespace nph::process

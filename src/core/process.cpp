#include "core/process.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <csignal>

#include <fmt/format.h>

#include "core/env.h"
#include "core/error.h"

namespace nph::process {

namespace {

std::vector<char*> argumentVector(const std::vector<std::string>& argv, const char* who) {
  if (argv.empty()) throw UsageError(fmt::format("{}: empty argument vector", who));
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  return args;
}

/// waitpid, retried on EINTR; false when the child cannot be waited for.
bool reap(pid_t pid, int& status) {
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return false;
  }
  return true;
}

/// RAII for a posix_spawn_file_actions_t.
struct FileActions {
  posix_spawn_file_actions_t a{};
  FileActions() { posix_spawn_file_actions_init(&a); }
  ~FileActions() { posix_spawn_file_actions_destroy(&a); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
};

}  // namespace

int run(const std::vector<std::string>& argv) {
  std::vector<char*> args = argumentVector(argv, "process::run");
  pid_t pid = -1;
  const int err = ::posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ);
  if (err == ENOENT || err == EACCES || err == ENOEXEC || err == ENOTDIR) return 127;  // exec failed
  if (err != 0) return -1;
  int status = 0;
  if (!reap(pid, status)) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::optional<Ending> runWithin(const std::vector<std::string>& argv, std::uint64_t timeout_s) {
  std::vector<char*> args = argumentVector(argv, "process::runWithin");
  constexpr int kAliveFd = 3;
  int alive[2] = {-1, -1};  // the child holds the write end (as fd 3) until it exits: EOF = ended
  if (::pipe2(alive, O_CLOEXEC) != 0) return std::nullopt;
  // Both ends away from fd 3, so dup2 onto 3 in the child always makes a fresh, inheritable fd.
  for (int& fd : alive) {
    const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, 10);
    ::close(fd);
    fd = moved;
  }
  if (alive[0] < 0 || alive[1] < 0) {
    for (const int fd : alive)
      if (fd >= 0) ::close(fd);
    return std::nullopt;
  }
  pid_t pid = -1;
  int err = 0;
  {
    FileActions actions;
    posix_spawn_file_actions_adddup2(&actions.a, alive[1], kAliveFd);
    err = ::posix_spawn(&pid, args[0], &actions.a, nullptr, args.data(), environ);
  }
  ::close(alive[1]);
  if (err != 0) {
    ::close(alive[0]);
    return std::nullopt;
  }
  pollfd pfd{alive[0], POLLIN, 0};
  int ready = 0;
  const int timeout_ms = int(std::min<std::uint64_t>(timeout_s * 1000, std::uint64_t(INT_MAX)));
  while ((ready = ::poll(&pfd, 1, timeout_ms)) < 0 && errno == EINTR) {
  }
  ::close(alive[0]);
  int status = 0;
  if (ready == 0) {  // still running after the limit
    ::kill(pid, SIGKILL);
    reap(pid, status);
    return Ending{Ending::How::TimedOut, 0};
  }
  if (!reap(pid, status)) return std::nullopt;
  if (WIFSIGNALED(status)) return Ending{Ending::How::Signalled, WTERMSIG(status)};
  return Ending{Ending::How::Exited, WEXITSTATUS(status)};
}

std::string toolPath(const char* env_name, const char* default_name) {
  const auto pinned = env::get(env_name);
  if (!pinned) return default_name;
  struct stat st {};
  if (pinned->front() != '/' || ::stat(pinned->c_str(), &st) != 0 || !S_ISREG(st.st_mode) ||
      ::access(pinned->c_str(), X_OK) != 0) {
    throw UsageError(
        fmt::format("{} = \"{}\": expected the absolute path of an executable {}", env_name, *pinned, default_name));
  }
  return *pinned;
}

std::string gnuplotQuoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') out += "''";
    else if (c == '\n' || c == '\r') out += ' ';  // a newline would end the command
    else out += c;
  }
  return out + "'";
}

}  // namespace nph::process

#include "core/process.h"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include <fmt/format.h>

#include "core/env.h"
#include "core/error.h"

namespace nph::process {

int run(const std::vector<std::string>& argv) {
  if (argv.empty()) throw UsageError("process::run: empty argument vector");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
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

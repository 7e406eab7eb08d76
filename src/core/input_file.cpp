#include "core/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"

namespace nph {

void requireRegularFile(const std::string& path, const std::string& expected) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    throw InputError(fmt::format("{}: {}, expected {}", path,
                                 err == ENOENT ? std::string("no such file") : std::generic_category().message(err),
                                 expected));
  }
  if (S_ISREG(st.st_mode)) return;
  const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                     : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                     : S_ISCHR(st.st_mode)  ? "a character device"
                     : S_ISBLK(st.st_mode)  ? "a block device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a regular file";
  throw InputError(fmt::format("{}: is {}, expected {} as a regular file", path, kind, expected));
}

}  // namespace nph

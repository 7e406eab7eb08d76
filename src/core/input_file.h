#pragma once
// Input paths must be regular files (issue #18): a FIFO blocks the first read forever (in the
// CLI and in dataset_open), a device never ends, a directory gives confusing library errors.
// The file type is checked with stat() before anything opens the path, so the refusal does not
// depend on a timeout.
#include <string>

namespace nph {

/// Throws InputError "<path>: is a FIFO (named pipe), expected <expected> as a regular file"
/// (or: no such file, a directory, a character/block device, a socket) unless `path` names a
/// regular file, following symbolic links.
void requireRegularFile(const std::string& path, const std::string& expected);

}  // namespace nph

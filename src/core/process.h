#pragma once
// Running external tools (gnuplot, ffmpeg) without a shell (issue #18): the program gets an
// argument vector through fork/execvp, so no file name can inject a command
// (`nephele-bench accuracy -o "x';touch PWNED;'"` ran `touch` through std::system before).
// Tool paths can be pinned with an environment variable instead of trusting PATH.
#include <string>
#include <vector>

namespace nph::process {

/// Runs argv[0] with `argv` (no shell, PATH lookup only when argv[0] has no '/') and waits.
/// Returns its exit status; 127 when it could not be executed, -1 when it could not be started
/// or ended by a signal.
int run(const std::vector<std::string>& argv);

/// The program to run for a tool: the value of `env_name` (e.g. NEPHELE_GNUPLOT) when set, which
/// must then be an absolute path to an executable file (UsageError otherwise), else `default_name`
/// looked up in PATH.
std::string toolPath(const char* env_name, const char* default_name);

/// `text` as a single-quoted gnuplot string: gnuplot writes a quote inside '...' as two quotes,
/// and interprets no other escapes there.
std::string gnuplotQuoted(const std::string& text);

}  // namespace nph::process

#pragma once
// The body of main() shared by the `nephele` and `nephele-bench` executables: parse the command
// line, install the temp-file cleanup, run the chosen action, and turn typed exceptions into one
// line on stderr and an exit code (STYLE.md 6; cli/commands.h lists the codes).
#include "cli/commands.h"

namespace nph::cli {

/// `program` prefixes every error line ("nephele: error: ...").
int runCommandLine(CLI::App& app, const Action& run, int argc, char** argv, const char* program);

}  // namespace nph::cli

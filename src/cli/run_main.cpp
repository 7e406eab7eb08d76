#include "cli/run_main.h"

#include <cstdio>
#include <exception>
#include <new>

#include "core/error.h"
#include "core/temp_files.h"
#include "core/terminal_text.h"

namespace nph::cli {

int runCommandLine(CLI::App& app, const Action& run, int argc, char** argv, const char* program) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version to stdout, errors to stderr
    return code == 0 ? kExitOk : kExitUsage;
  }
  // Ctrl-C or a kill removes this run's temporary files (a later run would, too).
  temp_files::installSignalCleanup();
  try {
    return run ? run() : kExitUsage;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, terminalSafe(e.what(), false).c_str());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    // The limits (core/limits.h) are checked before every allocation a file can size; this is
    // the machine running out of memory on an accepted input.
    std::fprintf(stderr,
                 "%s: error: out of memory (std::bad_alloc); lower NEPHELE_IO_MEMORY_BUDGET_MB or render a smaller "
                 "image/sub-range\n",
                 program);
    return kExitFailure;
  } catch (const std::exception& e) {  // messages may quote strings from files: escape controls
    std::fprintf(stderr, "%s: error: %s\n", program, terminalSafe(e.what(), false).c_str());
    return kExitFailure;
  }
}

}  // namespace nph::cli

// nephele: command-line front end. Errors inside are typed exceptions (core/error.h); here they
// become one line on stderr and an exit code (STYLE.md 6).
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <new>

#include "cli/commands.h"
#include "core/error.h"
#include "core/temp_files.h"
#include "core/terminal_text.h"

int main(int argc, char** argv) {
  CLI::App app{"nephele: volumetric clouds from weather-model output (WRF wrfout, ICON NetCDF).\n"
               "  info     what a wrfout, ICON or .nph file holds\n"
               "  convert  model files -> ice/water extinction volumes in a .nph cache file\n"
               "  render   one frame of a scene file (deep light map + ray caster), headless\n"
               "  animate  image sequence (and video) of a scene's time range and camera keyframes\n"
               "  bench    benchmarks: `bench accuracy` (run time against error of every quality knob)\n"
               "Run `nephele <command> --help` for the options of a command."};
  app.set_version_flag("--version", "nephele " NEPHELE_VERSION);
  app.require_subcommand(1);
  nph::cli::Action run;
  nph::cli::addInfoCommand(app, run);
  nph::cli::addConvertCommand(app, run);
  nph::cli::addRenderCommand(app, run);
  nph::cli::addAnimateCommand(app, run);
  nph::cli::addBenchCommand(app, run);
  nph::cli::addExportVdbCommand(app, run);
#ifdef NEPHELE_HAVE_GLFW
  nph::cli::addViewCommand(app, run);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version to stdout, errors to stderr
    return code == 0 ? nph::cli::kExitOk : nph::cli::kExitUsage;
  }
  // Ctrl-C or a kill removes this run's temporary files (a later run would, too).
  nph::temp_files::installSignalCleanup();
  try {
    return run ? run() : nph::cli::kExitUsage;
  } catch (const nph::UsageError& e) {
    std::fprintf(stderr, "nephele: error: %s\n", nph::terminalSafe(e.what(), false).c_str());
    return nph::cli::kExitUsage;
  } catch (const std::bad_alloc&) {
    // The limits (core/limits.h) are checked before every allocation a file can size; this is
    // the machine running out of memory on an accepted input.
    std::fprintf(stderr, "nephele: error: out of memory (std::bad_alloc); lower NEPHELE_IO_MEMORY_BUDGET_MB or "
                         "render a smaller image/sub-range\n");
    return nph::cli::kExitFailure;
  } catch (const std::exception& e) {  // messages may quote strings from files: escape controls
    std::fprintf(stderr, "nephele: error: %s\n", nph::terminalSafe(e.what(), false).c_str());
    return nph::cli::kExitFailure;
  }
}

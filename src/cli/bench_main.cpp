// nephele-bench: the tools that are not part of the shipped renderer (issue 17): `accuracy`, the
// run time against error of every quality knob against the path tracer (src/accuracy, which links
// the sample-data generator). Kept out of `nephele` so the product binary links neither.
#include "cli/commands.h"
#include "cli/run_main.h"

int main(int argc, char** argv) {
  CLI::App app{"nephele-bench: benchmarks that need the whole renderer.\n"
               "  accuracy  run time against error of every quality knob (path-traced truth, docs/accuracy.md)\n"
               "Run `nephele-bench <command> --help` for the options of a command. Speed benchmarks of the\n"
               "renderer's phases are Google Benchmark programs: `make bench`."};
  app.set_version_flag("--version", "nephele-bench " NEPHELE_VERSION);
  app.require_subcommand(1);
  nph::cli::Action run;
  nph::cli::addBenchAccuracyCommand(app, run);
  return nph::cli::runCommandLine(app, run, argc, argv, "nephele-bench");
}

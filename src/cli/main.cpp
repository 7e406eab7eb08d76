// nephele: command-line front end. Errors inside are typed exceptions (core/error.h); here they
// become one line on stderr and an exit code (STYLE.md 6; cli/run_main.h).
#include "cli/commands.h"
#include "cli/run_main.h"

int main(int argc, char** argv) {
  CLI::App app{"nephele: volumetric clouds from weather-model output (WRF wrfout, ICON NetCDF).\n"
               "  info        what a wrfout, ICON or .nph file holds\n"
               "  convert     model files -> ice/water extinction volumes in a .nph cache file\n"
               "  render      one frame of a scene file (deep light map + ray caster), headless\n"
               "  animate     image sequence (and video) of a scene's time range and camera keyframes\n"
               "  export-vdb  OpenVDB grids of the extinction volumes (Blender, Houdini, Unreal)\n"
               "  view        interactive window (GLFW builds)\n"
               "Run `nephele <command> --help` for the options of a command. Benchmarks (run time against\n"
               "error of every quality knob) are in the separate tool `nephele-bench`."};
  app.set_version_flag("--version", "nephele " NEPHELE_VERSION);
  app.require_subcommand(1);
  nph::cli::Action run;
  nph::cli::addInfoCommand(app, run);
  nph::cli::addConvertCommand(app, run);
  nph::cli::addRenderCommand(app, run);
  nph::cli::addAnimateCommand(app, run);
  nph::cli::addExportVdbCommand(app, run);
#ifdef NEPHELE_HAVE_GLFW
  nph::cli::addViewCommand(app, run);
#endif
  return nph::cli::runCommandLine(app, run, argc, argv, "nephele");
}

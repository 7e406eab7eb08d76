#pragma once
// Subcommands of the `nephele` executable, one file each (info.cpp, convert.cpp; later render,
// animate, view, bench). Each add*Command registers its CLI11 subcommand with its options; when
// the subcommand is chosen on the command line, its callback stores the action to run in `run`.
// Actions return the process exit code and throw nph::Error subclasses for failures; main.cpp
// turns those into a message on stderr and the exit codes below.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <string>

namespace nph::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  ///< bad input data, I/O errors
inline constexpr int kExitUsage = 2;    ///< bad command line

using Action = std::function<int()>;

/// Check of model-data arguments: an existing file or folder, or a pattern with * ? [ that
/// io::expandModelInputs expands (quoted, the shell's argument limit does not apply to it).
inline CLI::Validator existingPathOrPattern() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        std::error_code ec;
        if (std::filesystem::exists(path, ec) || path.find_first_of("*?[") != std::string::npos) return {};
        return "no such file or folder: " + path;
      },
      "PATH");
}

void addInfoCommand(CLI::App& app, Action& run);
void addConvertCommand(CLI::App& app, Action& run);
void addRenderCommand(CLI::App& app, Action& run);
void addAnimateCommand(CLI::App& app, Action& run);
void addBenchAccuracyCommand(CLI::App& app, Action& run);  ///< nephele-bench only (bench_main.cpp)
void addExportVdbCommand(CLI::App& app, Action& run);      ///< interop/vdb_export.h
void addViewCommand(CLI::App& app, Action& run);           ///< only with NEPHELE_HAVE_GLFW

}  // namespace nph::cli

#pragma once
// Output options shared by `render` and `animate`: the OpenColorIO display and view
// (docs/colour.md).
#include <CLI/CLI.hpp>

#include <string>

#include "scene/output_image.h"

namespace nph::cli {

/// --display NAME, --view NAME.
void addColourOptions(CLI::App& cmd, std::string& display, std::string& view);
/// The command line's display/view over the scene's (output.display, output.view); checks them
/// against the config (InputError listing what it has).
void applyColourOptions(const std::string& display, const std::string& view, scene::ImageOutputOptions& image);

}  // namespace nph::cli

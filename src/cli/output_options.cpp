#include "cli/output_options.h"

#include "core/error.h"
#include "scene/colour_output.h"

namespace nph::cli {

void addColourOptions(CLI::App& cmd, std::string& display, std::string& view) {
  cmd.add_option("--display", display,
                 "PNG colour through OpenColorIO: \"sRGB\", \"Rec.1886 Rec.709\", \"Rec.2100-PQ\", \"Rec.2100-HLG\" "
                 "(16-bit PNG), or a display of output.ocio_config / $NEPHELE_OCIO_CONFIG (docs/colour.md); "
                 "default: the tone curve + sRGB");
  cmd.add_option("--view", view,
                 "OpenColorIO view: \"nephele\" (the ACES fitted curve), \"ACES SDR video\", \"ACES HDR video\", "
                 "\"Raw\"; default: the display's first");
}

void applyColourOptions(const std::string& display, const std::string& view, scene::ImageOutputOptions& image) {
  if (!display.empty()) {
    image.display = display;
    image.view.clear();
  }
  if (!view.empty()) image.view = view;
  if (image.display.empty() && !image.view.empty())
    throw UsageError("--view needs a display (--display or output.display)");
  if (!image.display.empty()) (void)scene::DisplayOutput::open(image.ocio_config, image.display, image.view);
}

}  // namespace nph::cli

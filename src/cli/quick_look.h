#pragma once
// Quick look (issue #15): `nephele render|animate|view <wrfout | ICON | .nph>` with no scene file.
// The framing (engine/quick_look.h, shared with the Python module) is an ordinary scene *file
// text*, so `--print-scene` shows exactly what was rendered and re-rendering the printed file
// gives the same bytes.
#include <memory>
#include <string>
#include <vector>

#include "engine/dataset.h"
#include "scene/scene_file.h"

namespace nph::cli {

/// True when `path` is data rather than a scene file: it starts with the NetCDF classic, HDF5
/// (netCDF-4), GRIB or .nph signature, or it is a folder (of model files: DWD's GRIB2 layout).
/// Scene files are JSON text.
bool isDataFile(const std::string& path);

struct QuickLook {
  std::string scene_json;                          ///< the scene file text (what --print-scene prints)
  scene::SceneDescription scene;                   ///< scene_json parsed
  std::shared_ptr<const engine::Dataset> dataset;  ///< the opened data; timestep 0 already read
};

struct QuickLookRequest {
  std::string data_path;
  std::vector<std::string> outputs;  ///< output.paths; may be empty
  int width = 1920, height = 1080;
};

/// Opens the data, reads its first timestep (once: the returned dataset hands that volume to the
/// renderer instead of reading it again) and frames it. InputError names the file.
QuickLook makeQuickLook(const QuickLookRequest& request);

}  // namespace nph::cli

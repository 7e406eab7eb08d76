#pragma once
// Quick look framing (issue #15; the Python module's default scene, issue #16): the scene file
// text `nephele render|animate|view DATA` renders when given no scene file. The data is framed
// automatically — the oblique preset on the whole domain, the sun from the data's own time and
// place (a fixed afternoon sun where the data has no time or place on Earth, or where that sun
// is below 10°), Blue Marble under georeferenced data, and a height exaggeration that makes the
// troposphere readable at the domain's scale — as ordinary scene text, so `--print-scene` shows
// exactly what was rendered and re-rendering the printed file gives the same bytes.
#include <string>
#include <vector>

#include "volume/extinction_volumes.h"

namespace nph::engine {

struct QuickLookRequest {
  std::string data_path;             ///< the data's file or folder; "" for data in memory (no data.path)
  std::vector<std::string> outputs;  ///< output.paths (made absolute); may be empty
  int width = 1920, height = 1080;
  std::string name;  ///< what the description calls data without a path
};

/// The scene text of a quick look at data whose first timestep is `first_timestep`.
std::string quickLookSceneText(const QuickLookRequest& request, const ExtinctionVolumes& first_timestep);

/// Height exaggeration that shows the cloud layer at the domain's scale: the tallest cloud top
/// becomes about 1/12 of the domain's longer horizontal side, rounded to a whole number in [1, 10]
/// (the sample hurricane, 1500 km wide with tops near 16 km: 8).
double quickLookExaggeration(double domain_long_side_m, double cloud_top_m);

}  // namespace nph::engine

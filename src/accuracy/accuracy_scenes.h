#pragma once
// The standard scenes of the accuracy benchmark (issue 6): what the GPU renderer and the path
// tracer both render, pixel for pixel. Each is a volume, its frame (height exaggeration), a camera
// and a sun:
//   hurricane-above-sun-high      generated WRF hurricane (data_tools), nadir view, sun at 70°
//   hurricane-oblique-sun-low     same storm, oblique view from the south, sun at 12°
//   hurricane-oblique-sun-behind  oblique view, sun behind the camera at 30° (back scattering)
//   stratus-sun-low               ICON-like stratocumulus deck (τ ≈ 5-25), oblique, sun at 15°
//   cumulus-sun-high              field of fair-weather cumuli (cores τ ≈ 30), sun at 65°
//   cumulus-sun-behind            same field, sun behind the camera at 35°
//   cirrus-sun-low                thin ice layer (τ ≈ 0.05-0.6), sun at 10° ahead of the camera
//   hurricane-golden-hour         the hurricane's oblique view, sun at 5° from the west
//   cumulus-golden-hour           the cumulus field, sun at 5° from the west-north-west
// The stratus, cumulus and cirrus volumes are built in memory from smooth seeded noise; the
// hurricane goes through the real chain (NetCDF writer → WRF loader → optics) at reduced size.
#include <string>
#include <vector>

#include "scene/camera.h"
#include "scene/sun.h"
#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::accuracy {

struct AccuracyScene {
  std::string name;
  std::string volume_name;  ///< scenes sharing a volume share it (hurricane, cumulus)
  const ExtinctionVolumes* volumes = nullptr;
  volume::VolumeFrame frame;
  scene::Camera camera;
  scene::Sun sun;
};

/// Owns the volumes the scenes point into.
struct SceneSet {
  std::vector<ExtinctionVolumes> volumes;
  std::vector<AccuracyScene> scenes;
};

/// All standard scenes at width × height pixels. `quick`: smaller volumes (tests).
/// `scratch_dir` receives the generated hurricane NetCDF file.
SceneSet standardScenes(int width, int height, bool quick, const std::string& scratch_dir);

/// In-memory builders (also used by the stress tests). Heights in metres above sea level.
ExtinctionVolumes stratusDeck(int n, unsigned seed);
ExtinctionVolumes cumulusField(int n, unsigned seed);
ExtinctionVolumes cirrusLayer(int n, unsigned seed);

}  // namespace nph::accuracy

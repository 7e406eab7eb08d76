#pragma once
// Scene files: the JSON description of one render (docs/scene-file.md; example
// examples/scenes/hurricane.json). Parsing is strict — an unknown key, a wrong type or a value out
// of range is an InputError naming the file and the JSON path ("scene.json: camera.fov_deg:
// expected a number, got a string") — because a typo in a broadcast graphics job must fail
// loudly, not render with a default.
//
// Relative paths in the file (data, basemap, outputs) are resolved against the scene file's
// folder. Explicit sun and camera values are in the world frame of volume_frame.h (x east, y
// north of the *grid*, metres); "from_time" suns are turned from true north into that frame.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "lighting/knobs.h"
#include "scene/camera.h"
#include "scene/georeference.h"
#include "scene/output_image.h"
#include "scene/passes.h"
#include "scene/sun.h"
#include "volume/volume_frame.h"

namespace nph::scene {

struct DataSpec {
  std::string path;                     ///< .nph cache (or a model file the CLI converts)
  int timestep = 0;                     ///< index into the file's timesteps
  std::optional<std::string> time_utc;  ///< instead of `timestep`: the timestep at this time
};

enum class CameraPreset { Overview, Oblique, Top };

struct CameraSpec {
  /// A preset framed from the volume (cameraFor), unless position_m/target_m are given.
  std::optional<CameraPreset> preset = CameraPreset::Overview;
  std::optional<glm::dvec3> position_m;
  std::optional<glm::dvec3> target_m;
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fov_deg = 40.0;                ///< vertical field of view
  std::optional<double> azimuth_deg;    ///< preset: compass direction from the target to the camera
  std::optional<double> elevation_deg;  ///< preset: angle of the camera above the horizon
  double distance_scale = 1.0;          ///< preset: 1 frames the volume, < 1 moves closer
};

struct SunSpec {
  bool from_time = false;               ///< solar position at the footprint centre
  std::optional<std::string> time_utc;  ///< from_time: this time instead of the data's
  double azimuth_deg = 135.0;           ///< explicit: world frame, clockwise from grid north
  double elevation_deg = 45.0;
  glm::dvec3 colour{1.0, 1.0, 1.0};
  double intensity = 1.0;
};

struct BasemapSpec {
  std::string path;             ///< equirectangular image
  double margin = 0.25;         ///< around the footprint, fraction of its larger side
  int pixels_long_side = 2048;  ///< resolution of the reprojected basemap
  /// The night side's city lights (issue 14; scene/night_lights.h), warped onto the basemap's
  /// grids: any GDAL raster as `path`; empty = night_lights.h kCityLightsPath where installed.
  /// Drawn with the style knob city_lights (0 = off, then not read).
  std::string night_lights;
};

/// "terrain": the ground's heights beyond the model's own field (issue 14 item 2; scene/dem.h).
struct TerrainSpec {
  /// A user DEM: any GDAL raster with a CRS and one band of metres. Inside the domain it replaces
  /// the model's field where it has data; beyond the domain it is the ground to the horizon.
  std::string dem;
};

struct OutputSpec {
  std::vector<std::string> paths;  ///< .png and/or .exr; may be empty when the CLI gives them
  int width = 1920;
  int height = 1080;
  ImageOutputOptions image{kDefaultExposureEv, ToneCurve::AcesFitted, /*write_depth=*/false,
                           /*date_time=*/{}};   ///< exposure, tone curve, Z in EXR
  ExposureMode exposure = ExposureMode::Fixed;  ///< "exposure": fixed, or following the sun (image.exposure_ev at 35°)
  bool passes = false;  ///< "passes": .exr outputs carry the compositing passes as layers (scene/passes.h)
  std::vector<std::pair<Pass, std::string>> pass_files;  ///< "pass_files": {"shadow": "matte.png", ...}
  /// Whether the renderer must produce the passes (Z, layers or pass files).
  bool wantsPasses() const { return image.write_depth || passes || !pass_files.empty(); }
};

/// The image options of a frame lit by a sun at `sun_elevation_deg`: spec.image with, under
/// ExposureMode::Sun, sunExposureOffsetEv added to its exposure. Every writer of a frame (render,
/// animate, view, the Python module) takes its options from here.
ImageOutputOptions imageOptionsFor(const OutputSpec& spec, double sun_elevation_deg);

/// The image written to output.paths: the frame, with Z (output.depth) or with every pass as a
/// layer (output.passes; Z included). `passes` may be null only when !spec.wantsPasses().
RgbaImage outputFrame(const OutputSpec& spec, const RgbaImage& frame, const RgbaImage& cloud,
                      const FramePasses* passes);

enum class ViewMode { Flat, Globe };

struct SceneDescription {
  std::string source_file;  ///< the scene file, for messages ("<string>" when parsed from text)
  std::optional<DataSpec> data;
  CameraSpec camera;
  SunSpec sun;
  std::optional<BasemapSpec> basemap;
  std::optional<TerrainSpec> terrain;  ///< "terrain": {"dem": ...}; none: the model's own field only
  lighting::QualitySettings quality;   ///< "quality": a preset and overrides (lighting/knobs.h)
  lighting::StyleSettings style;       ///< "style": the look (the knob table's style rows)
  OutputSpec output;
  double height_exaggeration = 1.0;  ///< Nes 2008 §5.5.2
  ViewMode view = ViewMode::Flat;
  LonLatOffset lonlat_offset;                 ///< Nes 2008 §5.5.1
  std::optional<LonLat> centre_if_cartesian;  ///< placement of idealised (Cartesian) grids
  std::string base_dir;                       ///< folder relative paths were resolved against
  std::string animation_json;  ///< the "animation" section as JSON text, "" when absent (engine/animation.h)
};

/// Reads and parses a scene file; InputError on a missing file, bad JSON or a bad value.
SceneDescription loadSceneFile(const std::string& path);
/// Parses JSON text; `name` appears in messages, relative paths are resolved against `base_dir`.
SceneDescription parseSceneText(std::string_view text, const std::string& name, const std::string& base_dir = "");

/// The camera of `spec` for a volume: presets frame the volume's bounding box so it fills the
/// view at `distance_scale` = 1. Overview: from the south, 55° above the horizon; oblique: from
/// the south-south-west (azimuth 200°), 20° above the horizon, a little closer; top: straight down,
/// north up. Flat-map world frame (the globe view transforms it).
Camera cameraFor(const CameraSpec& spec, const volume::VolumeFrame& frame, int width, int height);

/// The sun of `spec`: explicit values, or (from_time) the solar position at the footprint centre
/// at `spec.time_utc` or else `data_time_utc`, turned into the world frame (grid north).
/// Throws InputError when from_time has no time or no georeference.
Sun sunFor(const SunSpec& spec, const SceneGeoreference* geo, const geo::OptionalUtcTime& data_time);

}  // namespace nph::scene

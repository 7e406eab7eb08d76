// Quick look framing (quick_look.h).
#include "engine/quick_look.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/log.h"
#include "scene/basemap.h"
#include "scene/georeference.h"
#include "scene/scene_file.h"
#include "volume/volume_frame.h"

namespace nph::engine {
namespace {

/// NASA Blue Marble from Debian's marble-qt-data (tools/debian-packages.txt).
constexpr const char* kBlueMarble = scene::kBlueMarblePath;
/// The fixed sun of a quick look without a usable solar position: mid-afternoon from the
/// south-east quadrant, high enough for readable shadows (as the make-demo scene).
constexpr double kFixedSunAzimuth_deg = 140.0;
constexpr double kFixedSunElevation_deg = 35.0;
/// Below this the timed sun lights the clouds from the side or below: a poor first picture.
constexpr double kMinTimedSunElevation_deg = 10.0;
/// A voxel counts as cloud from this extinction on (optical depth 0.01 over 100 m).
constexpr float kCloudExtinction_per_m = 1e-4f;

/// Where the cloud is, from one scan of the voxels (a voxel counts from kCloudExtinction_per_m on).
struct CloudExtent {
  /// Top of the highest cloudy layer above mean sea level; the whole column for clear air.
  double top_m = 0.0;
  /// How far the cloud reaches horizontally from the domain's centre, as a fraction of the domain's
  /// half diagonal: the farthest corner of any column holding cloud (1 for clear air, so the domain
  /// is framed as before). The presets frame the domain's bounding sphere about its centre, so
  /// scaling their distance by this keeps every cloudy column in the frame while a storm that fills
  /// a third of its domain (a hurricane run's nest, make demo's storm) is no longer a third of the
  /// picture.
  double reach = 1.0;
};

CloudExtent cloudExtent(const ExtinctionVolumes& v) {
  const std::size_t layer = std::size_t(v.nx) * std::size_t(v.ny);
  std::vector<char> cloudy(layer, 0);
  int top_layer = -1;
  for (int k = 0; k < v.nz; ++k) {
    const std::size_t base = std::size_t(k) * layer;
    for (std::size_t n = 0; n < layer; ++n) {
      if (v.ice_per_m[base + n] > kCloudExtinction_per_m || v.water_per_m[base + n] > kCloudExtinction_per_m) {
        cloudy[n] = 1;
        top_layer = k;
      }
    }
  }
  CloudExtent e;
  e.top_m = v.z_bottom_m + double(top_layer >= 0 ? top_layer + 1 : v.nz) * v.dz_m;
  if (top_layer < 0) return e;
  const double cx = 0.5 * v.nx, cy = 0.5 * v.ny;  // in columns; dx = dy for the grids nephele reads
  double reach2 = 0.0;
  for (int j = 0; j < v.ny; ++j) {
    for (int i = 0; i < v.nx; ++i) {
      if (!cloudy[std::size_t(j) * std::size_t(v.nx) + std::size_t(i)]) continue;
      const double dx = std::max(std::abs(i - cx), std::abs(i + 1 - cx)),
                   dy = std::max(std::abs(j - cy), std::abs(j + 1 - cy));
      reach2 = std::max(reach2, dx * dx + dy * dy);
    }
  }
  e.reach = std::sqrt(reach2 / (cx * cx + cy * cy));
  return e;
}

/// The quick look's camera distance never drops below this share of the preset's: the storm's
/// surroundings and the basemap stay in the picture.
constexpr double kMinDistanceScale = 0.35;

}  // namespace

double quickLookExaggeration(double domain_long_side_m, double cloud_top_m) {
  if (!(domain_long_side_m > 0.0) || !(cloud_top_m > 0.0)) return 1.0;
  const double e = std::round(domain_long_side_m / (12.0 * cloud_top_m));
  return std::clamp(e, 1.0, 10.0);
}

std::string quickLookSceneText(const QuickLookRequest& r, const ExtinctionVolumes& v) {
  const volume::VolumeFrame unit = volume::frameOf(v, 1.0);
  const glm::dvec3 extent = unit.size_m();
  // Framed on the cloud, not the domain: the camera closes in by the cloud's reach (rounded to
  // 0.05, at least kMinDistanceScale) and the exaggeration follows the framed width.
  const CloudExtent cloud = cloudExtent(v);
  const double scale = std::clamp(std::ceil(cloud.reach * 20.0) / 20.0, kMinDistanceScale, 1.0);
  const double exaggeration = quickLookExaggeration(scale * std::max(extent.x, extent.y), cloud.top_m);
  const bool on_earth = !v.georef.proj_definition.empty();

  nlohmann::ordered_json j;
  j["description"] = fmt::format("quick look at {} (nephele --print-scene; docs/scene-file.md)",
                                 r.data_path.empty() ? r.name : std::filesystem::path(r.data_path).filename().string());
  if (r.data_path.empty()) {  // data in memory (the Python module's arrays): handed to the renderer
    j["data"] = {{"timestep", 0}};
  } else {
    j["data"] = {{"path", std::filesystem::absolute(r.data_path).lexically_normal().string()}, {"timestep", 0}};
  }
  j["camera"] = {{"preset", "oblique"}, {"fov_deg", 40}};
  if (scale < 1.0) j["camera"]["distance_scale"] = scale;

  // The sun from the data's own time and place when that gives a daylit picture.
  bool timed_sun = false;
  if (on_earth && v.time_utc) {
    try {
      const volume::VolumeFrame frame = volume::frameOf(v, exaggeration);
      const scene::SceneGeoreference geo(v, frame);
      scene::SunSpec spec;
      spec.from_time = true;
      const scene::Sun sun = scene::sunFor(spec, &geo, v.time_utc);
      timed_sun = sun.elevation_deg >= kMinTimedSunElevation_deg;
      if (!timed_sun) {
        log::info("quick look: the sun at {} is {:.1f} deg high there; using a fixed afternoon sun",
                  v.time_utc->iso8601(), sun.elevation_deg);
      }
    } catch (const InputError& e) {
      log::info("quick look: no solar position ({}); using a fixed afternoon sun", e.what());
    }
  }
  if (timed_sun) {
    j["sun"] = {{"from_time", true}};
  } else {
    j["sun"] = {{"azimuth_deg", kFixedSunAzimuth_deg}, {"elevation_deg", kFixedSunElevation_deg}};
  }
  if (on_earth && std::filesystem::exists(kBlueMarble)) {
    j["basemap"] = {{"path", kBlueMarble}, {"margin", 0.4}, {"pixels_long_side", 2048}};
  }
  j["quality"] = {{"preset", "broadcast"}};
  std::vector<std::string> outputs;  // absolute: the printed scene works from any folder
  for (const auto& o : r.outputs) outputs.push_back(std::filesystem::absolute(o).lexically_normal().string());
  j["output"] = {{"paths", outputs}, {"width", r.width}, {"height", r.height}};
  j["height_exaggeration"] = exaggeration;
  j["view"] = "flat";

  return j.dump(2) + "\n";
}

}  // namespace nph::engine

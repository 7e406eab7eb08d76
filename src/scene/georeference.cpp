#include "scene/georeference.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"

namespace nph::scene {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
/// Step for the finite-difference true-north direction [deg of latitude] (~1.1 km).
constexpr double kNorthStep_deg = 0.01;

// ---- SceneGeoreference -----------------------------------------------------------------------

std::string projectionFor(const geo::GridGeoreference& grid, const std::optional<LonLat>& centre) {
  if (!grid.proj_definition.empty()) return grid.proj_definition;
  if (!centre) {
    throw InputError("the volume's grid is Cartesian (no map projection in the model file): give "
                     "the lon/lat of its centre to place it on the Earth");
  }
  return fmt::format("+proj=aeqd +lat_0={} +lon_0={} +x_0=0 +y_0=0 +R={} +units=m +no_defs", centre->lat_deg,
                     centre->lon_deg, volume::kEarthRadius_m);
}

}  // namespace

SceneGeoreference::SceneGeoreference(const geo::GridGeoreference& grid, const volume::VolumeFrame& frame,
                                     LonLatOffset offset, std::optional<LonLat> centre_if_cartesian)
    : frame_(frame), offset_(offset), projection_(projectionFor(grid, centre_if_cartesian)) {
  if (!std::isfinite(offset.lon_deg) || !std::isfinite(offset.lat_deg)) {
    throw UsageError("SceneGeoreference: lon/lat offset must be finite");
  }
  const glm::dvec3 size = frame.size_m();
  if (grid.proj_definition.empty()) {
    origin_ = {-0.5 * size.x, -0.5 * size.y};  // aeqd centred on the footprint
    scale_ = {1.0, 1.0};
  } else if (grid.geographic) {
    // Undo frameOf()'s local equirectangular scaling (same central latitude, same sphere).
    const double latCentre = grid.y0 + 0.5 * double(frame.voxels.y - 1) * grid.dy_m;
    const double metresPerDegree = volume::kEarthRadius_m * kDeg;
    scale_ = {1.0 / (metresPerDegree * std::cos(latCentre * kDeg)), 1.0 / metresPerDegree};
    origin_ = {grid.x0 - 0.5 * grid.dx_m, grid.y0 - 0.5 * grid.dy_m};
  } else {
    scale_ = {1.0, 1.0};
    origin_ = {grid.x0 - 0.5 * grid.dx_m, grid.y0 - 0.5 * grid.dy_m};
  }
}

glm::dvec2 SceneGeoreference::projectedFromWorld(glm::dvec2 w) const { return origin_ + w * scale_; }
glm::dvec2 SceneGeoreference::worldFromProjected(glm::dvec2 p) const { return (p - origin_) / scale_; }

LonLat SceneGeoreference::lonLatFromWorld(glm::dvec2 world_xy_m) const {
  LonLat ll = projection_.inverse(projectedFromWorld(world_xy_m));
  ll.lon_deg = normaliseLongitude_deg(ll.lon_deg + offset_.lon_deg);
  ll.lat_deg += offset_.lat_deg;
  return ll;
}

glm::dvec2 SceneGeoreference::worldFromLonLat(LonLat ll) const {
  const LonLat data{ll.lon_deg - offset_.lon_deg, ll.lat_deg - offset_.lat_deg};
  return worldFromProjected(projection_.forward(data));
}

void SceneGeoreference::lonLatFromWorldBatch(double* xy, std::size_t n) const {
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec2 p = projectedFromWorld({xy[2 * i], xy[2 * i + 1]});
    xy[2 * i] = p.x;
    xy[2 * i + 1] = p.y;
  }
  projection_.inverseBatch(xy, n);
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(xy[2 * i])) continue;
    xy[2 * i] = normaliseLongitude_deg(xy[2 * i] + offset_.lon_deg);
    xy[2 * i + 1] += offset_.lat_deg;
  }
}

std::array<LonLat, 4> SceneGeoreference::footprintCorners() const {
  const glm::dvec3 s = frame_.size_m();
  return {lonLatFromWorld({0.0, 0.0}), lonLatFromWorld({s.x, 0.0}), lonLatFromWorld({s.x, s.y}),
          lonLatFromWorld({0.0, s.y})};
}

LonLat SceneGeoreference::footprintCentre() const {
  const glm::dvec3 s = frame_.size_m();
  return lonLatFromWorld({0.5 * s.x, 0.5 * s.y});
}

void SceneGeoreference::footprintBounds(LonLat& lo, LonLat& hi) const {
  constexpr int kSamplesPerEdge = 64;
  const glm::dvec3 s = frame_.size_m();
  lo = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  hi = {-lo.lon_deg, -lo.lat_deg};
  for (int k = 0; k <= kSamplesPerEdge; ++k) {
    const double t = double(k) / kSamplesPerEdge;
    for (glm::dvec2 w :
         {glm::dvec2{t * s.x, 0.0}, glm::dvec2{t * s.x, s.y}, glm::dvec2{0.0, t * s.y}, glm::dvec2{s.x, t * s.y}}) {
      const LonLat ll = lonLatFromWorld(w);
      lo = {std::min(lo.lon_deg, ll.lon_deg), std::min(lo.lat_deg, ll.lat_deg)};
      hi = {std::max(hi.lon_deg, ll.lon_deg), std::max(hi.lat_deg, ll.lat_deg)};
    }
  }
}

double SceneGeoreference::trueNorthClockwiseFromGridNorth_deg(glm::dvec2 world_xy_m) const {
  const LonLat ll = lonLatFromWorld(world_xy_m);
  const double south = std::max(ll.lat_deg - kNorthStep_deg, -90.0 + kNorthStep_deg);
  const double north = std::min(ll.lat_deg + kNorthStep_deg, 90.0 - kNorthStep_deg);
  const glm::dvec2 d = worldFromLonLat({ll.lon_deg, north}) - worldFromLonLat({ll.lon_deg, south});
  return std::atan2(d.x, d.y) / kDeg;
}

Sun SceneGeoreference::sunInWorld(const Sun& geographic, glm::dvec2 world_xy_m) const {
  Sun s = geographic;
  const double az = s.azimuth_deg + trueNorthClockwiseFromGridNorth_deg(world_xy_m);
  s.azimuth_deg = az - 360.0 * std::floor(az / 360.0);
  return s;
}

glm::dvec3 SceneGeoreference::ecefFromWorld(const glm::dvec3& world_m) const {
  return ecefFromLonLat(lonLatFromWorld({world_m.x, world_m.y}), world_m.z);
}

// ---- globe -----------------------------------------------------------------------------------

glm::dvec3 ecefFromLonLat(LonLat ll, double height_m, double radius_m) {
  const double lon = ll.lon_deg * kDeg, lat = ll.lat_deg * kDeg, r = radius_m + height_m;
  return {r * std::cos(lat) * std::cos(lon), r * std::cos(lat) * std::sin(lon), r * std::sin(lat)};
}

LonLat lonLatFromEcef(const glm::dvec3& p) {
  return {std::atan2(p.y, p.x) / kDeg, std::atan2(p.z, std::hypot(p.x, p.y)) / kDeg};
}

glm::dmat3 ecefFromEnu(LonLat ll) {
  const double lon = ll.lon_deg * kDeg, lat = ll.lat_deg * kDeg;
  const glm::dvec3 east{-std::sin(lon), std::cos(lon), 0.0};
  const glm::dvec3 north{-std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat)};
  const glm::dvec3 up{std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
  return glm::dmat3(east, north, up);
}

Camera globeCameraFrom(const Camera& flat, const SceneGeoreference& geo) {
  constexpr double kUpStep_m = 1000.0;  // short enough that the sphere is flat over it
  Camera c = flat;
  c.position_m = geo.ecefFromWorld(flat.position_m);
  c.target_m = geo.ecefFromWorld(flat.target_m);
  c.up = glm::normalize(geo.ecefFromWorld(flat.target_m + kUpStep_m * glm::normalize(flat.up)) - c.target_m);
  // The whole Earth may be in view: the far plane must reach past the horizon.
  c.far_m = std::max(flat.far_m, glm::length(c.position_m) + volume::kEarthRadius_m);
  return c;
}

glm::dvec3 toSunEcef(const Sun& world_sun, const SceneGeoreference& geo, glm::dvec2 world_xy_m) {
  Sun geographic = world_sun;
  geographic.azimuth_deg -= geo.trueNorthClockwiseFromGridNorth_deg(world_xy_m);
  return glm::normalize(ecefFromEnu(geo.lonLatFromWorld(world_xy_m)) * geographic.toSun());
}

}  // namespace nph::scene

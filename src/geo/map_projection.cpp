#include "geo/map_projection.h"

#include <fmt/format.h>
#include <proj.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace nph::geo {
namespace {

/// PROJ reports failed points as HUGE_VAL; anything beyond this is not a coordinate.
constexpr double kNotACoordinate = 1e30;

bool usable(double v) { return std::isfinite(v) && std::abs(v) < kNotACoordinate; }
bool usableLatitude(double lat_deg) { return usable(lat_deg) && std::abs(lat_deg) <= 90.0 + 1e-9; }

/// The geographic side: longlat on the definition's own sphere/ellipsoid (see the datum note in
/// the header). proj_crs_get_geodetic_crs is no use here: for ob_tran it returns the rotated CRS
/// itself.
std::string geographicCrsOf(const std::string& proj_definition) {
  std::string figure;
  std::istringstream tokens(proj_definition);
  for (std::string token; tokens >> token;) {
    for (const char* key : {"+R=", "+a=", "+b=", "+rf=", "+f=", "+ellps=", "+datum="}) {
      if (token.rfind(key, 0) == 0) figure += " " + token;
    }
  }
  if (figure.empty()) figure = " +ellps=WGS84";
  return "+proj=longlat" + figure + " +no_defs +type=crs";
}

}  // namespace

double normaliseLongitude_deg(double lon) {
  double r = std::fmod(lon + 180.0, 360.0);
  if (r <= 0.0) r += 360.0;
  return r - 180.0;
}

struct MapProjection::Impl {
  PJ_CONTEXT* ctx = nullptr;
  PJ* pj = nullptr;
  ~Impl() {
    proj_destroy(pj);
    proj_context_destroy(ctx);
  }
};

MapProjection::MapProjection(const std::string& proj_definition)
    : impl_(std::make_unique<Impl>()), definition_(proj_definition) {
  impl_->ctx = proj_context_create();
  proj_log_level(impl_->ctx, PJ_LOG_NONE);
  const std::string geographic = geographicCrsOf(proj_definition);
  const std::string projected = proj_definition + " +type=crs";
  PJ* raw = proj_definition.empty()
                ? nullptr
                : proj_create_crs_to_crs(impl_->ctx, geographic.c_str(), projected.c_str(), nullptr);
  PJ* normalized = raw ? proj_normalize_for_visualization(impl_->ctx, raw) : nullptr;
  proj_destroy(raw);
  if (normalized == nullptr) {
    throw InputError(fmt::format("PROJ cannot use the projection '{}' (expected a PROJ string "
                                 "such as '+proj=lcc +lat_1=30 +lat_2=60 +lon_0=-75 +R=6370000')",
                                 proj_definition));
  }
  impl_->pj = normalized;
}

MapProjection::~MapProjection() = default;
MapProjection::MapProjection(MapProjection&&) noexcept = default;
MapProjection& MapProjection::operator=(MapProjection&&) noexcept = default;

glm::dvec2 MapProjection::forward(LonLat ll) const {
  const PJ_COORD out = proj_trans(impl_->pj, PJ_FWD, proj_coord(ll.lon_deg, ll.lat_deg, 0.0, 0.0));
  if (!usable(out.xy.x) || !usable(out.xy.y)) {
    throw InputError(fmt::format("projection '{}' cannot project lon {} lat {}", definition_, ll.lon_deg, ll.lat_deg));
  }
  return {out.xy.x, out.xy.y};
}

LonLat MapProjection::inverse(glm::dvec2 xy) const {
  const PJ_COORD out = proj_trans(impl_->pj, PJ_INV, proj_coord(xy.x, xy.y, 0.0, 0.0));
  if (!usable(out.lp.lam) || !usableLatitude(out.lp.phi)) {
    throw InputError(fmt::format("projection '{}' cannot invert x {} y {}", definition_, xy.x, xy.y));
  }
  return {out.lp.lam, out.lp.phi};
}

void MapProjection::inverseBatch(double* xy, std::size_t n) const {
  if (n == 0) return;
  const std::size_t stride = 2 * sizeof(double);
  proj_trans_generic(impl_->pj, PJ_INV, xy, stride, n, xy + 1, stride, n, nullptr, 0, 0, nullptr, 0, 0);
  for (std::size_t i = 0; i < n; ++i) {
    double& lon = xy[2 * i];
    double& lat = xy[2 * i + 1];
    if (!usable(lon) || !usableLatitude(lat)) lon = lat = std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace nph::geo

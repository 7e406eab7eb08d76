#include "geo_transform.h"

#include <fmt/format.h>
#include <proj.h>

#include <cmath>

#include "core/error.h"

namespace nph::datagen {

GeoTransform::GeoTransform(const std::string& proj_definition, double sphere_radius_m)
    : definition_(proj_definition) {
  ctx_ = proj_context_create();
  const std::string geographic = fmt::format("+proj=longlat +R={} +no_defs +type=crs", sphere_radius_m);
  const std::string projected = proj_definition + " +type=crs";
  PJ* raw = proj_create_crs_to_crs(ctx_, geographic.c_str(), projected.c_str(), nullptr);
  if (raw == nullptr) {
    proj_context_destroy(ctx_);
    throw UsageError(fmt::format("PROJ cannot build a transform for '{}'", proj_definition));
  }
  pj_ = proj_normalize_for_visualization(ctx_, raw);
  proj_destroy(raw);
  if (pj_ == nullptr) {
    proj_context_destroy(ctx_);
    throw UsageError(fmt::format("PROJ cannot normalise the transform for '{}'", proj_definition));
  }
}

GeoTransform::~GeoTransform() {
  proj_destroy(pj_);
  proj_context_destroy(ctx_);
}

void GeoTransform::forward(double lon_deg, double lat_deg, double& x, double& y) const {
  const PJ_COORD out = proj_trans(pj_, PJ_FWD, proj_coord(lon_deg, lat_deg, 0.0, 0.0));
  x = out.xy.x;
  y = out.xy.y;
  if (!std::isfinite(x) || !std::isfinite(y)) {
    throw UsageError(fmt::format("PROJ '{}' cannot project lon {} lat {}", definition_, lon_deg, lat_deg));
  }
}

void GeoTransform::inverse(double x, double y, double& lon_deg, double& lat_deg) const {
  const PJ_COORD out = proj_trans(pj_, PJ_INV, proj_coord(x, y, 0.0, 0.0));
  lon_deg = out.lp.lam;
  lat_deg = out.lp.phi;
  if (!std::isfinite(lon_deg) || !std::isfinite(lat_deg)) {
    throw UsageError(fmt::format("PROJ '{}' cannot invert x {} y {}", definition_, x, y));
  }
}

}  // namespace nph::datagen

#include "projection.h"

#include <fmt/format.h>
#include <proj.h>

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace nph::io {

Projection::Projection(const std::string& proj_definition) : definition_(proj_definition) {
  ctx_ = proj_context_create();
  proj_log_level(ctx_, PJ_LOG_NONE);
  // The geographic side is longlat on the definition's own sphere/ellipsoid. (PROJ's
  // proj_crs_get_geodetic_crs is no use here: for ob_tran it returns the rotated CRS itself.)
  std::string figure;
  std::istringstream tokens(proj_definition);
  for (std::string token; tokens >> token;) {
    for (const char* key : {"+R=", "+a=", "+b=", "+rf=", "+f=", "+ellps=", "+datum="}) {
      if (token.rfind(key, 0) == 0) figure += " " + token;
    }
  }
  if (figure.empty()) figure = " +ellps=WGS84";
  const std::string geographic = "+proj=longlat" + figure + " +no_defs +type=crs";
  const std::string projected = proj_definition + " +type=crs";
  PJ* raw = proj_create_crs_to_crs(ctx_, geographic.c_str(), projected.c_str(), nullptr);
  PJ* normalized = raw ? proj_normalize_for_visualization(ctx_, raw) : nullptr;
  proj_destroy(raw);
  if (normalized == nullptr) {
    proj_context_destroy(ctx_);
    throw InputError(fmt::format("PROJ cannot use the projection '{}'", proj_definition));
  }
  pj_ = normalized;
}

Projection::~Projection() {
  proj_destroy(pj_);
  proj_context_destroy(ctx_);
}

void Projection::forward(double lon_deg, double lat_deg, double& x, double& y) const {
  const PJ_COORD out = proj_trans(pj_, PJ_FWD, proj_coord(lon_deg, lat_deg, 0.0, 0.0));
  x = out.xy.x;
  y = out.xy.y;
  if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 1e30 || std::abs(y) > 1e30) {
    throw InputError(fmt::format("projection '{}' cannot project lon {} lat {}", definition_, lon_deg, lat_deg));
  }
}

void Projection::inverse(double x, double y, double& lon_deg, double& lat_deg) const {
  const PJ_COORD out = proj_trans(pj_, PJ_INV, proj_coord(x, y, 0.0, 0.0));
  lon_deg = out.lp.lam;
  lat_deg = out.lp.phi;
  if (!std::isfinite(lon_deg) || !std::isfinite(lat_deg) || std::abs(lat_deg) > 90.0 + 1e-9) {
    throw InputError(fmt::format("projection '{}' cannot invert x {} y {}", definition_, x, y));
  }
}

void gridLonLat(const Projection& projection, const Georeference& georef, double i, double j,
                double& lon_deg, double& lat_deg) {
  projection.inverse(georef.x0 + i * georef.dx_m, georef.y0 + j * georef.dy_m, lon_deg, lat_deg);
}

}  // namespace nph::io

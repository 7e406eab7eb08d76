#pragma once
// Map projections of model grids through PROJ: lon/lat (degrees, on the projection's own sphere
// or ellipsoid) <-> projected x/y (metres, or degrees for longlat / rotated-pole grids).
#include <string>

#include "model_fields.h"

struct pj_ctx;
struct PJconsts;

namespace nph::io {

class Projection {
 public:
  /// `proj_definition` as in Georeference::proj_definition (a PROJ string without +type=crs).
  explicit Projection(const std::string& proj_definition);
  ~Projection();
  Projection(const Projection&) = delete;
  Projection& operator=(const Projection&) = delete;

  /// Throws InputError when PROJ cannot transform the point.
  void forward(double lon_deg, double lat_deg, double& x, double& y) const;
  void inverse(double x, double y, double& lon_deg, double& lat_deg) const;

 private:
  pj_ctx* ctx_ = nullptr;
  PJconsts* pj_ = nullptr;
  std::string definition_;
};

/// Longitude/latitude of mass point (i, j) of a georeferenced grid.
void gridLonLat(const Projection& projection, const Georeference& georef, double i, double j,
                double& lon_deg, double& lat_deg);

}  // namespace nph::io

#pragma once
// Geographic <-> projected transform through PROJ for the generators (lon/lat in degrees,
// x/y in the projection's units: metres, or degrees for longlat / ob_tran).
#include <string>

struct pj_ctx;
struct PJconsts;

namespace nph::datagen {

class GeoTransform {
 public:
  /// `proj_definition` is a PROJ string without +type=crs; the geographic side is a sphere of
  /// radius `sphere_radius_m` (WRF: 6 370 000 m).
  GeoTransform(const std::string& proj_definition, double sphere_radius_m);
  ~GeoTransform();
  GeoTransform(const GeoTransform&) = delete;
  GeoTransform& operator=(const GeoTransform&) = delete;

  void forward(double lon_deg, double lat_deg, double& x, double& y) const;
  void inverse(double x, double y, double& lon_deg, double& lat_deg) const;

 private:
  pj_ctx* ctx_ = nullptr;
  PJconsts* pj_ = nullptr;
  std::string definition_;
};

}  // namespace nph::datagen

#include "scene/volume_frame.h"

#include <cmath>
#include <numbers>

#include "core/error.h"

namespace nph::scene {

VolumeFrame frameOf(const ExtinctionVolumes& v, double height_exaggeration) {
  if (v.nx <= 0 || v.ny <= 0 || v.nz <= 0) {
    throw UsageError("frameOf: empty extinction volume (" + std::to_string(v.nx) + "x" +
                     std::to_string(v.ny) + "x" + std::to_string(v.nz) + ")");
  }
  if (!(height_exaggeration > 0.0) || !std::isfinite(height_exaggeration)) {
    throw UsageError("frameOf: height exaggeration must be a positive number");
  }
  VolumeFrame f;
  f.voxels = {v.nx, v.ny, v.nz};
  f.height_exaggeration = height_exaggeration;
  double dx = v.georef.dx_m, dy = v.georef.dy_m;
  if (v.georef.geographic) {
    double latCentre = v.georef.y0 + 0.5 * double(v.ny - 1) * v.georef.dy_m;
    const double degToRad = std::numbers::pi / 180.0;
    dx = v.georef.dx_m * degToRad * kEarthRadius_m * std::cos(latCentre * degToRad);
    dy = v.georef.dy_m * degToRad * kEarthRadius_m;
  }
  if (!(dx > 0.0) || !(dy > 0.0) || !(v.dz_m > 0.0)) {
    throw UsageError("frameOf: non-positive grid spacing");
  }
  f.voxel_size_m = {dx, dy, v.dz_m * height_exaggeration};
  f.z_bottom_m = v.z_bottom_m * height_exaggeration;
  return f;
}

}  // namespace nph::scene

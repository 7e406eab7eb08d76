#include "volume/volume_frame.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "core/error.h"

namespace nph::volume {

VolumeFrame frameOf(const ExtinctionVolumes& v, double height_exaggeration) {
  if (v.nx <= 0 || v.ny <= 0 || v.nz <= 0) {
    throw UsageError("frameOf: empty extinction volume (" + std::to_string(v.nx) + "x" + std::to_string(v.ny) + "x" +
                     std::to_string(v.nz) + ")");
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
  // Plausible spacings and heights, checked before they reach float textures and int texel
  // counts (dx = 1e+-300 m and z_bottom_m = +-1e308 overflowed conversions in the DLM and the
  // ray caster). 1 mm .. 10 000 km covers LES to global grids.
  constexpr double kMinSpacing_m = 1e-3, kMaxSpacing_m = 1e7, kMaxAbsHeight_m = 1e6;
  const auto spacing_ok = [](double s) { return s >= kMinSpacing_m && s <= kMaxSpacing_m; };
  if (!spacing_ok(dx) || !spacing_ok(dy) || !spacing_ok(v.dz_m) || !std::isfinite(v.z_bottom_m) ||
      std::abs(v.z_bottom_m) > kMaxAbsHeight_m) {
    throw InputError(fmt::format("{}: grid spacing dx {} m, dy {} m, dz {} m, bottom {} m; expected spacings in "
                                 "[{}, {}] m and a bottom within +-{} m",
                                 v.source_file.empty() ? std::string("extinction volume") : v.source_file, dx, dy,
                                 v.dz_m, v.z_bottom_m, kMinSpacing_m, kMaxSpacing_m, kMaxAbsHeight_m));
  }
  f.voxel_size_m = {dx, dy, v.dz_m * height_exaggeration};
  f.z_bottom_m = v.z_bottom_m * height_exaggeration;
  return f;
}

}  // namespace nph::volume

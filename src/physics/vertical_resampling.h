#pragma once
// From model levels (terrain-following, non-uniform, different in every column) to a uniform
// metric height grid (Muth 2026 §3.3.1 "Resampling"): per column, PCHIP (pchip.h) through the
// values at the mass-level heights; the horizontal grid stays native.
//
// Per column (i, j) with mass-level heights h_0 < ... < h_{n-1} and surface height s (HGT;
// without one, s = h_0 - (h_1 - h_0)/2, the first mass level lies half a layer above ground),
// the layer centred at z is
//   0                         z < s (below the terrain)
//   y_0                       s <= z <= h_0 (the lowest model layer reaches down to the ground)
//   PCHIP(z)                  h_0 < z < h_{n-1}
//   y_{n-1}                   up to half a layer above h_{n-1}, 0 beyond (above the model top)
//
// Bottom: z_bottom = dz * floor(min_ij s / dz) unless given, the same for all timesteps of a
// conversion (the terrain does not change). Top (Nes 2008 §5.6: keep only what the scene needs):
// cropped just above the highest condensate — the highest level k with β > crop threshold in
// any column, whose values vanish at h_{k+1} — plus one empty guard layer; or a fixed z_top.
#include <optional>

#include "io/model_fields.h"
#include "physics/extinction.h"
#include "volume/extinction_volumes.h"

namespace nph::physics {

struct VerticalGridOptions {
  double dz_m = 250.0;
  std::optional<double> z_bottom_m;  ///< default: from the lowest terrain
  std::optional<double> z_top_m;     ///< default: cropped above the highest condensate
  /// β [1/m] below which a level counts as empty for the crop: 1e-6 /m is an optical depth of
  /// 1e-3 per km, invisible.
  double crop_threshold_per_m = 1e-6;
};

struct VerticalGrid {
  double z_bottom_m = 0.0;
  double dz_m = 0.0;
  int nz = 0;
};

/// dz * floor(lowest surface height / dz).
double defaultBottomHeight_m(const io::ModelTimestep& ts, double dz_m);

/// Height of the highest non-empty level (crop rule above); nullopt when all is empty.
std::optional<double> condensateTopHeight_m(const io::ModelTimestep& ts, const ModelLevelExtinction& beta,
                                            double threshold_per_m);

VerticalGrid planVerticalGrid(const io::ModelTimestep& ts, const ModelLevelExtinction& beta,
                              const VerticalGridOptions& options);

/// Resamples `beta` onto `grid` into out.ice_per_m / out.water_per_m (sets nx, ny, nz, dz_m,
/// z_bottom_m; leaves the other fields). InputError when a column's heights do not increase.
void resampleVertically(const io::ModelTimestep& ts, const ModelLevelExtinction& beta, const VerticalGrid& grid,
                        ExtinctionVolumes& out);

/// A model-level field other than β (the sub-grid detail's TKE, cloud fraction, W; issue 13) on
/// `grid`: linear in height between mass levels (these fields only steer the procedural detail,
/// PCHIP's shape preservation buys nothing there), the end values below the lowest and above the
/// highest mass level. Empty when `field` is empty; InputError when its size is not nx·ny·nz.
std::vector<float> resampleFieldVertically(const io::ModelTimestep& ts, const std::vector<float>& field,
                                           const char* name, const VerticalGrid& grid);

}  // namespace nph::physics

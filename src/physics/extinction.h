#pragma once
// Extinction coefficients on the model's own levels (Nes 2008 §5.2.1, eq. 5.3-5.4, §5.6).
//
// For every hydrometeor class f with mass per kg of air q_f:
//   C_f = ρ_ref q_f                        mass content [kg/m³] (air_density.h: ρ_ref is the dry
//                                          density for WRF, the moist density for ICON)
//   β_f = 3 C_f / (2 ρ_f r_f)              Nes eq. 5.3: spheres of radius r_f, Q_ext = 2
// (r_f from the number concentration where available, effective_radius.h). The classes are
// summed into two volumes (Nes §5.6): water = cloud + rain, ice = ice + snow + graupel + hail.
// Single-scattering albedo ≈ 1 (Nes §2.2.2), so β_ext is also β_sca.
//
// Scheme-dependent phase: for WRF schemes without separate ice arrays (OpticsSettings::
// temperature_split_schemes, WSM3) QCLOUD below 273.15 K is cloud ice and QRAIN is snow: they
// take the ice/snow optics and go into the ice volume.
// ICON: the Muth §3.3.1 corrections (icon_corrections.h) are applied to qc/qi first when the
// file carries cloud cover. Negative mixing ratios (numerical noise of WRF's advection) count
// as 0; NaN/Inf in any field used, p <= 0 or T <= 0 are InputErrors naming file, variable, voxel.
#include <array>
#include <limits>
#include <vector>

#include "io/model_fields.h"
#include "physics/optics_settings.h"

namespace nph::physics {

/// Everything the optics need at one voxel. Absent classes have q = 0; absent number
/// concentrations and cloud cover are NaN.
struct VoxelState {
  io::ModelKind model = io::ModelKind::Wrf;
  int microphysics_scheme = -1;
  double pressure_pa = 0.0;
  double temperature_k = 0.0;
  double vapour_kg_per_kg = 0.0;
  std::array<double, io::kAllHydrometeors.size()> q_kg_per_kg{};
  std::array<double, io::kAllHydrometeors.size()> number_per_kg{
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  double cloud_cover = std::numeric_limits<double>::quiet_NaN();
};

struct VoxelExtinction {
  double ice_per_m = 0.0;
  double water_per_m = 0.0;
  double reference_density_kg_per_m3 = 0.0;  ///< ρ_ref used (dry for WRF, moist for ICON)
};

VoxelExtinction voxelExtinction(const VoxelState& v, const OpticsSettings& settings);

/// β fields on model levels, same layout as io::ModelTimestep.
struct ModelLevelExtinction {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> ice_per_m;
  std::vector<float> water_per_m;
};

/// Validates the timestep's fields (sizes, required fields, finite values; InputError naming
/// ts.source_file and the variable) and computes β at every voxel (parallel over rows).
ModelLevelExtinction modelLevelExtinction(const io::ModelTimestep& ts, const OpticsSettings& settings);

}  // namespace nph::physics

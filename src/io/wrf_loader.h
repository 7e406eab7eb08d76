#pragma once
// WRF ARW `wrfout` loader (NetCDF-C): one timestep at a time, on the model's own mass levels.
// WRF stores hydrometeors as mass ratios of particles to (dry) air, "particle/air mass ratios for
// rain, cloud, snow, ice and graupel" (Nes 2008 §5.1.1, §2.2.3 eq. 2.5: M_t = V rho_air H); they
// are handed over unchanged per class, whichever exist, with the scheme (MP_PHYSICS) recorded
// because schemes without separate ice keep frozen condensate in QCLOUD/QRAIN.
#include <cstdint>
#include <string>
#include <vector>

#include "load_options.h"
#include "model_fields.h"

namespace nph::io {

/// WRF constants (WRF share/module_model_constants.F; Skamarock et al. 2019, ARW v4 tech note).
inline constexpr double kWrfGravity_m_per_s2 = 9.81;              ///< g
inline constexpr double kWrfGasConstantDryAir_J_per_kgK = 287.0;  ///< R_d
/// c_p = 7 R_d / 2 (ideal diatomic gas), so R_d / c_p = 2/7 = 0.2857.
inline constexpr double kWrfSpecificHeatDryAir_J_per_kgK = 7.0 * kWrfGasConstantDryAir_J_per_kgK / 2.0;
inline constexpr double kWrfReferencePressure_pa = 100000.0;  ///< p0 of the Exner function
inline constexpr double kWrfThetaOffset_k = 300.0;            ///< T in wrfout is θ - 300 K
inline constexpr double kWrfEarthRadius_m = 6370000.0;        ///< WRF's sphere (EARTH_RADIUS_M)

/// Projection attributes of a wrfout file (global attributes).
struct WrfProjectionAttributes {
  int map_proj = 0;
  double truelat1 = 0, truelat2 = 0, stand_lon = 0, cen_lat = 0, cen_lon = 0, moad_cen_lat = 0;
  double pole_lat = 90, pole_lon = 0;
  double dx_m = 0, dy_m = 0;
};

/// Georeference of WRF mass points from the projection attributes: MAP_PROJ 1 Lambert conformal,
/// 2 polar stereographic, 3 Mercator, 6 lat-lon (rotated pole when POLE_LAT != 90), 0 Cartesian;
/// all on WRF's sphere of radius 6 370 000 m. The domain centre ((nx-1)/2, (ny-1)/2) lies at
/// (CEN_LAT, CEN_LON). `path` is for messages; InputError names the offending attribute.
geo::GridGeoreference wrfGeoreference(const WrfProjectionAttributes& attributes, int nx, int ny,
                                      const std::string& path);

/// The time of every timestep in the file (WRF `Times`); none where the file has no `Times` or a
/// row is not a time (logged).
std::vector<geo::OptionalUtcTime> listWrfTimes(const std::string& path);

/// Loads timestep `time_index` of a wrfout file. With LoadOptions::defer_detail the sub-grid
/// detail's fields (CLDFRA, TKE_PBL/QKE, W, U, V) are left out and `detail_deferred` is set.
ModelTimestep loadWrfTimestep(const std::string& path, std::int64_t time_index, const LoadOptions& options = {});

/// Reads the detail fields that loadWrfTimestep left out into `ts` (from ts.source_file at
/// ts.time_index; InputError if the file's grid is no longer ts's).
void loadWrfDetail(ModelTimestep& ts, const LoadOptions& options = {});

}  // namespace nph::io

#pragma once
// The contract between the model loaders (io/: WRF, ICON) and the optics (physics/).
// A loader turns one timestep of one file into ModelTimestep: fields on the model's own
// (terrain-following, non-uniform) levels, SI units, with the georeference of the horizontal grid.
// Layout of every 3-D field: x fastest, then y, then level k (bottom to top):
//   index(i, j, k) = (k * ny + j) * nx + i.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geo/grid_georeference.h"
#include "geo/utc_time.h"

namespace nph::io {

/// Hydrometeor classes (Nes 2008 §2.2.3; WRF Q*, ICON q*).
enum class Hydrometeor : std::uint8_t { Cloud, Rain, Ice, Snow, Graupel, Hail };
inline constexpr std::array kAllHydrometeors = {Hydrometeor::Cloud, Hydrometeor::Rain,    Hydrometeor::Ice,
                                                Hydrometeor::Snow,  Hydrometeor::Graupel, Hydrometeor::Hail};

/// Which model produced the file; decides how mixing ratios are to be read (see below).
enum class ModelKind : std::uint8_t { Wrf, Icon };

/// What a loader repaired while reading one timestep (counts of values), for logs and `nephele info`.
/// (ICON's condensate consistency corrections, Muth 2026 §3.3.1, are not applied by the loaders:
/// physics/icon_corrections.h applies them, so loaded ICON fields are exactly the file's.)
struct LoadRepairs {
  std::int64_t negative_clamped = 0;  ///< negative mixing ratios / cloud cover set to 0
  std::int64_t missing_as_zero = 0;   ///< _FillValue / missing_value in condensate fields read as 0
};

/// One timestep of model output on model levels.
struct ModelTimestep {
  std::string source_file;        ///< path of the file this timestep came from
  std::int64_t time_index = 0;    ///< index of the timestep inside source_file
  geo::OptionalUtcTime time_utc;  ///< parsed from the file (WRF Times, ICON time); none when it does not say
  ModelKind model = ModelKind::Wrf;
  int nx = 0, ny = 0, nz = 0;  ///< mass points

  /// Mixing ratios [kg/kg] per class present in the file. WRF: per kg of dry air.
  /// ICON: specific contents, per kg of moist air. Absent classes are absent from the map.
  std::map<Hydrometeor, std::vector<float>> q_kg_per_kg;
  /// Number concentrations [1/kg] where a two-moment scheme wrote them (WRF QN*).
  std::map<Hydrometeor, std::vector<float>> number_per_kg;
  std::vector<float> water_vapour_kg_per_kg;  ///< QVAPOR (dry mixing ratio) or qv (specific)
  std::vector<float> pressure_pa;             ///< full pressure (WRF P+PB)
  std::vector<float> temperature_k;           ///< air temperature (WRF: from θ and Exner)
  std::vector<float> height_m;                ///< mass-level height above mean sea level
  std::vector<float> terrain_height_m;        ///< nx*ny surface height above MSL
  std::vector<float> cloud_cover_fraction;    ///< ICON clc / 100, may be empty

  /// Fields for sub-grid detail (issue 13), on mass points, each empty when the file has none.
  /// WRF: CLDFRA; TKE_PBL (else QKE / 2: MYNN's QKE is twice the TKE); W, U, V averaged from
  /// their staggered points to the mass points. Not used by the optics.
  std::vector<float> cloud_fraction;                                  ///< WRF CLDFRA [0, 1]
  std::vector<float> tke_m2_per_s2;                                   ///< turbulent kinetic energy
  std::vector<float> wind_u_m_per_s, wind_v_m_per_s, wind_w_m_per_s;  ///< grid-relative x, y and vertical wind
  /// The detail fields above are not loaded yet (LoadOptions::defer_detail): io::loadDeferredDetail
  /// reads them.
  bool detail_deferred = false;

  /// WRF MP_PHYSICS option (e.g. 3 = WSM3: no separate ice, frozen condensate lives in
  /// QCLOUD/QRAIN below 0 °C). -1 when unknown or not WRF.
  int microphysics_scheme = -1;

  geo::GridGeoreference georef;  ///< horizontal georeference of the native grid

  LoadRepairs repairs;  ///< added for issue 3 (io): what the loader repaired

  std::size_t voxelCount() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx) + std::size_t(i);
  }
};

}  // namespace nph::io

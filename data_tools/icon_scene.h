#pragma once
// ICON-like cloud scene (stratus deck, scattered cumulus, thin cirrus) written as ICON's own
// lon-lat NetCDF output / `cdo -f nc copy` of DWD's regular-lat-lon GRIB2 writes it, or on a small
// native triangular (icosahedral) grid. Levels are ordered top to bottom, as ICON writes them.
// Both condensate inconsistencies of Muth 2026 §3.3.1 are present on purpose:
//   A: CLC = 0 where QC + QI > 0 (thin cirrus in the east, cumulus fringes),
//   B: CLC > 0 where QC + QI = 0 (a dissolving stratus patch whose condensate was depleted).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geo/utc_time.h"

#include "nc_writer.h"

namespace nph::datagen {

struct IconSceneSpec {
  int nlon = 40, nlat = 36, nz = 20;       ///< regular grid points and full levels
  int ntimes = 2;                          ///< hourly timesteps
  double lon0_deg = 9.0, lat0_deg = 46.0;  ///< first grid point (south-west corner)
  double dlon_deg = 0.1, dlat_deg = 0.1;
  bool lat_descending = false;  ///< write lat north to south (as some GRIB scans do)
  double model_top_m = 20000.0;
  std::uint64_t seed = 1;
  NcFormat format = NcFormat::Classic64;
  /// Native grid: icosahedron edges divided into this many parts (ICON RnBk: n * 2^k);
  /// 0 writes the regular lat-lon file.
  int native_divisions = 0;
};

struct IconTruth {
  int nlon = 0, nlat = 0, nz = 0, ntimes = 0;
  std::int64_t ncells = 0;  ///< native grid cells (0 for regular)
  /// Cells (all timesteps) with inconsistency A (CLC = 0, QC + QI > 0) and B (CLC > 0, QC + QI = 0).
  std::int64_t clc_zero_with_condensate = 0;
  std::int64_t clc_without_condensate = 0;
  std::string first_time_utc;  ///< ISO 8601
};

IconTruth writeIconScene(const IconSceneSpec& spec, const std::string& path);

/// The scene sampled on its horizontal points one timestep at a time: what writeIconScene writes
/// as NetCDF, for other writers (GRIB2: grib2_writer.h) to write the very same values.
class IconSceneSampler {
 public:
  /// UsageError (naming `path`) for an impossible spec or a native grid without cells.
  IconSceneSampler(const IconSceneSpec& spec, const std::string& path);
  ~IconSceneSampler();
  bool native() const;
  /// Regular grid axes [deg]: longitudes west to east, latitudes in written order.
  const std::vector<double>& lonAxisDeg() const;
  const std::vector<double>& latAxisDeg() const;
  /// Native grid: cell centres [radian], in file order.
  std::vector<double> cellLonRad() const;
  std::vector<double> cellLatRad() const;
  /// Horizontal points per level (regular: row by row, nlon x nlat; native: cells).
  std::size_t points() const;
  geo::UtcTime time(int t) const;
  /// Fields of timestep t, ICON's names and units (temp [K], pres [Pa], qv, qc, qi, qr, qs, qg
  /// [kg/kg], clc [%], z_ifc [m] on nz + 1 half levels), level-major with the model top first.
  /// Counts the condensate inconsistencies into `truth` when given.
  std::map<std::string, std::vector<float>> fields(int t, IconTruth* truth) const;

 private:
  friend IconTruth writeIconScene(const IconSceneSpec& spec, const std::string& path);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// ICON's Earth radius [m] (mo_physical_constants: earth_radius = 6.371229e6).
inline constexpr double kIconEarthRadius_m = 6371229.0;

}  // namespace nph::datagen

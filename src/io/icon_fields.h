#pragma once
// What the two ICON readers share (io/-internal): the NetCDF loader (icon_loader.cpp) and the
// GRIB2 loader (grib2_loader.cpp) read the same ICON quantities from different containers, check
// each field as it is read (checkIconField), and hand the fields on the source points to one
// assembly (assembleIconTimestep) that orders the levels bottom to top, derives full-level
// heights from half levels (Muth 2026 §3.2: z_k = (h_k + h_k+1) / 2) and maps the horizontal
// points onto nephele's regular grid, resampling the native triangular grid. So a GRIB2 file and
// its `cdo -f nc copy` give the same ModelTimestep, bit for bit where the values agree.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "load_options.h"
#include "model_fields.h"

namespace nph::io {

/// ICON quantities as the readers check them (units as ICON and DWD's GRIB2 write them).
enum class IconQuantity : std::uint8_t {
  Condensate,        ///< specific content [kg/kg]: at most kMaxMixingRatio, negatives clamped to 0
  SpecificHumidity,  ///< qv [kg/kg]: as Condensate
  Temperature,       ///< [K] in [100, 400]
  Pressure,          ///< [Pa] in [1, 2e5]
  Height,            ///< HHL / z_ifc / z_mc [m] in [kLowestHeight_m, kHighestHeight_m]
  CloudCoverPercent  ///< clc [%] (or a fraction when `fraction_units`): to [0, 1], clamped
};

/// Checks (and repairs, counting in `repairs`) one field as read; InputError names `origin`
/// ("file: variable") and the first bad element. `fraction_units`: clc already in [0, 1].
void checkIconField(const std::string& path, const std::string& var, IconQuantity quantity, std::vector<float>& data,
                    LoadRepairs& repairs, bool fraction_units = false);

/// One ICON timestep on the source points, as a reader found it. Every 3-D field is level-major
/// (level k, then point p: index k * npoints + p), levels in file order (ICON: top first).
struct IconSourceFields {
  std::string path;  ///< named in errors and in ModelTimestep::source_file
  std::int64_t time_index = 0;
  geo::OptionalUtcTime time_utc;
  std::size_t nz = 0;       ///< full levels
  std::size_t npoints = 0;  ///< horizontal source points

  std::map<Hydrometeor, std::vector<float>> q_kg_per_kg;
  std::vector<float> temperature_k, pressure_pa, water_vapour_kg_per_kg;
  std::vector<float> cloud_cover_fraction;  ///< may be empty
  std::vector<float> heights_m;             ///< nz + 1 half levels, or nz full levels
  bool heights_are_half_levels = true;
  std::string heights_name;  ///< the heights' variable, for errors
  LoadRepairs repairs;

  /// Horizontal points. Regular grid: `lon_deg` (nlon, increasing) and `lat_deg` (nlat, either
  /// direction), points row by row (p = j * nlon + i). Native grid: one lon/lat per point.
  bool native = false;
  std::vector<double> lon_deg, lat_deg;
  std::string lon_name = "lon", lat_name = "lat";  ///< for errors
};

/// Orders, derives and maps `src` into nephele's ModelTimestep (see the file comment).
ModelTimestep assembleIconTimestep(IconSourceFields src, const LoadOptions& options);

}  // namespace nph::io

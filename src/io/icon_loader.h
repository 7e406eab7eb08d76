#pragma once
// ICON loader (NetCDF-C). Variables as Muth 2026 §3.2 (table 3.1) lists them: CLC [%], specific
// QC/QI (+ QR/QS/QG), QV, T, P on full levels, heights HHL/z_ifc on half levels (levels numbered
// from the model top), full-level heights as half-level midpoints.
// Formats: regular lat-lon output (ICON's lon-lat NetCDF output, or
// `cdo -f nc copy` of DWD's regular-lat-lon GRIB2) and native triangular-grid output (ncells,
// clon/clat in radians), the latter resampled onto a regular lat-lon grid. Fields are delivered as
// the file has them (clc as a fraction): the Muth 2026 §3.3.1 condensate consistency corrections
// are the optics' job (physics/icon_corrections.h), so they are applied exactly once.
#include <cstdint>
#include <string>
#include <vector>

#include "load_options.h"
#include "model_fields.h"

namespace nph::io {

/// ICON's Earth radius [m] (ICON mo_physical_constants: earth_radius = 6.371229e6 m).
inline constexpr double kIconEarthRadius_m = 6371229.0;

/// The time of every timestep in the file (none when the file has no time axis or unknown units).
std::vector<geo::OptionalUtcTime> listIconTimes(const std::string& path);

/// Loads timestep `time_index` of an ICON file (regular or native; see sniffFormat).
ModelTimestep loadIconTimestep(const std::string& path, std::int64_t time_index, const LoadOptions& options = {});

/// Converts a CF/ICON time value to a UTC time: units "<unit> since YYYY-MM-DD[ hh:mm:ss]"
/// (unit seconds/minutes/hours/days) or ICON's absolute "day as %Y%m%d.%f". None when unknown.
geo::OptionalUtcTime timeFromValue(double value, const std::string& units);

}  // namespace nph::io

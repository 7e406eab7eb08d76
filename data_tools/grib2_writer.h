#pragma once
// The ICON scene (icon_scene.h) as GRIB2, written through ecCodes' C API
// (codes_grib_handle_new_from_samples("GRIB2"), codes_set_*, values, message appended): the same
// float values as the NetCDF file, in DWD's ICON conventions, so the GRIB2 and NetCDF paths of
// nephele can be compared. Centre 78 (DWD, "edzw"), so ecCodes names the parameters with DWD's
// shortNames (QC, QI, ..., HHL, CLON, CLAT); model levels are typeOfFirstFixedSurface 150
// (generalized vertical height), level 1 at the top, full levels as layers [k, k+1], HHL on the
// half levels 1 .. nz + 1; run 2026-03-18 12 UTC, forecastTime t hours.
#include <string>
#include <vector>

#include "icon_scene.h"

namespace nph::datagen {

enum class Grib2Layout {
  DwdFiles,   ///< one file per variable, level and step, DWD's open-data names; HHL (and CLON/CLAT) once
  SingleFile  ///< every message in one file (icon_scene.grib2)
};

struct Grib2WriteOptions {
  Grib2Layout layout = Grib2Layout::DwdFiles;
  /// ecCodes packingType: grid_simple (DWD's classic), grid_ccsds (DWD since 2023), grid_ieee
  /// (32-bit floats: the NetCDF file's values exactly), ... (ecCodes 2.28's grid_complex encoder
  /// loses data: see tests/io/grib2_loader_test.cpp)
  std::string packing = "grid_simple";
  long bits_per_value = 16;  ///< for the packings that take it (not grid_ieee)
  /// Native grid: uuidOfHGrid of the fields (16 bytes as 32 hex digits) and of CLON/CLAT.
  std::string fields_uuid = "0123456789abcdef0123456789abcdef";
  std::string coordinates_uuid = "0123456789abcdef0123456789abcdef";
  bool write_hhl = true;  ///< false: leave HHL out (a hostile data set)
};

/// Writes the scene into folder `dir` (created); returns the files written, sorted.
std::vector<std::string> writeIconSceneGrib2(const IconSceneSpec& spec, const std::string& dir,
                                             const Grib2WriteOptions& options = {});

}  // namespace nph::datagen

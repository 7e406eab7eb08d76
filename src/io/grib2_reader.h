#pragma once
// GRIB2 messages through ecCodes' C API (codes_handle_new_from_file, codes_get_*): an index of
// every message of a file (what it is, where, on which grid, packed how) without the values, and
// the values of one message on demand. Any packing ecCodes decodes is read (simple, complex with
// spatial differencing, CCSDS, JPEG 2000, PNG, IEEE, second order); what it cannot decode, or a
// non-grid-point packing, is an InputError naming the file, the message and the packing.
// WMO GRIB2 (FM 92 GRIB edition 2): Section 0 holds "GRIB", the edition (2) and the message's
// total length; Section 8 is "7777".
#include <cstdint>
#include <string>
#include <vector>

namespace nph::io {

/// The horizontal grid of a message (Section 3), as far as nephele reads it.
struct Grib2Grid {
  std::string type;        ///< ecCodes gridType: "regular_ll", "unstructured_grid", ...
  std::size_t points = 0;  ///< numberOfDataPoints
  // regular_ll (template 3.0): first point and increments in degrees, scanning mode flags.
  long ni = 0, nj = 0;
  double lat_first_deg = 0, lon_first_deg = 0, di_deg = 0, dj_deg = 0;
  bool i_scans_negatively = false, j_scans_positively = false, j_points_consecutive = false;
  // unstructured_grid (template 3.101, ICON's native grid): the grid's identity.
  std::string uuid;                             ///< uuidOfHGrid as 32 hex digits
  long grid_number = 0, grid_in_reference = 0;  ///< numberOfGridUsed, numberOfGridInReference

  bool operator==(const Grib2Grid&) const = default;
  /// "regular_ll 40 x 36 from (46 N, 9 E) by (0.1, 0.1) deg" / "unstructured_grid 1234 cells uuid ...".
  std::string describe() const;
};

/// One GRIB2 message as indexed (no values).
struct Grib2Message {
  std::string file;
  std::size_t number = 0;   ///< 1-based position in `file`
  std::int64_t offset = 0;  ///< byte offset of "GRIB" in `file`
  std::string short_name;   ///< ecCodes shortName (DWD's tables where centre = 78, edzw)
  long discipline = 0, category = 0, parameter = 0;
  long level_type = 0;         ///< typeOfFirstFixedSurface (150: generalized vertical height)
  long level = 0;              ///< scaled value of the first fixed surface (ICON: level number, 1 = top)
  std::string valid_time_utc;  ///< validityDate/validityTime as ISO 8601
  Grib2Grid grid;
  std::string packing;      ///< packingType
  long data_template = -1;  ///< dataRepresentationTemplateNumber (code table 5.0)
  long bits_per_value = 0;

  /// "FILE: message N (SHORTNAME, level L, TIME)", the prefix of every error about it.
  std::string where() const;
};

/// True when `path` is a regular file starting with the GRIB signature (edition not checked).
bool hasGribSignature(const std::string& path);

/// Indexes every message of `path`. InputError when the file is not GRIB edition 2, when a
/// message is truncated (its Section 0 length runs past the end of the file, or "7777" is
/// missing), or when ecCodes cannot parse a message; the error names the file and the message.
std::vector<Grib2Message> scanGrib2File(const std::string& path);

/// Decoded values of one message in the file's scanning order; `missing_points` counts the points
/// the bitmap marks missing (their values are NaN). InputError for packings ecCodes cannot decode
/// or that are not grid-point data.
std::vector<double> readGrib2Values(const Grib2Message& message, std::size_t& missing_points);

/// Packing types (packingType) read as grid-point data.
const std::vector<std::string>& supportedGrib2Packings();

}  // namespace nph::io

#pragma once
// The exact size a classic NetCDF file (CDF-1, CDF-2, CDF-5) must have, read from its header.
//
// NetCDF-C opens a truncated classic file and returns zeros for the missing bytes, so a wrfout
// missing the last 6 KB of QCLOUD converted without a word. The previous check assumed a 32-byte
// header; a real header (hundreds of attributes) is many KB, which hid the truncation. NetCDF-C
// does not expose the variables' file offsets ("begin"), so this walks the header as the format
// specification lays it out (NetCDF Users Guide, "File Format Specifications", classic format
// BNF) and returns max(begin + bytes) over the variables.
#include <cstdint>
#include <optional>
#include <string>

namespace nph::io {

/// Bytes a classic-format file must hold for all the data its header declares (the end of the
/// last variable's last record); nullopt when `path` is not a classic file or its header cannot
/// be walked (the caller then keeps NetCDF-C's own checks). A header declaring numrecs as
/// "streaming" (0xFFFFFFFF) counts as zero records.
std::optional<std::uint64_t> classicDataEnd_bytes(const std::string& path);

}  // namespace nph::io

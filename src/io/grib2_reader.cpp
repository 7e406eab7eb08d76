#include "grib2_reader.h"

#include <eccodes.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>

#include "core/error.h"
#include "core/input_file.h"
#include "core/log.h"
#include "geo/utc_time.h"

namespace nph::io {
namespace {

/// ecCodes writes its complaints to stderr by default; they become debug lines of nephele's log,
/// and the InputError that follows says what went wrong in nephele's words.
void routeEccodesLog() {
  static std::once_flag once;
  std::call_once(once, [] {
    codes_context_set_logging_proc(codes_context_get_default(), [](const codes_context*, int, const char* message) {
      log::debug("ecCodes: {}", message ? message : "");
    });
  });
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;
struct HandleDeleter {
  void operator()(codes_handle* h) const { codes_handle_delete(h); }
};
using HandlePtr = std::unique_ptr<codes_handle, HandleDeleter>;

FilePtr openFile(const std::string& path) {
  requireRegularFile(path, "a GRIB2 file");
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) throw InputError(fmt::format("{}: cannot be opened for reading", path));
  return f;
}

/// The message starting at `offset` of `f`, parsed by ecCodes.
HandlePtr handleAt(std::FILE* f, const std::string& path, std::size_t number, std::int64_t offset) {
  if (std::fseek(f, long(offset), SEEK_SET) != 0) {
    throw InputError(fmt::format("{}: message {} at byte {} cannot be reached", path, number, offset));
  }
  int err = 0;
  HandlePtr h(codes_handle_new_from_file(nullptr, f, PRODUCT_GRIB, &err));
  if (!h || err != CODES_SUCCESS) {
    throw InputError(fmt::format("{}: message {} at byte {} cannot be parsed by ecCodes ({}), expected a GRIB2 message",
                                 path, number, offset, codes_get_error_message(err)));
  }
  return h;
}

long getLong(codes_handle* h, const char* key, long fallback) {
  long v = 0;
  return codes_get_long(h, key, &v) == CODES_SUCCESS ? v : fallback;
}
double getDouble(codes_handle* h, const char* key, double fallback) {
  double v = 0;
  return codes_get_double(h, key, &v) == CODES_SUCCESS ? v : fallback;
}
std::string getString(codes_handle* h, const char* key) {
  std::array<char, 256> buffer{};
  std::size_t length = buffer.size();
  if (codes_get_string(h, key, buffer.data(), &length) != CODES_SUCCESS) return "";
  return std::string(buffer.data());
}

/// uuidOfHGrid (16 bytes of template 3.101) as 32 hex digits.
std::string uuidOf(codes_handle* h) {
  std::array<unsigned char, 16> bytes{};
  std::size_t length = bytes.size();
  if (codes_get_bytes(h, "uuidOfHGrid", bytes.data(), &length) != CODES_SUCCESS || length != bytes.size()) return "";
  std::string hex;
  for (unsigned char b : bytes) hex += fmt::format("{:02x}", b);
  return hex;
}

std::string isoFromValidity(long date, long time) {
  const int y = int(date / 10000), mo = int(date / 100 % 100), d = int(date % 100);
  const int hh = int(time / 100), mi = int(time % 100);
  if (mo < 1 || mo > 12 || d < 1 || d > geo::daysInMonth(y, mo) || hh > 23 || mi > 59) return "";
  return geo::UtcTime::fromCivil(y, mo, d, hh, mi).iso8601();
}

/// Section 0 of GRIB edition 2: "GRIB", 2 reserved octets, discipline, edition, 8-octet length.
struct Section0 {
  int edition = 0;
  std::uint64_t total_length = 0;
};

}  // namespace

std::string Grib2Grid::describe() const {
  if (type == "regular_ll") {
    return fmt::format("regular_ll {} x {} from ({} N, {} E) by ({}, {}) deg{}", ni, nj, lat_first_deg, lon_first_deg,
                       di_deg, dj_deg, j_scans_positively ? ", south to north" : ", north to south");
  }
  if (type == "unstructured_grid") {
    return fmt::format("unstructured_grid {} cells, grid {} uuidOfHGrid {}", points, grid_number, uuid);
  }
  return fmt::format("{} ({} points)", type, points);
}

std::string Grib2Message::where() const {
  return fmt::format("{}: message {} ({}, level {}, {})", file, number, short_name, level,
                     valid_time_utc.empty() ? "no time" : valid_time_utc);
}

const std::vector<std::string>& supportedGrib2Packings() {
  static const std::vector<std::string> kPackings = {
      "grid_simple", "grid_complex",      "grid_complex_spatial_differencing", "grid_ccsds", "grid_jpeg", "grid_png",
      "grid_ieee",   "grid_second_order", "grid_simple_log_preprocessing"};
  return kPackings;
}

bool hasGribSignature(const std::string& path) {
  // Only regular files are opened: a FIFO would block this read forever (issue #18); the loaders
  // refuse the others by file type with their own message.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  return in.read(magic.data(), 4) && std::string(magic.data(), 4) == "GRIB";
}

std::vector<Grib2Message> scanGrib2File(const std::string& path) {
  routeEccodesLog();
  FilePtr f = openFile(path);
  const std::uint64_t file_size = std::filesystem::file_size(path);
  // Frame the messages from Section 0 before ecCodes sees them, so that truncation is reported as
  // such (ecCodes would only say "end of resource reached" or skip the rest silently).
  std::vector<std::int64_t> offsets;
  std::uint64_t pos = 0;
  while (pos < file_size) {
    std::array<unsigned char, 16> s0{};
    if (std::fseek(f.get(), long(pos), SEEK_SET) != 0) break;
    const std::size_t got = std::fread(s0.data(), 1, s0.size(), f.get());
    const bool grib = got >= 4 && std::equal(s0.begin(), s0.begin() + 4, "GRIB");
    if (!grib) {
      if (offsets.empty()) {
        throw InputError(fmt::format("{}: does not start with \"GRIB\", expected a GRIB2 file", path));
      }
      // Padding after the last message (some writers pad to a block size): only zeros allowed.
      std::vector<unsigned char> rest(std::size_t(std::min<std::uint64_t>(file_size - pos, 1 << 16)));
      (void)std::fseek(f.get(), long(pos), SEEK_SET);
      const std::size_t n = std::fread(rest.data(), 1, rest.size(), f.get());
      if (std::all_of(rest.begin(), rest.begin() + std::ptrdiff_t(n), [](unsigned char c) { return c == 0; })) break;
      throw InputError(fmt::format("{}: after message {} (ending at byte {}) come {} bytes that are not a GRIB "
                                   "message, expected \"GRIB\" or the end of the file",
                                   path, offsets.size(), pos, file_size - pos));
    }
    const std::size_t number = offsets.size() + 1;
    if (got < s0.size()) {
      throw InputError(fmt::format("{}: message {} at byte {} is truncated: the file ends {} bytes into its 16-byte "
                                   "Section 0",
                                   path, number, pos, got));
    }
    Section0 head;
    head.edition = s0[7];
    for (std::size_t b = 8; b < 16; ++b) head.total_length = (head.total_length << 8) | s0[b];
    if (head.edition != 2) {
      throw InputError(fmt::format("{}: message {} at byte {} is GRIB edition {}, expected edition 2 (GRIB2)", path,
                                   number, pos, head.edition));
    }
    if (head.total_length < 16 + 4 || pos + head.total_length > file_size) {
      throw InputError(fmt::format("{}: message {} at byte {} is truncated: Section 0 declares {} bytes, the file "
                                   "holds {} from there",
                                   path, number, pos, head.total_length, file_size - pos));
    }
    std::array<char, 4> end{};
    (void)std::fseek(f.get(), long(pos + head.total_length - 4), SEEK_SET);
    if (std::fread(end.data(), 1, 4, f.get()) != 4 || std::string(end.data(), 4) != "7777") {
      throw InputError(fmt::format("{}: message {} at byte {} does not end in \"7777\" after its declared {} bytes, "
                                   "expected a complete GRIB2 message",
                                   path, number, pos, head.total_length));
    }
    offsets.push_back(std::int64_t(pos));
    pos += head.total_length;
  }

  std::vector<Grib2Message> messages;
  for (std::size_t n = 0; n < offsets.size(); ++n) {
    HandlePtr h = handleAt(f.get(), path, n + 1, offsets[n]);
    Grib2Message m;
    m.file = path;
    m.number = n + 1;
    m.offset = offsets[n];
    m.short_name = getString(h.get(), "shortName");
    m.discipline = getLong(h.get(), "discipline", -1);
    m.category = getLong(h.get(), "parameterCategory", -1);
    m.parameter = getLong(h.get(), "parameterNumber", -1);
    m.level_type = getLong(h.get(), "typeOfFirstFixedSurface", -1);
    m.level = getLong(h.get(), "level", -1);
    m.valid_time_utc = isoFromValidity(getLong(h.get(), "validityDate", 0), getLong(h.get(), "validityTime", 0));
    m.packing = getString(h.get(), "packingType");
    m.data_template = getLong(h.get(), "dataRepresentationTemplateNumber", -1);
    m.bits_per_value = getLong(h.get(), "bitsPerValue", 0);
    Grib2Grid& g = m.grid;
    g.type = getString(h.get(), "gridType");
    g.points = std::size_t(std::max(getLong(h.get(), "numberOfDataPoints", 0), 0L));
    if (g.type == "regular_ll") {
      g.ni = getLong(h.get(), "Ni", 0);
      g.nj = getLong(h.get(), "Nj", 0);
      g.lat_first_deg = getDouble(h.get(), "latitudeOfFirstGridPointInDegrees", 0);
      g.lon_first_deg = getDouble(h.get(), "longitudeOfFirstGridPointInDegrees", 0);
      g.di_deg = getDouble(h.get(), "iDirectionIncrementInDegrees", 0);
      g.dj_deg = getDouble(h.get(), "jDirectionIncrementInDegrees", 0);
      g.i_scans_negatively = getLong(h.get(), "iScansNegatively", 0) != 0;
      g.j_scans_positively = getLong(h.get(), "jScansPositively", 0) != 0;
      g.j_points_consecutive = getLong(h.get(), "jPointsAreConsecutive", 0) != 0;
    } else if (g.type == "unstructured_grid") {
      g.uuid = uuidOf(h.get());
      g.grid_number = getLong(h.get(), "numberOfGridUsed", 0);
      g.grid_in_reference = getLong(h.get(), "numberOfGridInReference", 0);
    }
    messages.push_back(std::move(m));
  }
  return messages;
}

std::vector<double> readGrib2Values(const Grib2Message& message, std::size_t& missing_points) {
  routeEccodesLog();
  const auto& packings = supportedGrib2Packings();
  if (std::find(packings.begin(), packings.end(), message.packing) == packings.end()) {
    throw InputError(fmt::format("{}: packing \"{}\" (data representation template 5.{}) is not supported, "
                                 "expected grid-point data packed as one of {}",
                                 message.where(), message.packing.empty() ? "unknown" : message.packing,
                                 message.data_template, fmt::join(packings, ", ")));
  }
  FilePtr f = openFile(message.file);
  HandlePtr h = handleAt(f.get(), message.file, message.number, message.offset);
  std::size_t size = 0;
  int err = codes_get_size(h.get(), "values", &size);
  if (err == CODES_SUCCESS && size != message.grid.points) {
    throw InputError(fmt::format("{}: holds {} values, expected numberOfDataPoints = {}", message.where(), size,
                                 message.grid.points));
  }
  std::vector<double> values(size);
  if (err == CODES_SUCCESS) err = codes_get_double_array(h.get(), "values", values.data(), &size);
  if (err != CODES_SUCCESS) {
    throw InputError(fmt::format("{}: its {} data ({} bits per value) cannot be decoded by ecCodes ({}), expected a "
                                 "packing this ecCodes build decodes",
                                 message.where(), message.packing, message.bits_per_value,
                                 codes_get_error_message(err)));
  }
  missing_points = 0;
  if (getLong(h.get(), "bitmapPresent", 0) != 0) {
    const double missing = getDouble(h.get(), "missingValue", CODES_MISSING_DOUBLE);
    for (double& v : values) {
      if (v == missing) {
        v = std::numeric_limits<double>::quiet_NaN();
        ++missing_points;
      }
    }
  }
  return values;
}

}  // namespace nph::io

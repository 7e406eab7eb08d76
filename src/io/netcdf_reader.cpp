#include "netcdf_reader.h"

#include <fmt/format.h>
#include <netcdf.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>

#include "classic_header.h"
#include "core/env.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/large_buffer.h"
#include "core/limits.h"
#include "core/log.h"
#include "core/process.h"
#include "load_options.h"

namespace nph::io {

std::size_t memoryBudgetBytes(const LoadOptions& options) {
  if (options.memory_budget_bytes != 0) return options.memory_budget_bytes;
  // Strict: garbage or a value whose bytes overflow is an error, not a silent default or 0.
  return static_cast<std::size_t>(limits::memoryBudgetBytesFromEnv());
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out;
}

namespace {

/// libhdf5 (1.10.8 in Debian 12) can free an invalid pointer — memory corruption, a crash under
/// AddressSanitizer and undefined behaviour without it — while NetCDF-C opens a damaged netCDF-4
/// file (found by the fuzz campaign, `fuzz.run.model`; the input is
/// tests/fuzz/corpus/model/hdf5-invalid-free-on-open). No check of ours can run before the
/// library's own parsing of the HDF5 metadata, so a file with the HDF5 signature is first opened
/// by a separate process, nephele-nc-probe (nc_probe_main.cpp: nc_open, nc_inq, nc_close), started
/// with posix_spawn; this process opens it only when the probe opened it. A file the probe's
/// nc_open refused is reported with the probe's NetCDF error and never opened here: the invalid
/// free is on that error path, and whether it crashes depends on the heap (the fresh probe got a
/// clean NC_EHDFERR where this process crashed). A crashed probe becomes an InputError naming the
/// file. A probe that has not finished after
/// NEPHELE_HDF5_OPEN_TIMEOUT_S seconds (default 300: a metadata parse takes milliseconds, a damaged
/// file can make libhdf5 loop forever) is killed and the file refused (process::runWithin: no
/// clock, no polling). Until session 11 the probe was a fork() of this process: in a
/// multithreaded process (llvmpipe, plugin hosts) the child inherited locks held by other threads
/// and ran PROJ's atfork handler, and deadlocked under ASan (core/process.h). The probe executable
/// is NEPHELE_NC_PROBE when set (an absolute path), else the build tree's, else the install
/// prefix's; when none exists the file is opened here, as before the guard, with a warning.
/// The InputError for a NetCDF-C open that failed with `status`.
[[noreturn]] void throwOpenFailure(const std::string& path, int status) {
  if (status == NC_ENOTNC) {
    throw InputError(
        fmt::format("{}: not a NetCDF file (expected NetCDF classic, 64-bit offset or NetCDF-4/HDF5)", path));
  }
  throw InputError(fmt::format("{}: cannot be opened as NetCDF ({}); the file may be truncated or damaged", path,
                               nc_strerror(status)));
}

std::optional<std::string> ncProbeExecutable() {
  if (env::get("NEPHELE_NC_PROBE")) return process::toolPath("NEPHELE_NC_PROBE", "nephele-nc-probe");
  for (const char* candidate : {NEPHELE_NC_PROBE_BUILD, NEPHELE_NC_PROBE_INSTALL}) {
    if (::access(candidate, X_OK) == 0) return std::string(candidate);
  }
  return std::nullopt;
}

void probeHdf5Open(const std::string& path) {
  static constexpr unsigned char kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  unsigned char head[8] = {};
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    const std::size_t n = std::fread(head, 1, sizeof head, f);
    std::fclose(f);
    if (n != sizeof head || std::memcmp(head, kHdf5Signature, sizeof head) != 0) return;
  } else {
    return;  // nc_open reports it
  }
  constexpr int kOpened = 0, kRefusedBase = 64;                             // nc_probe_main.cpp
  const std::uint64_t timeout_s = limits::hdf5OpenTimeoutSecondsFromEnv();  // UsageError before starting it
  const std::optional<std::string> probe = ncProbeExecutable();
  if (!probe) {
    static std::once_flag warned;
    std::call_once(warned, [] {
      log::warn("nephele-nc-probe was not found ({} or {}; NEPHELE_NC_PROBE sets it): netCDF-4 files are opened "
                "without the separate-process guard against libhdf5 crashes",
                NEPHELE_NC_PROBE_BUILD, NEPHELE_NC_PROBE_INSTALL);
    });
    return;
  }
  const std::optional<process::Ending> end = process::runWithin({*probe, path}, timeout_s);
  if (!end) return;  // no process to spare: open it here, as before the guard
  using How = process::Ending::How;
  if (end->how == How::TimedOut) {
    throw InputError(fmt::format("{}: the HDF5 library did not finish reading this NetCDF-4 file's metadata in {} s "
                                 "(in a separate process nephele opens such files in first): the file is damaged, or "
                                 "raise NEPHELE_HDF5_OPEN_TIMEOUT_S",
                                 path, timeout_s));
  }
  if (end->how == How::Exited && end->code == kOpened) return;
  if (end->how == How::Exited && end->code > kRefusedBase) throwOpenFailure(path, -(end->code - kRefusedBase));
  const std::string how =
      end->how == How::Signalled ? fmt::format("signal {}", end->code) : fmt::format("exit status {}", end->code);
  throw InputError(fmt::format("{}: the HDF5 library crashed reading this NetCDF-4 file's metadata ({} in a separate "
                               "process nephele opens such files in first): the file is damaged",
                               path, how));
}

}  // namespace

NcReader::NcReader(std::string path) : path_(std::move(path)) {
  requireRegularFile(path_, "a NetCDF file");
  probeHdf5Open(path_);
  const int status = nc_open(path_.c_str(), NC_NOWRITE, &ncid_);
  if (status != NC_NOERR) {
    ncid_ = -1;
    throwOpenFailure(path_, status);
  }
  checkClassicFileSize();
}

void NcReader::checkClassicFileSize() {
  // NetCDF-C opens a truncated classic (CDF-1/2/5) file and reads zeros past its end without an
  // error: compare the file size with the exact end of the data its header declares
  // (classic_header.h). NetCDF-4/HDF5 files fail to open when truncated (but see
  // requireStoredData for variables declared and never written).
  if (nc_inq_format(ncid_, &format_) != NC_NOERR) return;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path_, ec);
  if (ec) return;
  file_bytes_ = size;
  if (format_ != NC_FORMAT_CLASSIC && format_ != NC_FORMAT_64BIT_OFFSET && format_ != NC_FORMAT_CDF5) return;
  const auto declared = classicDataEnd_bytes(path_);
  if (declared && size < *declared) {
    throw InputError(fmt::format("{}: truncated NetCDF file: {} bytes, but its header declares data up to byte {} "
                                 "({} bytes missing)",
                                 path_, size, *declared, *declared - size));
  }
}

void NcReader::requireStoredData(const std::string& var, int id) const {
  // A NetCDF-4 file may declare gigabytes it never wrote: HDF5 then makes up fill values (a 16 KB
  // file declaring 2000 x 2000 x 55 grew to 2.7 GB over 162 s). One variable cannot hold more
  // than any compression of the whole file could store.
  if (format_ != NC_FORMAT_NETCDF4 && format_ != NC_FORMAT_NETCDF4_CLASSIC) return;
  nc_type type = NC_NAT;
  nc_inq_vartype(ncid_, id, &type);
  std::size_t type_size = 0;
  nc_inq_type(ncid_, type, nullptr, &type_size);
  double declared = double(type_size);
  for (const std::size_t len : varShape(var)) declared *= double(len);
  if (declared > kMaxCompressionRatio * double(std::max<std::uintmax_t>(file_bytes_, 1))) {
    throw InputError(fmt::format("{}: {} declares {:.0f} bytes in a NetCDF-4 file of {} bytes, more than {:.0f}x its "
                                 "size: its data were never written (deflate cannot pass ~1032x)",
                                 path_, var, declared, file_bytes_, kMaxCompressionRatio));
  }
}

NcReader::~NcReader() {
  if (ncid_ >= 0) nc_close(ncid_);
}

void NcReader::fail(const std::string& what) const { throw InputError(fmt::format("{}: {}", path_, what)); }

int NcReader::varId(const std::string& name) const {
  int id = -1;
  if (nc_inq_varid(ncid_, name.c_str(), &id) != NC_NOERR) fail(fmt::format("variable {} is missing", name));
  return id;
}

bool NcReader::hasVar(const std::string& name) const {
  int id = -1;
  return nc_inq_varid(ncid_, name.c_str(), &id) == NC_NOERR;
}

bool NcReader::hasDim(const std::string& name) const { return dimLength(name).has_value(); }

std::optional<std::size_t> NcReader::dimLength(const std::string& name) const {
  int id = -1;
  if (nc_inq_dimid(ncid_, name.c_str(), &id) != NC_NOERR) return std::nullopt;
  std::size_t len = 0;
  if (nc_inq_dimlen(ncid_, id, &len) != NC_NOERR) fail(fmt::format("cannot read the length of dimension {}", name));
  return len;
}

std::optional<std::string> NcReader::firstVar(std::initializer_list<const char*> names) const {
  for (const char* n : names) {
    if (hasVar(n)) return std::string(n);
  }
  return std::nullopt;
}

std::vector<std::string> NcReader::varDimNames(const std::string& name) const {
  const int id = varId(name);
  int ndims = 0;
  nc_inq_varndims(ncid_, id, &ndims);
  std::vector<int> dimids(static_cast<std::size_t>(ndims));
  if (ndims > 0) nc_inq_vardimid(ncid_, id, dimids.data());
  std::vector<std::string> names;
  for (int d : dimids) {
    char buf[NC_MAX_NAME + 1] = {};
    nc_inq_dimname(ncid_, d, buf);
    names.emplace_back(buf);
  }
  return names;
}

std::vector<std::size_t> NcReader::varShape(const std::string& name) const {
  const int id = varId(name);
  int ndims = 0;
  nc_inq_varndims(ncid_, id, &ndims);
  std::vector<int> dimids(static_cast<std::size_t>(ndims));
  if (ndims > 0) nc_inq_vardimid(ncid_, id, dimids.data());
  std::vector<std::size_t> shape;
  for (int d : dimids) {
    std::size_t len = 0;
    nc_inq_dimlen(ncid_, d, &len);
    shape.push_back(len);
  }
  return shape;
}

void NcReader::requireDims(const std::string& var, const std::vector<std::string>& expected) const {
  if (!hasVar(var)) fail(fmt::format("variable {} is missing, expected ({})", var, joinNames(expected)));
  const auto names = varDimNames(var);
  if (names.size() != expected.size()) {
    fail(fmt::format("{} has {} dims, expected {} ({})", var, names.size(), expected.size(), joinNames(expected)));
  }
  if (names != expected)
    fail(fmt::format("{} has dims ({}), expected ({})", var, joinNames(names), joinNames(expected)));
}

void NcReader::requireNumeric(const std::string& var) const {
  nc_type type = NC_NAT;
  nc_inq_vartype(ncid_, varId(var), &type);
  if (type == NC_CHAR || type == NC_STRING || type > NC_STRING) {
    fail(fmt::format("{} has a non-numeric type, expected float or double", var));
  }
}

std::optional<double> NcReader::globalNumber(const std::string& name) const {
  nc_type type = NC_NAT;
  std::size_t len = 0;
  if (nc_inq_att(ncid_, NC_GLOBAL, name.c_str(), &type, &len) != NC_NOERR) return std::nullopt;
  if (type == NC_CHAR || type == NC_STRING || len < 1) fail(fmt::format("global attribute {} is not a number", name));
  std::vector<double> v(len);
  if (nc_get_att_double(ncid_, NC_GLOBAL, name.c_str(), v.data()) != NC_NOERR) {
    fail(fmt::format("global attribute {} cannot be read as a number", name));
  }
  return v[0];
}

static std::optional<std::string> textAtt(int ncid, int varid, const std::string& name) {
  nc_type type = NC_NAT;
  std::size_t len = 0;
  if (nc_inq_att(ncid, varid, name.c_str(), &type, &len) != NC_NOERR || type != NC_CHAR) return std::nullopt;
  std::string s(len, '\0');
  if (len > 0 && nc_get_att_text(ncid, varid, name.c_str(), s.data()) != NC_NOERR) return std::nullopt;
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::optional<std::string> NcReader::globalText(const std::string& name) const {
  return textAtt(ncid_, NC_GLOBAL, name);
}

std::optional<std::string> NcReader::varText(const std::string& var, const std::string& att) const {
  if (!hasVar(var)) return std::nullopt;
  return textAtt(ncid_, varId(var), att);
}

bool NcReader::packingAttribute(const std::string& var, int id, const char* name, double& value) const {
  nc_type type = NC_NAT;
  std::size_t len = 0;
  if (nc_inq_att(ncid_, id, name, &type, &len) != NC_NOERR) return false;
  // CF conventions §8.1: scale_factor and add_offset are single numbers of the unpacked type. A
  // char "scale_factor" was ignored before, and packed shorts read as 1.8e4 kg/kg.
  if (type == NC_CHAR || type == NC_STRING || type > NC_STRING || len != 1) {
    fail(fmt::format("{}:{} is {}, expected one number (CF packing attribute)", var, name,
                     type == NC_CHAR || type == NC_STRING ? "text" : fmt::format("{} values", len)));
  }
  if (nc_get_att_double(ncid_, id, name, &value) != NC_NOERR || !std::isfinite(value)) {
    fail(fmt::format("{}:{} cannot be read as a finite number", var, name));
  }
  return true;
}

void NcReader::requireFloatingOrPacked(const std::string& var) const {
  requireNumeric(var);
  const int id = varId(var);
  nc_type type = NC_NAT;
  nc_inq_vartype(ncid_, id, &type);
  if (type == NC_FLOAT || type == NC_DOUBLE) return;
  nc_type at = NC_NAT;
  std::size_t len = 0;
  if (nc_inq_att(ncid_, id, "scale_factor", &at, &len) == NC_NOERR) return;  // packed (CF §8.1)
  fail(fmt::format("{} is an integer variable without scale_factor, expected float or double mixing ratios "
                   "[kg/kg] (or CF-packed integers with scale_factor)",
                   var));
}

std::vector<float> NcReader::readFloats(const std::string& var, const std::vector<std::size_t>& start,
                                        const std::vector<std::size_t>& count, float fill_replacement,
                                        ReadStats& stats) const {
  const int id = varId(var);
  requireNumeric(var);
  requireStoredData(var, id);
  std::size_t n = 1;
  for (std::size_t c : count) n *= c;
  // Huge pages for the model fields (core/large_buffer.h): 512× fewer page faults on first touch.
  std::vector<float> data = hugePageFloats(n);
  if (n == 0) return data;
  const int status = nc_get_vara_float(ncid_, id, start.data(), count.data(), data.data());
  if (status != NC_NOERR && status != NC_ERANGE) {
    fail(fmt::format("cannot read {} ({}); the file may be truncated or damaged", var, nc_strerror(status)));
  }
  // Missing-value markers, compared on the raw (packed) values: _FillValue, missing_value, and
  // NetCDF's default fill for never-written data (ncdump shows these as "_").
  nc_type type = NC_NAT;
  nc_inq_vartype(ncid_, id, &type);
  std::vector<float> markers;
  for (const char* att : {"_FillValue", "missing_value"}) {
    nc_type at = NC_NAT;
    std::size_t len = 0;
    if (nc_inq_att(ncid_, id, att, &at, &len) == NC_NOERR && len >= 1 && at != NC_CHAR) {
      std::vector<double> v(len);
      nc_get_att_double(ncid_, id, att, v.data());
      for (double m : v) markers.push_back(static_cast<float>(m));
    }
  }
  if (type == NC_FLOAT || type == NC_DOUBLE) markers.push_back(NC_FILL_FLOAT);
  double scale = 1.0, offset = 0.0;
  const bool has_scale = packingAttribute(var, id, "scale_factor", scale);
  const bool has_offset = packingAttribute(var, id, "add_offset", offset);
  const bool nan_marker = std::any_of(markers.begin(), markers.end(), [](float m) { return std::isnan(m); });
  markers.erase(std::remove_if(markers.begin(), markers.end(), [](float m) { return std::isnan(m); }), markers.end());
  const bool scaled = has_scale || has_offset;
  if (!nan_marker && !scaled && !markers.empty() && markers.size() <= 3) {
    // Common case, branch-free so that it vectorises: up to three markers, no packing.
    const float a = markers[0], b = markers[std::min<std::size_t>(1, markers.size() - 1)],
                c = markers[markers.size() - 1];
    std::int64_t missing = 0;
    for (float& v : data) {
      const bool miss = (v == a) | (v == b) | (v == c);
      missing += miss;
      v = miss ? fill_replacement : v;
    }
    stats.fill_values += missing;
    return data;
  }
  for (float& v : data) {
    bool missing = nan_marker && std::isnan(v);
    for (float m : markers) missing |= v == m;
    if (missing) {
      v = fill_replacement;
      ++stats.fill_values;
    } else if (scaled) {
      v = static_cast<float>(double(v) * scale + offset);
    }
  }
  return data;
}

std::vector<double> NcReader::readDoubles(const std::string& var) const {
  const int id = varId(var);
  requireNumeric(var);
  requireStoredData(var, id);
  std::size_t n = 1;
  for (std::size_t c : varShape(var)) n *= c;
  std::vector<double> data(n);
  if (n > 0) {
    const int status = nc_get_var_double(ncid_, id, data.data());
    if (status != NC_NOERR) fail(fmt::format("cannot read {} ({})", var, nc_strerror(status)));
  }
  return data;
}

std::string NcReader::readTextRow(const std::string& var, std::size_t index) const {
  const int id = varId(var);
  nc_type type = NC_NAT;
  nc_inq_vartype(ncid_, id, &type);
  auto shape = varShape(var);
  // (Time, DateStrLen), or (DateStrLen) in a single-timestep file without Time (index 0 only).
  if (shape.size() == 1 && index == 0) shape.insert(shape.begin(), 1);
  if (type != NC_CHAR || shape.size() != 2)
    fail(fmt::format("{} is not a 2-D char variable, expected (Time, DateStrLen)", var));
  std::string s(shape[1], '\0');
  const std::size_t start[2] = {index, 0};
  const std::size_t count[2] = {1, shape[1]};
  const bool timed = varShape(var).size() == 2;
  if (shape[1] > 0 && (timed ? nc_get_vara_text(ncid_, id, start, count, s.data())
                             : nc_get_vara_text(ncid_, id, start + 1, count + 1, s.data())) != NC_NOERR) {
    fail(fmt::format("cannot read row {} of {}", index, var));
  }
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

}  // namespace nph::io

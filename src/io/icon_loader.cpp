#include "icon_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/limits.h"
#include "core/log.h"
#include "field_checks.h"
#include "geo/utc_time.h"
#include "icon_fields.h"
#include "netcdf_reader.h"

namespace nph::io {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// Dimension names accepted for each axis (ICON output, cdo, CF).
const std::vector<std::string> kLonNames = {"lon", "longitude", "x"};
const std::vector<std::string> kLatNames = {"lat", "latitude", "y"};
bool isOneOf(const std::string& s, const std::vector<std::string>& names) {
  return std::find(names.begin(), names.end(), s) != names.end();
}

struct IconClass {
  Hydrometeor kind;
  std::initializer_list<const char*> names;
};

/// Layout of one ICON file as the loader understands it.
struct IconLayout {
  bool native = false;
  std::string temp, pres, heights;  // variable names
  bool heights_are_half_levels = true;
  std::string lon_dim, lat_dim, cell_dim;
  std::size_t nlon = 0, nlat = 0, ncells = 0, nz = 0, nt = 0;
  bool has_time = false;
};

std::string need(const NcReader& nc, std::initializer_list<const char*> names, const char* meaning) {
  if (auto v = nc.firstVar(names)) return *v;
  std::vector<std::string> list(names.begin(), names.end());
  throw InputError(
      fmt::format("{}: variable {} is missing, expected {} ({})", nc.path(), *names.begin(), meaning, joinNames(list)));
}

IconLayout iconLayout(const NcReader& nc) {
  IconLayout l;
  l.temp = need(nc, {"temp", "t", "T"}, "air temperature [K]");
  l.pres = need(nc, {"pres", "p", "P"}, "air pressure [Pa]");
  const auto dims = nc.varDimNames(l.temp);
  const auto shape = nc.varShape(l.temp);
  l.native = nc.hasDim("ncells") || nc.hasVar("clon");
  const std::size_t horiz = l.native ? 1 : 2;
  if (dims.size() != horiz + 2 && dims.size() != horiz + 1) {
    throw InputError(fmt::format("{}: {} has {} dims, expected {} ({})", nc.path(), l.temp, dims.size(), horiz + 2,
                                 l.native ? "time, height, ncells" : "time, height, lat, lon"));
  }
  l.has_time = dims.size() == horiz + 2;
  if (l.has_time && dims[0] != "time") {
    throw InputError(fmt::format("{}: {} has dims ({}), expected time first", nc.path(), l.temp, joinNames(dims)));
  }
  const std::size_t zi = l.has_time ? 1 : 0;
  l.nz = shape[zi];
  l.nt = l.has_time ? shape[0] : 1;
  if (l.native) {
    l.cell_dim = dims[zi + 1];
    l.ncells = shape[zi + 1];
  } else {
    l.lat_dim = dims[zi + 1];
    l.lon_dim = dims[zi + 2];
    l.nlat = shape[zi + 1];
    l.nlon = shape[zi + 2];
    if (!isOneOf(l.lat_dim, kLatNames) || !isOneOf(l.lon_dim, kLonNames)) {
      throw InputError(
          fmt::format("{}: {} has dims ({}), expected (time, height, lat, lon)", nc.path(), l.temp, joinNames(dims)));
    }
  }
  for (auto [name, len] : {std::pair<const char*, std::size_t>{"height", l.nz}, {"lat", l.nlat}, {"lon", l.nlon}}) {
    if (!l.native || std::string(name) == "height") {
      if (len == 0)
        throw InputError(
            fmt::format("{}: {} has a zero-length {} dimension, expected at least 1", nc.path(), l.temp, name));
    }
  }
  if (l.native && l.ncells == 0)
    throw InputError(fmt::format("{}: dimension {} has length 0, expected cells", nc.path(), l.cell_dim));
  if (l.has_time && l.nt == 0)
    throw InputError(fmt::format("{}: dimension time has length 0, expected at least one timestep", nc.path()));
  if (auto h = nc.firstVar({"z_ifc", "HHL", "hhl"})) {
    l.heights = *h;
  } else if (auto m = nc.firstVar({"z_mc", "z_mg"})) {
    l.heights = *m;
    l.heights_are_half_levels = false;
  } else {
    throw InputError(fmt::format("{}: variable z_ifc is missing, expected half-level heights (z_ifc or HHL, height_2 = "
                                 "height + 1 levels) or full-level heights (z_mc/z_mg)",
                                 nc.path()));
  }
  return l;
}

/// Reads one 3-D field (levels x horizontal) of timestep t; accepts (time, z, ...) or (z, ...).
std::vector<float> readLevels(const NcReader& nc, const IconLayout& l, const std::string& var, std::size_t t,
                              std::size_t levels, float fill, ReadStats& stats) {
  const auto dims = nc.varDimNames(var);
  const auto shape = nc.varShape(var);
  const std::size_t horiz = l.native ? 1 : 2;
  const bool timed = dims.size() == horiz + 2;
  if (dims.size() != horiz + 2 && dims.size() != horiz + 1) {
    throw InputError(fmt::format("{}: {} has {} dims, expected {} ({})", nc.path(), var, dims.size(), horiz + 2,
                                 l.native ? "time, height, ncells" : "time, height, lat, lon"));
  }
  if (!timed && dims[0] == "time") {
    throw InputError(fmt::format("{}: {} has {} dims ({}), expected {} ({})", nc.path(), var, dims.size(),
                                 joinNames(dims), horiz + 2,
                                 l.native ? "time, height, ncells" : "time, height, lat, lon"));
  }
  const std::size_t zi = timed ? 1 : 0;
  if (timed && dims[0] != "time")
    throw InputError(fmt::format("{}: {} has dims ({}), expected time first", nc.path(), var, joinNames(dims)));
  const bool horizontal_ok =
      l.native ? (dims[zi + 1] == l.cell_dim) : (dims[zi + 1] == l.lat_dim && dims[zi + 2] == l.lon_dim);
  if (!horizontal_ok || shape[zi] != levels) {
    throw InputError(fmt::format("{}: {} has dims ({}) of shape ({}), expected {} levels on ({})", nc.path(), var,
                                 joinNames(dims), fmt::join(shape, ", "), levels,
                                 l.native ? l.cell_dim : l.lat_dim + ", " + l.lon_dim));
  }
  std::vector<std::size_t> start, count;
  if (timed) {
    start.push_back(std::min(t, shape[0] - 1));  // time-constant fields may have a length-1 time
    count.push_back(1);
  }
  start.push_back(0);
  count.push_back(levels);
  for (std::size_t h = zi + 1; h < shape.size(); ++h) {
    start.push_back(0);
    count.push_back(shape[h]);
  }
  auto data = nc.readFloats(var, start, count, fill, stats);
  requireFinite(nc.path(), var, data);
  return data;
}

}  // namespace

geo::OptionalUtcTime timeFromValue(double value, const std::string& units) {
  if (!std::isfinite(value)) return std::nullopt;
  if (units.rfind("day as %Y%m%d", 0) == 0) {
    const auto ymd = static_cast<std::int64_t>(std::floor(value));
    const double frac = value - double(ymd);
    const std::int64_t y = ymd / 10000, m = (ymd / 100) % 100, d = ymd % 100;
    if (m < 1 || m > 12 || d < 1 || d > geo::daysInMonth(int(y), int(m))) return std::nullopt;
    return geo::UtcTime::fromCivil(int(y), int(m), int(d)).plusSeconds(double(std::llround(frac * 86400.0)));
  }
  const auto since = units.find(" since ");
  if (since == std::string::npos) return std::nullopt;
  const std::string unit = units.substr(0, since);
  const double factor = unit == "seconds" || unit == "second" || unit == "s" ? 1.0
                        : unit == "minutes" || unit == "minute"              ? 60.0
                        : unit == "hours" || unit == "hour" || unit == "h"   ? 3600.0
                        : unit == "days" || unit == "day" || unit == "d"     ? 86400.0
                                                                             : 0.0;
  if (factor == 0.0) return std::nullopt;
  int y = 0, mo = 0, d = 0, hh = 0, mi = 0, ss = 0;
  const std::string ref = units.substr(since + 7);
  const int got = std::sscanf(ref.c_str(), "%d-%d-%d%*[ T]%d:%d:%d", &y, &mo, &d, &hh, &mi, &ss);
  if (got < 3 || mo < 1 || mo > 12 || d < 1 || d > geo::daysInMonth(y, mo)) return std::nullopt;
  const double base_s = double(std::int64_t(hh) * 3600 + std::int64_t(mi) * 60 + ss);
  return geo::UtcTime::fromCivil(y, mo, d).plusSeconds(base_s + double(std::llround(value * factor)));
}

std::vector<geo::OptionalUtcTime> listIconTimes(const std::string& path) {
  const NcReader nc(path);
  const IconLayout l = iconLayout(nc);
  std::vector<geo::OptionalUtcTime> times(l.nt);
  if (l.has_time && nc.hasVar("time")) {
    const auto values = nc.readDoubles("time");
    const std::string units = nc.varText("time", "units").value_or("");
    for (std::size_t t = 0; t < l.nt && t < values.size(); ++t) times[t] = timeFromValue(values[t], units);
  }
  return times;
}

ModelTimestep loadIconTimestep(const std::string& path, std::int64_t time_index, const LoadOptions& options) {
  const NcReader nc(path);
  const IconLayout l = iconLayout(nc);
  if (time_index < 0 || std::size_t(time_index) >= l.nt) {
    throw InputError(fmt::format("{}: timestep {} does not exist, expected 0 .. {}", path, time_index, l.nt - 1));
  }
  const std::size_t t = std::size_t(time_index);
  const std::size_t nz = l.nz;
  const std::size_t nsrc = l.native ? l.ncells : l.nlat * l.nlon;
  // Source fields held at once: up to 7 condensate/state fields + heights (nz + 1) + clc.
  requireWithinBudget(path, "one timestep", double(nsrc) * double(nz + 1), 12, memoryBudgetBytes(options));

  static const std::array<IconClass, 6> kClasses = {{{Hydrometeor::Cloud, {"qc", "QC", "clwmr"}},
                                                     {Hydrometeor::Ice, {"qi", "QI"}},
                                                     {Hydrometeor::Rain, {"qr", "QR"}},
                                                     {Hydrometeor::Snow, {"qs", "QS"}},
                                                     {Hydrometeor::Graupel, {"qg", "QG"}},
                                                     {Hydrometeor::Hail, {"qh", "QH"}}}};
  IconSourceFields src;  // on source points (flat), levels in file order
  src.path = path;
  src.time_index = time_index;
  src.nz = nz;
  src.npoints = nsrc;
  src.native = l.native;
  ReadStats cond_stats;
  for (const IconClass& c : kClasses) {
    if (auto name = nc.firstVar(c.names)) {
      nc.requireFloatingOrPacked(*name);
      auto data = readLevels(nc, l, *name, t, nz, 0.0f, cond_stats);
      checkIconField(path, *name, IconQuantity::Condensate, data, src.repairs);
      src.q_kg_per_kg[c.kind] = std::move(data);
    }
  }
  if (src.q_kg_per_kg.empty()) {
    throw InputError(
        fmt::format("{}: no condensate variable, expected at least one of qc, qi, qr, qs, qg (time, height, "
                    "{})",
                    path, l.native ? "ncells" : "lat, lon"));
  }
  auto read_state = [&](const std::string& var, std::size_t levels, IconQuantity quantity) {
    ReadStats s;
    auto data = readLevels(nc, l, var, t, levels, std::numeric_limits<float>::quiet_NaN(), s);
    if (s.fill_values > 0) {
      throw InputError(fmt::format("{}: {} has {} missing values (_FillValue/missing_value), expected a complete field",
                                   path, var, s.fill_values));
    }
    checkIconField(path, var, quantity, data, src.repairs);
    return data;
  };
  src.temperature_k = read_state(l.temp, nz, IconQuantity::Temperature);
  src.pressure_pa = read_state(l.pres, nz, IconQuantity::Pressure);
  if (auto qv = nc.firstVar({"qv", "QV"})) {
    nc.requireFloatingOrPacked(*qv);
    src.water_vapour_kg_per_kg = readLevels(nc, l, *qv, t, nz, 0.0f, cond_stats);
    checkIconField(path, *qv, IconQuantity::SpecificHumidity, src.water_vapour_kg_per_kg, src.repairs);
  } else {
    log::warn("{}: qv is missing; specific humidity taken as 0", path);
    src.water_vapour_kg_per_kg.assign(nz * nsrc, 0.0f);
  }
  if (auto clc = nc.firstVar({"clc", "CLC", "ccl"})) {
    src.cloud_cover_fraction = readLevels(nc, l, *clc, t, nz, 0.0f, cond_stats);
    const std::string units = nc.varText(*clc, "units").value_or("%");
    checkIconField(path, *clc, IconQuantity::CloudCoverPercent, src.cloud_cover_fraction, src.repairs,
                   !(units == "%" || units == "percent"));
  }
  src.repairs.missing_as_zero = cond_stats.fill_values;
  src.heights_are_half_levels = l.heights_are_half_levels;
  src.heights_name = l.heights;
  src.heights_m = read_state(l.heights, l.heights_are_half_levels ? nz + 1 : nz, IconQuantity::Height);
  if (l.has_time && nc.hasVar("time")) {
    const auto values = nc.readDoubles("time");
    if (t < values.size()) src.time_utc = timeFromValue(values[t], nc.varText("time", "units").value_or(""));
  }

  if (!l.native) {
    src.lon_name = nc.hasVar(l.lon_dim) ? l.lon_dim : need(nc, {"lon", "longitude"}, "longitudes [deg]");
    src.lat_name = nc.hasVar(l.lat_dim) ? l.lat_dim : need(nc, {"lat", "latitude"}, "latitudes [deg]");
    src.lon_deg = nc.readDoubles(src.lon_name);
    src.lat_deg = nc.readDoubles(src.lat_name);
    if (src.lon_deg.size() != l.nlon || src.lat_deg.size() != l.nlat) {
      throw InputError(fmt::format("{}: {}/{} have {}/{} values, expected {}/{}", path, src.lon_name, src.lat_name,
                                   src.lon_deg.size(), src.lat_deg.size(), l.nlon, l.nlat));
    }
  } else {
    src.lon_name = need(nc, {"clon"}, "cell centre longitudes [radian]");
    src.lat_name = need(nc, {"clat"}, "cell centre latitudes [radian]");
    src.lon_deg = nc.readDoubles(src.lon_name);
    src.lat_deg = nc.readDoubles(src.lat_name);
    if (nc.varText(src.lon_name, "units").value_or("radian").rfind("rad", 0) == 0) {
      for (double& v : src.lon_deg) v *= kDegPerRad;
      for (double& v : src.lat_deg) v *= kDegPerRad;
    }
  }
  return assembleIconTimestep(std::move(src), options);
}

}  // namespace nph::io

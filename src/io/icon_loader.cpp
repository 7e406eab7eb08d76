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

/// Resampling of the native grid: nearest cell centre, found with a uniform bucket grid in
/// (lon cos(lat_mid), lat), so the search is O(1) per target point rather than O(ncells).
/// Nearest-cell (rather than barycentric) keeps each cell's values intact: cloud cover and
/// condensate of one cell stay together (the ICON corrections compare them cell by cell) and no
/// new extrema or mixed cloud edges appear; the price is blocky edges at the cell scale.
class CellLocator {
 public:
  CellLocator(const std::vector<double>& lon_deg, const std::vector<double>& lat_deg, double cos_mid, double bucket_deg)
      : lon_(lon_deg), lat_(lat_deg), cos_(cos_mid), bucket_(bucket_deg) {
    min_x_ = std::numeric_limits<double>::max();
    min_y_ = std::numeric_limits<double>::max();
    double max_x = -min_x_, max_y = -min_y_;
    for (std::size_t c = 0; c < lon_.size(); ++c) {
      min_x_ = std::min(min_x_, lon_[c] * cos_);
      max_x = std::max(max_x, lon_[c] * cos_);
      min_y_ = std::min(min_y_, lat_[c]);
      max_y = std::max(max_y, lat_[c]);
    }
    nbx_ = static_cast<int>((max_x - min_x_) / bucket_) + 1;
    nby_ = static_cast<int>((max_y - min_y_) / bucket_) + 1;
    start_.assign(std::size_t(nbx_) * std::size_t(nby_) + 1, 0);
    std::vector<std::size_t> bucket_of(lon_.size());
    for (std::size_t c = 0; c < lon_.size(); ++c) {
      bucket_of[c] = bucketIndex(bx(lon_[c] * cos_), by(lat_[c]));
      ++start_[bucket_of[c] + 1];
    }
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    cells_.resize(lon_.size());
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t c = 0; c < lon_.size(); ++c) cells_[fill[bucket_of[c]]++] = c;
  }

  std::size_t nearest(double lon, double lat) const {
    const double x = lon * cos_;
    const int cx = bx(x), cy = by(lat);
    double best = std::numeric_limits<double>::max();
    std::size_t best_cell = 0;
    for (int ring = 0; ring < std::max(nbx_, nby_) + 1; ++ring) {
      // Only the buckets on the ring's perimeter, clipped to the grid (the inner ones were
      // searched by the smaller rings).
      for (int j = std::max(cy - ring, 0); j <= std::min(cy + ring, nby_ - 1); ++j) {
        const bool edge_row = std::abs(j - cy) == ring;
        const int step = edge_row ? 1 : std::max(2 * ring, 1);
        for (int i = cx - ring; i <= cx + ring; i += step) {
          if (i < 0 || i >= nbx_) continue;
          const std::size_t b = bucketIndex(i, j);
          for (std::size_t n = start_[b]; n < start_[b + 1]; ++n) {
            const std::size_t c = cells_[n];
            const double dx = lon_[c] * cos_ - x, dy = lat_[c] - lat;
            const double d2 = dx * dx + dy * dy;
            if (d2 < best) {
              best = d2;
              best_cell = c;
            }
          }
        }
      }
      // Any cell in a further ring is at least `ring * bucket` away.
      const double reach = ring * bucket_;
      if (best < std::numeric_limits<double>::max() && best <= reach * reach) break;
    }
    return best_cell;
  }

 private:
  int bx(double x) const { return std::clamp(static_cast<int>((x - min_x_) / bucket_), 0, nbx_ - 1); }
  int by(double y) const { return std::clamp(static_cast<int>((y - min_y_) / bucket_), 0, nby_ - 1); }
  std::size_t bucketIndex(int i, int j) const { return std::size_t(j) * std::size_t(nbx_) + std::size_t(i); }
  const std::vector<double>& lon_;
  const std::vector<double>& lat_;
  double cos_, bucket_;
  double min_x_ = 0, min_y_ = 0;
  int nbx_ = 1, nby_ = 1;
  std::vector<std::size_t> start_, cells_;
};

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
  const std::size_t budget = memoryBudgetBytes(options);
  // Source fields held at once: up to 7 condensate/state fields + heights (nz + 1) + clc.
  requireWithinBudget(path, "one timestep", double(nsrc) * double(nz + 1), 12, budget);

  static const std::array<IconClass, 6> kClasses = {{{Hydrometeor::Cloud, {"qc", "QC", "clwmr"}},
                                                     {Hydrometeor::Ice, {"qi", "QI"}},
                                                     {Hydrometeor::Rain, {"qr", "QR"}},
                                                     {Hydrometeor::Snow, {"qs", "QS"}},
                                                     {Hydrometeor::Graupel, {"qg", "QG"}},
                                                     {Hydrometeor::Hail, {"qh", "QH"}}}};
  ModelTimestep src;  // on source points (flat), levels in file order
  ReadStats cond_stats;
  for (const IconClass& c : kClasses) {
    if (auto name = nc.firstVar(c.names)) {
      nc.requireFloatingOrPacked(*name);
      auto data = readLevels(nc, l, *name, t, nz, 0.0f, cond_stats);
      requireAtMost(path, *name, data, kMaxMixingRatio_kg_per_kg, "a mixing ratio [kg/kg]");
      const std::int64_t negative = clampNegative(data);
      if (negative > 0) {
        log::warn("{}: {} had {} negative values, set to 0", path, *name, negative);
        src.repairs.negative_clamped += negative;
      }
      src.q_kg_per_kg[c.kind] = std::move(data);
    }
  }
  if (src.q_kg_per_kg.empty()) {
    throw InputError(
        fmt::format("{}: no condensate variable, expected at least one of qc, qi, qr, qs, qg (time, height, "
                    "{})",
                    path, l.native ? "ncells" : "lat, lon"));
  }
  auto read_state = [&](const std::string& var, std::size_t levels) {
    ReadStats s;
    auto data = readLevels(nc, l, var, t, levels, std::numeric_limits<float>::quiet_NaN(), s);
    if (s.fill_values > 0) {
      throw InputError(fmt::format("{}: {} has {} missing values (_FillValue/missing_value), expected a complete field",
                                   path, var, s.fill_values));
    }
    return data;
  };
  src.temperature_k = read_state(l.temp, nz);
  requireRange(path, l.temp, src.temperature_k, 100.0, 400.0, "a temperature [K]");
  src.pressure_pa = read_state(l.pres, nz);
  requireRange(path, l.pres, src.pressure_pa, 1.0, 2.0e5, "a pressure [Pa]");
  if (auto qv = nc.firstVar({"qv", "QV"})) {
    nc.requireFloatingOrPacked(*qv);
    src.water_vapour_kg_per_kg = readLevels(nc, l, *qv, t, nz, 0.0f, cond_stats);
    requireAtMost(path, *qv, src.water_vapour_kg_per_kg, kMaxMixingRatio_kg_per_kg, "a specific humidity [kg/kg]");
    src.repairs.negative_clamped += clampNegative(src.water_vapour_kg_per_kg);
  } else {
    log::warn("{}: qv is missing; specific humidity taken as 0", path);
    src.water_vapour_kg_per_kg.assign(nz * nsrc, 0.0f);
  }
  if (auto clc = nc.firstVar({"clc", "CLC", "ccl"})) {
    src.cloud_cover_fraction = readLevels(nc, l, *clc, t, nz, 0.0f, cond_stats);
    // clc is in percent (ICON, DWD GRIB2 "%"): to [0, 1]; negative values clamp to 0.
    const std::string units = nc.varText(*clc, "units").value_or("%");
    const double scale = units == "%" || units == "percent" ? 0.01 : 1.0;
    for (float& v : src.cloud_cover_fraction) v = static_cast<float>(std::clamp(double(v) * scale, 0.0, 1.0));
  }
  src.repairs.missing_as_zero = cond_stats.fill_values;
  std::vector<float> heights = read_state(l.heights, l.heights_are_half_levels ? nz + 1 : nz);
  requireRange(path, l.heights, heights, kLowestHeight_m, kHighestHeight_m, "a height [m]");

  // Vertical order: ICON writes level 1 at the model top; nephele wants bottom to top.
  const bool top_down = nz > 1 ? heights[0] > heights[(l.heights_are_half_levels ? nz : nz - 1) * nsrc] : false;
  auto flip = [&](std::vector<float>& f, std::size_t levels) {
    if (!top_down || f.empty()) return;
    for (std::size_t k = 0; k < levels / 2; ++k) {
      std::swap_ranges(f.begin() + std::ptrdiff_t(k * nsrc), f.begin() + std::ptrdiff_t((k + 1) * nsrc),
                       f.begin() + std::ptrdiff_t((levels - 1 - k) * nsrc));
    }
  };
  for (auto& [kind, f] : src.q_kg_per_kg) flip(f, nz);
  flip(src.temperature_k, nz);
  flip(src.pressure_pa, nz);
  flip(src.water_vapour_kg_per_kg, nz);
  flip(src.cloud_cover_fraction, nz);
  flip(heights, l.heights_are_half_levels ? nz + 1 : nz);
  // Mass-level heights: midpoints of half levels (Muth §3.2: z_k = (h_k + h_k+1) / 2).
  std::vector<float> height(nz * nsrc);
  std::vector<float> terrain(nsrc);
  for (std::size_t p = 0; p < nsrc; ++p) {
    if (l.heights_are_half_levels) {
      terrain[p] = heights[p];
      for (std::size_t k = 0; k < nz; ++k) {
        const float lo = heights[k * nsrc + p], hi = heights[(k + 1) * nsrc + p];
        if (!(hi > lo)) {
          throw InputError(fmt::format("{}: {} does not increase with height at level {} (point {}): {} m then {} m",
                                       path, l.heights, k, p, lo, hi));
        }
        height[k * nsrc + p] = 0.5f * (lo + hi);
      }
    } else {
      for (std::size_t k = 0; k < nz; ++k) height[k * nsrc + p] = heights[k * nsrc + p];
      // Surface: half a layer below the lowest full level.
      const float dz = nz > 1 ? heights[nsrc + p] - heights[p] : 20.0f;
      terrain[p] = heights[p] - 0.5f * dz;
    }
  }
  heights = {};

  ModelTimestep ts;
  ts.source_file = path;
  ts.time_index = time_index;
  ts.model = ModelKind::Icon;
  ts.nz = static_cast<int>(nz);
  ts.repairs = src.repairs;
  if (l.has_time && nc.hasVar("time")) {
    const auto values = nc.readDoubles("time");
    if (t < values.size()) ts.time_utc = timeFromValue(values[t], nc.varText("time", "units").value_or(""));
  }
  ts.georef.proj_definition = fmt::format("+proj=longlat +R={} +no_defs", kIconEarthRadius_m);
  ts.georef.geographic = true;

  // Horizontal mapping: target (i, j) -> source point index.
  std::vector<std::size_t> source_of;
  if (!l.native) {
    const std::string lon_var = nc.hasVar(l.lon_dim) ? l.lon_dim : need(nc, {"lon", "longitude"}, "longitudes [deg]");
    const std::string lat_var = nc.hasVar(l.lat_dim) ? l.lat_dim : need(nc, {"lat", "latitude"}, "latitudes [deg]");
    const auto lon = nc.readDoubles(lon_var);
    const auto lat = nc.readDoubles(lat_var);
    if (lon.size() != l.nlon || lat.size() != l.nlat) {
      throw InputError(fmt::format("{}: {}/{} have {}/{} values, expected {}/{}", path, lon_var, lat_var, lon.size(),
                                   lat.size(), l.nlon, l.nlat));
    }
    auto spacing = [&](const std::vector<double>& v, const std::string& name) {
      if (v.size() < 2) return 0.0;
      const double step = v[1] - v[0];
      for (std::size_t n = 1; n < v.size(); ++n) {
        if (!(std::abs((v[n] - v[n - 1]) - step) <= 1e-3 * std::abs(step)) || step == 0.0) {
          throw InputError(
              fmt::format("{}: {} is not evenly spaced at index {}, expected a regular lat-lon grid", path, name, n));
        }
      }
      return step;
    };
    const double dlon = spacing(lon, lon_var);
    const double dlat = spacing(lat, lat_var);
    if (dlon < 0.0) throw InputError(fmt::format("{}: {} decreases, expected increasing longitudes", path, lon_var));
    const bool south_first = dlat >= 0.0;
    ts.nx = static_cast<int>(l.nlon);
    ts.ny = static_cast<int>(l.nlat);
    ts.georef.dx_m = l.nlon > 1 ? dlon : 1.0;
    ts.georef.dy_m = l.nlat > 1 ? std::abs(dlat) : 1.0;
    ts.georef.x0 = lon.front();
    ts.georef.y0 = south_first ? lat.front() : lat.back();
    source_of.resize(l.nlon * l.nlat);
    for (std::size_t j = 0; j < l.nlat; ++j) {
      const std::size_t sj = south_first ? j : l.nlat - 1 - j;  // rows south to north
      for (std::size_t i = 0; i < l.nlon; ++i) source_of[j * l.nlon + i] = sj * l.nlon + i;
    }
  } else {
    const std::string clon = need(nc, {"clon"}, "cell centre longitudes [radian]");
    const std::string clat = need(nc, {"clat"}, "cell centre latitudes [radian]");
    auto lon = nc.readDoubles(clon);
    auto lat = nc.readDoubles(clat);
    if (lon.size() != l.ncells || lat.size() != l.ncells) {
      throw InputError(
          fmt::format("{}: clon/clat have {}/{} values, expected ncells = {}", path, lon.size(), lat.size(), l.ncells));
    }
    const bool radians = nc.varText(clon, "units").value_or("radian").rfind("rad", 0) == 0;
    double lat_min = 90, lat_max = -90, lon_min = 1e9, lon_max = -1e9;
    for (std::size_t c = 0; c < l.ncells; ++c) {
      if (radians) {
        lon[c] *= kDegPerRad;
        lat[c] *= kDegPerRad;
      }
      if (!std::isfinite(lon[c]) || !std::isfinite(lat[c]) || std::abs(lat[c]) > 90.0) {
        throw InputError(fmt::format("{}: clon/clat of cell {} is not a valid position, expected radians", path, c));
      }
      lat_min = std::min(lat_min, lat[c]);
      lat_max = std::max(lat_max, lat[c]);
      lon_min = std::min(lon_min, lon[c]);
      lon_max = std::max(lon_max, lon[c]);
    }
    const double cos_mid = std::max(std::cos(0.5 * (lat_min + lat_max) / kDegPerRad), 0.01);
    double dlat = options.native_resolution_deg;
    if (!(dlat > 0.0)) {
      // One target point per cell on average over the cells' bounding box.
      const double area = std::max((lon_max - lon_min) * cos_mid, 1e-9) * std::max(lat_max - lat_min, 1e-9);
      dlat = std::sqrt(area / double(l.ncells));
      // ... but never finer than the longer extent over ncells: for cells along a line (two
      // cells, or one row) the box has no area, and the clamped area above gave ~1e-5 deg
      // spacing, a 44 000-point row whose empty buckets CellLocator::nearest scanned for hours.
      // With this floor each axis has at most ncells + 1 points, the grid at most 3 ncells + 1.
      dlat = std::max(dlat, std::max((lon_max - lon_min) * cos_mid, lat_max - lat_min) / double(l.ncells));
    }
    const double dlon = dlat / cos_mid;
    const double nx_d = std::floor((lon_max - lon_min) / dlon) + 1.0;
    const double ny_d = std::floor((lat_max - lat_min) / dlat) + 1.0;
    requireWithinBudget(path, "the resampled native grid", nx_d * ny_d * double(nz), 12, budget);
    const auto nx_checked = limits::toIntChecked<int>(nx_d), ny_checked = limits::toIntChecked<int>(ny_d);
    if (!nx_checked || !ny_checked) {
      throw InputError(fmt::format("{}: the resampled native grid would be {} x {} points, more than an int "
                                   "indexes (LoadOptions::native_resolution_deg too fine)",
                                   path, nx_d, ny_d));
    }
    ts.nx = *nx_checked;
    ts.ny = *ny_checked;
    ts.georef.dx_m = dlon;
    ts.georef.dy_m = dlat;
    ts.georef.x0 = lon_min;
    ts.georef.y0 = lat_min;
    const CellLocator locator(lon, lat, cos_mid, 2.0 * dlat);
    source_of.resize(std::size_t(ts.nx) * std::size_t(ts.ny));
    for (int j = 0; j < ts.ny; ++j) {
      for (int i = 0; i < ts.nx; ++i) {
        source_of[std::size_t(j) * std::size_t(ts.nx) + std::size_t(i)] =
            locator.nearest(lon_min + i * dlon, lat_min + j * dlat);
      }
    }
  }

  const std::size_t n2 = std::size_t(ts.nx) * std::size_t(ts.ny);
  auto remap = [&](const std::vector<float>& f, std::size_t levels) {
    std::vector<float> out(levels * n2);
    for (std::size_t k = 0; k < levels; ++k)
      for (std::size_t p = 0; p < n2; ++p) out[k * n2 + p] = f[k * nsrc + source_of[p]];
    return out;
  };
  for (auto& [kind, f] : src.q_kg_per_kg) ts.q_kg_per_kg[kind] = remap(f, nz);
  ts.temperature_k = remap(src.temperature_k, nz);
  ts.pressure_pa = remap(src.pressure_pa, nz);
  ts.water_vapour_kg_per_kg = remap(src.water_vapour_kg_per_kg, nz);
  if (!src.cloud_cover_fraction.empty()) ts.cloud_cover_fraction = remap(src.cloud_cover_fraction, nz);
  ts.height_m = remap(height, nz);
  ts.terrain_height_m = remap(terrain, 1);
  ts.georef.lon_deg.resize(n2);
  ts.georef.lat_deg.resize(n2);
  for (int j = 0; j < ts.ny; ++j) {
    for (int i = 0; i < ts.nx; ++i) {
      const std::size_t p = std::size_t(j) * std::size_t(ts.nx) + std::size_t(i);
      ts.georef.lon_deg[p] = static_cast<float>(ts.georef.x0 + i * ts.georef.dx_m);
      ts.georef.lat_deg[p] = static_cast<float>(ts.georef.y0 + j * ts.georef.dy_m);
    }
  }
  return ts;
}

}  // namespace nph::io

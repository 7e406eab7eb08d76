#include "wrf_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/log.h"
#include "core/terminal_text.h"
#include "field_checks.h"
#include "netcdf_reader.h"

namespace nph::io {
namespace {

constexpr double kRdOverCp = kWrfGasConstantDryAir_J_per_kgK / kWrfSpecificHeatDryAir_J_per_kgK;
/// Largest disagreement [deg] between XLAT/XLONG and the attribute georeference before we warn.
constexpr double kGeolocationWarnTolerance_deg = 0.05;
/// Largest misfit [grid cells] of XLAT/XLONG against a shifted grid for the loader to place the grid
/// by XLAT/XLONG (a cropped window); XLAT/XLONG are stored as float (~1e-5 deg ≈ 1 m).
constexpr double kGeolocationFitTolerance_cells = 0.05;

struct WrfClass {
  Hydrometeor kind;
  const char* q_name;
  const char* n_name;
};
constexpr std::array<WrfClass, 6> kWrfClasses = {{{Hydrometeor::Cloud, "QCLOUD", "QNCLOUD"},
                                                  {Hydrometeor::Rain, "QRAIN", "QNRAIN"},
                                                  {Hydrometeor::Ice, "QICE", "QNICE"},
                                                  {Hydrometeor::Snow, "QSNOW", "QNSNOW"},
                                                  {Hydrometeor::Graupel, "QGRAUP", "QNGRAUPEL"},
                                                  {Hydrometeor::Hail, "QHAIL", "QNHAIL"}}};

/// Row t of WRF's `Times` ("2026-09-01_12:00:00", UTC), parsed once here (issue 17: the loaders
/// store parsed times). A row that is not a time makes the timestep untimed, with a warning naming
/// the file, the variable and the text (escaped: it may hold terminal control sequences).
geo::OptionalUtcTime wrfTime(const NcReader& nc, std::size_t t) {
  if (!nc.hasVar("Times")) return std::nullopt;
  const std::string text = nc.readTextRow("Times", t);
  try {
    return geo::UtcTime::parse(text.substr(0, std::min<std::size_t>(text.size(), 19)));
  } catch (const InputError&) {
    log::warn("{}: Times[{}] = \"{}\" is not a time, expected YYYY-MM-DD_hh:mm:ss; the timestep has no time", nc.path(),
              t, terminalSafe(text, false));
    return std::nullopt;
  }
}

double requireAttribute(const NcReader& nc, const char* name, double lo, double hi, const char* meaning) {
  const auto v = nc.globalNumber(name);
  if (!v) throw InputError(fmt::format("{}: global attribute {} is missing, expected {}", nc.path(), name, meaning));
  if (!std::isfinite(*v) || *v < lo || *v > hi) {
    throw InputError(fmt::format("{}: global attribute {} = {} is absurd, expected {} in [{}, {}]", nc.path(), name, *v,
                                 meaning, lo, hi));
  }
  return *v;
}

/// A global attribute that WRF writes as a small integer code (MAP_PROJ, MP_PHYSICS), checked
/// before the cast: 1e20 or NaN converted to int is undefined behaviour.
int requireSmallInteger(const NcReader& nc, const char* name, const char* meaning) {
  constexpr double kMaxCode = 1000.0;  // WRF's codes are < 100
  const double v = *nc.globalNumber(name);
  if (!(v >= -kMaxCode && v <= kMaxCode) || v != std::floor(v)) {
    throw InputError(fmt::format("{}: global attribute {} = {} is absurd, expected {} (an integer in [{}, {}])",
                                 nc.path(), name, v, meaning, -kMaxCode, kMaxCode));
  }
  return static_cast<int>(v);
}

struct Dims {
  int nx = 0, ny = 0, nz = 0;
  std::size_t nt = 0;
};

Dims wrfDims(const NcReader& nc) {
  Dims d;
  for (const char* name : {"Time", "bottom_top", "bottom_top_stag", "south_north", "west_east"}) {
    const auto len = nc.dimLength(name);
    // A file without a Time dimension holds one timestep (xarray's ds.isel(Time=0), NCO's
    // ncwa -a Time): every variable is then read without it (timedDims below).
    if (!len && std::string(name) == "Time") continue;
    if (!len) {
      throw InputError(fmt::format("{}: dimension {} is missing, expected a wrfout file with Time, bottom_top, "
                                   "bottom_top_stag, south_north, west_east",
                                   nc.path(), name));
    }
    if (*len == 0 && std::string(name) != "Time") {
      throw InputError(fmt::format("{}: dimension {} has length 0, expected at least 1", nc.path(), name));
    }
    if (*len > std::size_t(std::numeric_limits<int>::max())) {
      throw InputError(
          fmt::format("{}: dimension {} has length {}, larger than nephele supports", nc.path(), name, *len));
    }
  }
  d.nt = nc.dimLength("Time").value_or(1);
  d.nx = static_cast<int>(*nc.dimLength("west_east"));
  d.ny = static_cast<int>(*nc.dimLength("south_north"));
  d.nz = static_cast<int>(*nc.dimLength("bottom_top"));
  if (*nc.dimLength("bottom_top_stag") != std::size_t(d.nz) + 1) {
    throw InputError(fmt::format("{}: bottom_top_stag has length {}, expected bottom_top + 1 = {}", nc.path(),
                                 *nc.dimLength("bottom_top_stag"), d.nz + 1));
  }
  if (d.nt == 0)
    throw InputError(fmt::format("{}: dimension Time has length 0, expected at least one timestep", nc.path()));
  return d;
}

/// Whether `var` has the dimensions `spatial` with a leading Time (true) or without it (false):
/// files written through xarray, salem or NCO carry static fields (HGT, XLAT, XLONG, ...) without
/// Time, and single-timestep files may drop it everywhere. InputError names both accepted forms.
bool timedDims(const NcReader& nc, const std::string& var, const std::vector<std::string>& spatial) {
  std::vector<std::string> timed = {"Time"};
  timed.insert(timed.end(), spatial.begin(), spatial.end());
  const std::vector<std::string> dims = nc.varDimNames(var);
  if (dims == timed) return true;
  if (dims == spatial) return false;
  nc.requireDims(var, timed);  // throws, naming the expected dimensions
  return true;
}

}  // namespace

geo::GridGeoreference wrfGeoreference(const WrfProjectionAttributes& a, int nx, int ny, const std::string& path) {
  geo::GridGeoreference g;
  auto bad = [&](const char* name, double v, const char* expected) {
    throw InputError(fmt::format("{}: global attribute {} = {} is absurd, expected {}", path, name, v, expected));
  };
  // 0.1 m (below any LES) .. 10 000 km; dx = 1e-30 m passed before and overflowed the DLM.
  if (!(std::isfinite(a.dx_m) && a.dx_m >= 0.1 && a.dx_m < 1e7)) bad("DX", a.dx_m, "a grid spacing in [0.1, 1e7) m");
  if (!(std::isfinite(a.dy_m) && a.dy_m >= 0.1 && a.dy_m < 1e7)) bad("DY", a.dy_m, "a grid spacing in [0.1, 1e7) m");
  g.dx_m = a.dx_m;
  g.dy_m = a.dy_m;
  if (a.map_proj == 0) return g;  // Cartesian (idealized): x0 = y0 = 0, no projection

  auto lat_ok = [](double v) { return std::isfinite(v) && std::abs(v) <= 90.0; };
  auto lon_ok = [](double v) { return std::isfinite(v) && std::abs(v) <= 360.0; };
  if (!lat_ok(a.cen_lat)) bad("CEN_LAT", a.cen_lat, "a latitude in [-90, 90]");
  if (!lon_ok(a.cen_lon)) bad("CEN_LON", a.cen_lon, "a longitude in [-360, 360]");
  if (!lon_ok(a.stand_lon)) bad("STAND_LON", a.stand_lon, "a longitude in [-360, 360]");
  if (!lat_ok(a.truelat1)) bad("TRUELAT1", a.truelat1, "a latitude in [-90, 90]");
  if (!lat_ok(a.truelat2)) bad("TRUELAT2", a.truelat2, "a latitude in [-90, 90]");
  if (!lat_ok(a.moad_cen_lat)) bad("MOAD_CEN_LAT", a.moad_cen_lat, "a latitude in [-90, 90]");

  const double r = kWrfEarthRadius_m;
  switch (a.map_proj) {
    case 1: {  // Lambert conformal conic, secant at TRUELAT1/TRUELAT2, central meridian STAND_LON.
      if (std::abs(a.truelat1) < 1e-6 && std::abs(a.truelat2) < 1e-6)
        bad("TRUELAT1", a.truelat1, "a non-zero true latitude for Lambert conformal");
      const double lat0 = std::abs(a.moad_cen_lat) > 1e-6 ? a.moad_cen_lat : a.truelat1;
      g.proj_definition =
          fmt::format("+proj=lcc +lat_1={} +lat_2={} +lat_0={} +lon_0={} +x_0=0 +y_0=0 +R={} +units=m +no_defs",
                      a.truelat1, a.truelat2, lat0, a.stand_lon, r);
      break;
    }
    case 2:  // Polar stereographic, true at TRUELAT1, pole of TRUELAT1's hemisphere.
      g.proj_definition =
          fmt::format("+proj=stere +lat_0={} +lat_ts={} +lon_0={} +x_0=0 +y_0=0 +R={} +units=m +no_defs",
                      a.truelat1 >= 0.0 ? 90 : -90, a.truelat1, a.stand_lon, r);
      break;
    case 3:  // Mercator, true at TRUELAT1.
      g.proj_definition = fmt::format("+proj=merc +lat_ts={} +lon_0={} +x_0=0 +y_0=0 +R={} +units=m +no_defs",
                                      a.truelat1, a.stand_lon, r);
      break;
    case 6: {  // Cylindrical equidistant lat-lon, possibly rotated. DX/DY are metres along the
               // (rotated) equator: degrees = DX / (R pi / 180).
      if (!lat_ok(a.pole_lat)) bad("POLE_LAT", a.pole_lat, "a latitude in [-90, 90]");
      if (!lon_ok(a.pole_lon)) bad("POLE_LON", a.pole_lon, "a longitude in [-360, 360]");
      g.geographic = true;
      const double m_per_deg = r * std::numbers::pi / 180.0;
      g.dx_m = a.dx_m / m_per_deg;
      g.dy_m = a.dy_m / m_per_deg;
      if (std::abs(a.pole_lat - 90.0) < 1e-6) {
        g.proj_definition = fmt::format("+proj=longlat +R={} +no_defs", r);
      } else {
        // WPS rotated pole: POLE_LAT/POLE_LON is where the true North Pole lies in the rotated
        // grid, STAND_LON the rotation about the Earth's axis (WPS user guide, "rotated lat-lon";
        // for a grid centred at (lat0, lon0): POLE_LAT = 90 - lat0, POLE_LON = 180,
        // STAND_LON = 180 - lon0). As PROJ ob_tran: o_lat_p = POLE_LAT, o_lon_p = 180 - POLE_LON,
        // lon_0 = 180 - STAND_LON (as wrf-python's RotatedLatLon does).
        g.proj_definition =
            fmt::format("+proj=ob_tran +o_proj=longlat +o_lat_p={} +o_lon_p={} +lon_0={} +R={} +no_defs", a.pole_lat,
                        180.0 - a.pole_lon, 180.0 - a.stand_lon, r);
      }
      break;
    }
    default:
      throw InputError(fmt::format("{}: global attribute MAP_PROJ = {} is not supported, expected 0 (Cartesian), "
                                   "1 (Lambert), 2 (polar stereographic), 3 (Mercator) or 6 (lat-lon)",
                                   path, a.map_proj));
  }
  // Origin: WRF places the centre of the domain at (CEN_LAT, CEN_LON) (WPS geogrid, d01).
  const geo::MapProjection projection(g.proj_definition);
  glm::dvec2 centre{0.0};
  try {
    centre = projection.forward({a.cen_lon, a.cen_lat});
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: CEN_LAT/CEN_LON cannot be projected: {}", path, e.what()));
  }
  g.x0 = centre.x - 0.5 * (nx - 1) * g.dx_m;
  g.y0 = centre.y - 0.5 * (ny - 1) * g.dy_m;
  return g;
}

std::vector<geo::OptionalUtcTime> listWrfTimes(const std::string& path) {
  const NcReader nc(path);
  const Dims d = wrfDims(nc);
  std::vector<geo::OptionalUtcTime> times;
  for (std::size_t t = 0; t < d.nt; ++t) times.push_back(wrfTime(nc, t));
  return times;
}

namespace {

/// What loadWrf reads: everything, all but the sub-grid detail's fields (LoadOptions::defer_detail),
/// or those fields alone into a timestep that lacks them (loadDeferredDetail).
enum class WrfPart : std::uint8_t { All, WithoutDetail, DetailOnly };

void loadWrf(const std::string& path, std::int64_t time_index, const LoadOptions& options, WrfPart part,
             ModelTimestep& ts) {
  const NcReader nc(path);
  const Dims d = wrfDims(nc);
  if (time_index < 0 || std::size_t(time_index) >= d.nt) {
    throw InputError(fmt::format("{}: timestep {} does not exist, expected 0 .. {}", path, time_index, d.nt - 1));
  }
  if (part == WrfPart::DetailOnly && (ts.nx != d.nx || ts.ny != d.ny || ts.nz != d.nz)) {
    throw InputError(fmt::format("{}: the grid is now {} x {} x {}, expected {} x {} x {} as when timestep {} was "
                                 "loaded (the file changed?)",
                                 path, d.nx, d.ny, d.nz, ts.nx, ts.ny, ts.nz, time_index));
  }
  const std::size_t t = std::size_t(time_index);
  ts.source_file = path;
  ts.time_index = time_index;
  ts.model = ModelKind::Wrf;
  ts.nx = d.nx;
  ts.ny = d.ny;
  ts.nz = d.nz;
  ts.time_utc = wrfTime(nc, t);

  const std::vector<std::string> mass_dims = {"bottom_top", "south_north", "west_east"};
  const std::vector<std::string> stag_dims = {"bottom_top_stag", "south_north", "west_east"};
  const std::vector<std::string> surface_dims = {"south_north", "west_east"};
  const std::vector<std::string> u_dims = {"bottom_top", "south_north", "west_east_stag"};
  const std::vector<std::string> v_dims = {"bottom_top", "south_north_stag", "west_east"};
  // Each variable with or without the Time dimension (timedDims); its start/count accordingly.
  std::map<std::string, bool> timed;
  auto require = [&](const std::string& var, const std::vector<std::string>& spatial) {
    timed[var] = timedDims(nc, var, spatial);
  };
  auto slab = [&](const std::string& var, std::vector<std::size_t> spatial_count, std::vector<std::size_t>& start_out,
                  std::vector<std::size_t>& count_out) {
    start_out.assign(spatial_count.size(), 0);
    count_out = std::move(spatial_count);
    if (timed.at(var)) {
      start_out.insert(start_out.begin(), t);
      count_out.insert(count_out.begin(), 1);
    }
  };

  const std::size_t nx = std::size_t(d.nx), ny = std::size_t(d.ny), nz = std::size_t(d.nz);
  const std::vector<std::size_t> count = {nz, ny, nx};
  const std::vector<std::size_t> count_stag = {nz + 1, ny, nx};
  ReadStats stats;

  auto read_state = [&](const char* var, const std::vector<std::size_t>& cnt) {
    ReadStats s;
    std::vector<std::size_t> st, ct;
    slab(var, cnt, st, ct);
    auto data = nc.readFloats(var, st, ct, std::numeric_limits<float>::quiet_NaN(), s);
    if (s.fill_values > 0) {
      throw InputError(fmt::format("{}: {} has {} missing values (_FillValue/missing_value), expected a complete field",
                                   path, var, s.fill_values));
    }
    requireFinite(path, var, data);
    return data;
  };
  if (part != WrfPart::DetailOnly) {
    // Which hydrometeors and number concentrations exist: check their shapes before reading.
    std::vector<const WrfClass*> present_q, present_n;
    for (const WrfClass& c : kWrfClasses) {
      if (nc.hasVar(c.q_name)) {
        require(c.q_name, mass_dims);
        present_q.push_back(&c);
      }
      if (nc.hasVar(c.n_name)) {
        require(c.n_name, mass_dims);
        present_n.push_back(&c);
      }
    }
    if (present_q.empty()) {
      throw InputError(fmt::format("{}: no hydrometeor variable, expected at least one of QCLOUD, QRAIN, QICE, QSNOW, "
                                   "QGRAUP, QHAIL (Time, bottom_top, south_north, west_east)",
                                   path));
    }
    for (const char* v : {"P", "PB", "T"}) require(v, mass_dims);
    for (const char* v : {"PH", "PHB"}) require(v, stag_dims);
    const bool has_qv = nc.hasVar("QVAPOR");
    if (has_qv) require("QVAPOR", mass_dims);

    // Memory: q + N + qv, p, T, height (+ 2 staggered temporaries), before allocating any of it.
    const double points = double(d.nx) * double(d.ny) * double(d.nz + 1);
    const int fields = static_cast<int>(present_q.size() + present_n.size()) + 4 + 3;
    requireWithinBudget(path, "one timestep", points, fields, memoryBudgetBytes(options));

    auto read_mixing = [&](const char* var, double max_value, const char* what) {
      nc.requireFloatingOrPacked(var);
      std::vector<std::size_t> st, ct;
      slab(var, count, st, ct);
      auto data = nc.readFloats(var, st, ct, 0.0f, stats);
      requireFinite(path, var, data);
      requireAtMost(path, var, data, max_value, what);
      const std::int64_t negative = clampNegative(data);
      if (negative > 0) {
        log::warn("{}: {} had {} negative values, set to 0", path, var, negative);
        ts.repairs.negative_clamped += negative;
      }
      return data;
    };

    for (const WrfClass* c : present_q) {
      ts.q_kg_per_kg[c->kind] = read_mixing(c->q_name, kMaxMixingRatio_kg_per_kg, "a mixing ratio [kg/kg]");
    }
    for (const WrfClass* c : present_n) {
      ts.number_per_kg[c->kind] =
          read_mixing(c->n_name, kMaxNumberConcentration_per_kg, "a number concentration [1/kg]");
    }
    if (has_qv) {
      ts.water_vapour_kg_per_kg = read_mixing("QVAPOR", kMaxMixingRatio_kg_per_kg, "a mixing ratio [kg/kg]");
    } else {
      log::warn("{}: QVAPOR is missing; water vapour taken as 0 (air density then ignores moisture)", path);
      ts.water_vapour_kg_per_kg.assign(nx * ny * nz, 0.0f);
    }
    ts.repairs.missing_as_zero = stats.fill_values;
    if (stats.fill_values > 0) log::warn("{}: {} missing values in mixing ratios read as 0", path, stats.fill_values);

    // Pressure: full pressure = perturbation P + base state PB [Pa].
    ts.pressure_pa = read_state("P", count);
    {
      const auto pb = read_state("PB", count);
      for (std::size_t n = 0; n < pb.size(); ++n) ts.pressure_pa[n] += pb[n];
    }
    requireRange(path, "P+PB", ts.pressure_pa, 1.0, 2.0e5, "a pressure [Pa]");

    // Temperature from potential temperature: theta = T + 300 K (WRF stores theta - t0, t0 = 300 K);
    // T = theta (p / p0)^(R_d/c_p), the Exner function with p0 = 1000 hPa and R_d/c_p = 2/7
    // (Skamarock et al. 2019, WRF ARW v4 tech note, §2.1; module_model_constants.F).
    ts.temperature_k = read_state("T", count);
    // Single-precision pow: its ~1e-7 relative error (3e-5 K) is below float32 storage of T.
    constexpr auto kappa = static_cast<float>(kRdOverCp);
    constexpr auto inv_p0 = static_cast<float>(1.0 / kWrfReferencePressure_pa);
    constexpr auto theta_offset = static_cast<float>(kWrfThetaOffset_k);
    for (std::size_t n = 0; n < ts.temperature_k.size(); ++n) {
      ts.temperature_k[n] = (ts.temperature_k[n] + theta_offset) * std::pow(ts.pressure_pa[n] * inv_p0, kappa);
    }
    requireRange(path, "T (as temperature from theta and Exner)", ts.temperature_k, 100.0, 400.0, "a temperature [K]");

    // Heights: geopotential PH + PHB on staggered (w) levels, divided by g, averaged to mass levels.
    {
      auto phi = read_state("PH", count_stag);
      const auto phb = read_state("PHB", count_stag);
      for (std::size_t n = 0; n < phi.size(); ++n)
        phi[n] = static_cast<float>((double(phi[n]) + double(phb[n])) / kWrfGravity_m_per_s2);
      requireRange(path, "(PH+PHB)/g", phi, kLowestHeight_m, kHighestHeight_m, "a height [m]");
      const std::size_t n2 = nx * ny;
      ts.height_m = hugePageFloats(nx * ny * nz);
      for (std::size_t k = 0; k < nz; ++k) {
        for (std::size_t c = 0; c < n2; ++c) {
          const double lo = phi[k * n2 + c], hi = phi[(k + 1) * n2 + c];
          if (!(hi > lo)) {
            throw InputError(
                fmt::format("{}: PH+PHB does not increase with height at level {} (column {}): {} m then {} m, "
                            "expected increasing geopotential",
                            path, k, c, lo, hi));
          }
          ts.height_m[k * n2 + c] = static_cast<float>(0.5 * (lo + hi));
        }
      }
      // Terrain: HGT when present, else the lowest staggered level (PHB + PH at the surface / g).
      if (nc.hasVar("HGT")) {
        require("HGT", surface_dims);
        ts.terrain_height_m = read_state("HGT", {ny, nx});
        requireRange(path, "HGT", ts.terrain_height_m, kLowestHeight_m, kHighestTerrain_m, "a terrain height [m]");
      } else {
        ts.terrain_height_m.assign(phi.begin(), phi.begin() + std::ptrdiff_t(n2));
      }
    }

    if (nc.globalNumber("MP_PHYSICS")) {
      ts.microphysics_scheme = requireSmallInteger(nc, "MP_PHYSICS", "a WRF microphysics scheme number");
    }
    if (ts.microphysics_scheme >= 0 && ts.microphysics_scheme <= 3 && ts.q_kg_per_kg.count(Hydrometeor::Ice) == 0) {
      log::debug("{}: MP_PHYSICS = {}: no separate ice; frozen condensate lives in QCLOUD/QRAIN below 0 °C", path,
                 ts.microphysics_scheme);
    }

    // Georeference.
    WrfProjectionAttributes a;
    a.map_proj = nc.globalNumber("MAP_PROJ") ? requireSmallInteger(nc, "MAP_PROJ", "a WRF map projection code") : 0;
    a.dx_m = requireAttribute(nc, "DX", -1e300, 1e300, "the grid spacing [m]");
    a.dy_m = requireAttribute(nc, "DY", -1e300, 1e300, "the grid spacing [m]");
    const bool has_geo = nc.hasVar("XLAT") && nc.hasVar("XLONG");
    if (a.map_proj != 0) {
      a.truelat1 = nc.globalNumber("TRUELAT1").value_or(0.0);
      a.truelat2 = nc.globalNumber("TRUELAT2").value_or(a.truelat1);
      a.stand_lon = requireAttribute(nc, "STAND_LON", -1e300, 1e300, "the standard longitude [deg]");
      a.cen_lat = requireAttribute(nc, "CEN_LAT", -1e300, 1e300, "the domain centre latitude [deg]");
      a.cen_lon = requireAttribute(nc, "CEN_LON", -1e300, 1e300, "the domain centre longitude [deg]");
      a.moad_cen_lat = nc.globalNumber("MOAD_CEN_LAT").value_or(a.cen_lat);
      a.pole_lat = nc.globalNumber("POLE_LAT").value_or(90.0);
      a.pole_lon = nc.globalNumber("POLE_LON").value_or(0.0);
    } else if (has_geo) {
      log::warn("{}: MAP_PROJ = 0 but XLAT/XLONG present; loading as Cartesian", path);
    }
    ts.georef = wrfGeoreference(a, d.nx, d.ny, path);
    if (has_geo && a.map_proj != 0) {
      require("XLAT", surface_dims);
      require("XLONG", surface_dims);
      ReadStats s;
      std::vector<std::size_t> s2, c2;
      slab("XLAT", {ny, nx}, s2, c2);
      ts.georef.lat_deg = nc.readFloats("XLAT", s2, c2, std::numeric_limits<float>::quiet_NaN(), s);
      slab("XLONG", {ny, nx}, s2, c2);
      ts.georef.lon_deg = nc.readFloats("XLONG", s2, c2, std::numeric_limits<float>::quiet_NaN(), s);
      requireFinite(path, "XLAT", ts.georef.lat_deg);
      requireFinite(path, "XLONG", ts.georef.lon_deg);
      // Consistency of the attribute georeference with the file's own geolocation (corners).
      const geo::MapProjection projection(ts.georef.proj_definition);
      double worst = 0.0;
      for (const auto& [i, j] :
           {std::pair{0, 0}, std::pair{d.nx - 1, 0}, std::pair{0, d.ny - 1}, std::pair{d.nx - 1, d.ny - 1}}) {
        const auto [lon, lat] = geo::gridLonLat(projection, ts.georef, i, j);
        const std::size_t c = std::size_t(j) * nx + std::size_t(i);
        double dlon = std::fmod(std::abs(lon - double(ts.georef.lon_deg[c])), 360.0);
        dlon = std::min(dlon, 360.0 - dlon);
        worst = std::max({worst, std::abs(lat - double(ts.georef.lat_deg[c])), dlon});
      }
      if (worst > kGeolocationWarnTolerance_deg) {
        // A window cut out of a larger domain (ncks -d, xarray isel, salem subset) keeps the
        // parent's CEN_LAT/CEN_LON, so the grid is not centred there. Trust XLAT/XLONG: place the
        // grid origin where the mass points' projected positions put it (the mean offset over all
        // points), and keep it when that fit agrees with XLAT/XLONG everywhere.
        glm::dvec2 offset{0.0};
        std::vector<glm::dvec2> xy(nx * ny);
        for (std::size_t j = 0; j < ny; ++j)
          for (std::size_t i = 0; i < nx; ++i) {
            const std::size_t c = j * nx + i;
            xy[c] = projection.forward({double(ts.georef.lon_deg[c]), double(ts.georef.lat_deg[c])});
            offset += xy[c] - glm::dvec2(double(i) * ts.georef.dx_m, double(j) * ts.georef.dy_m);
          }
        offset /= double(nx * ny);
        double misfit_cells = 0.0;
        for (std::size_t j = 0; j < ny; ++j)
          for (std::size_t i = 0; i < nx; ++i) {
            const glm::dvec2 e =
                xy[j * nx + i] - offset - glm::dvec2(double(i) * ts.georef.dx_m, double(j) * ts.georef.dy_m);
            misfit_cells = std::max({misfit_cells, std::abs(e.x) / ts.georef.dx_m, std::abs(e.y) / ts.georef.dy_m});
          }
        if (misfit_cells < kGeolocationFitTolerance_cells) {
          log::info("{}: CEN_LAT/CEN_LON ({}, {}) are not the centre of this grid (off by {:.3f} deg at a corner: a "
                    "window cropped from a larger domain?); placing the grid by XLAT/XLONG instead (fit within {:.3f} "
                    "grid cells)",
                    path, a.cen_lat, a.cen_lon, worst, misfit_cells);
          ts.georef.x0 = offset.x;
          ts.georef.y0 = offset.y;
        } else {
          log::warn("{}: projection from MAP_PROJ={} disagrees with XLAT/XLONG by {:.3f} deg at a corner, and no shift "
                    "of the grid fixes it (misfit {:.2f} grid cells); keeping the attributes' placement",
                    path, a.map_proj, worst, misfit_cells);
        }
      }
    }
  }
  if (part == WrfPart::WithoutDetail) return;
  // Fields for sub-grid detail (issue 13), where the file has them; destaggered to mass points.
  auto read_optional = [&](const char* var, const std::vector<std::string>& spatial, std::vector<std::size_t> cnt) {
    require(var, spatial);
    return read_state(var, cnt);
  };
  if (nc.hasVar("CLDFRA")) {
    ts.cloud_fraction = read_optional("CLDFRA", mass_dims, count);
    requireRange(path, "CLDFRA", ts.cloud_fraction, 0.0, 1.0 + 1e-6, "a cloud fraction [0, 1]");
  }
  if (nc.hasVar("TKE_PBL")) {
    ts.tke_m2_per_s2 = read_optional("TKE_PBL", mass_dims, count);
  } else if (nc.hasVar("QKE")) {
    ts.tke_m2_per_s2 = read_optional("QKE", mass_dims, count);  // MYNN: QKE = 2 TKE
    for (float& q : ts.tke_m2_per_s2) q *= 0.5f;
  }
  if (!ts.tke_m2_per_s2.empty()) requireRange(path, "TKE_PBL/QKE", ts.tke_m2_per_s2, 0.0, 1e4, "a TKE [m2/s2]");
  const std::size_t n2 = nx * ny;
  if (nc.hasVar("W")) {
    const auto w = read_optional("W", stag_dims, count_stag);
    ts.wind_w_m_per_s.resize(nx * ny * nz);
    for (std::size_t m = 0; m < ts.wind_w_m_per_s.size(); ++m) ts.wind_w_m_per_s[m] = 0.5f * (w[m] + w[m + n2]);
  }
  if (nc.hasVar("U")) {
    const auto u = read_optional("U", u_dims, {nz, ny, nx + 1});
    ts.wind_u_m_per_s.resize(nx * ny * nz);
    for (std::size_t r = 0; r < nz * ny; ++r)
      for (std::size_t i = 0; i < nx; ++i)
        ts.wind_u_m_per_s[r * nx + i] = 0.5f * (u[r * (nx + 1) + i] + u[r * (nx + 1) + i + 1]);
  }
  if (nc.hasVar("V")) {
    const auto v = read_optional("V", v_dims, {nz, ny + 1, nx});
    ts.wind_v_m_per_s.resize(nx * ny * nz);
    for (std::size_t k = 0; k < nz; ++k)
      for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
          const std::size_t a0 = (k * (ny + 1) + j) * nx + i;
          ts.wind_v_m_per_s[(k * ny + j) * nx + i] = 0.5f * (v[a0] + v[a0 + nx]);
        }
  }
}

}  // namespace

ModelTimestep loadWrfTimestep(const std::string& path, std::int64_t time_index, const LoadOptions& options) {
  ModelTimestep ts;
  loadWrf(path, time_index, options, options.defer_detail ? WrfPart::WithoutDetail : WrfPart::All, ts);
  ts.detail_deferred = options.defer_detail;
  return ts;
}

void loadWrfDetail(ModelTimestep& ts, const LoadOptions& options) {
  loadWrf(ts.source_file, ts.time_index, options, WrfPart::DetailOnly, ts);
}

}  // namespace nph::io

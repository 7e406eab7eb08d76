#include "wrf_hurricane.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>

#include "atmosphere.h"
#include "core/error.h"
#include "dem_writer.h"
#include "geo/map_projection.h"
#include "geo/utc_time.h"
#include "wrf_alpine.h"

namespace nph::datagen {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRdOverCp = kWrfGasConstantDryAir_J_per_kgK / kWrfSpecificHeatDryAir_J_per_kgK;
/// Ratio of the gas constants of dry air and water vapour (287.0 / 461.6), for q_s = eps e/(p - e).
constexpr double kEpsilonRdOverRv = 0.622;

// ---- storm geometry (kilometres, hours) ------------------------------------------------------
constexpr double kRadiusMaxWind_km = 40.0;      ///< eyewall radius at the surface
constexpr double kEyewallTilt_km_per_km = 2.5;  ///< outward slope of the eyewall with height
constexpr double kEyeClearRadius_km = 14.0;
constexpr double kCentralPressureDeficit_pa = 5000.0;
constexpr double kMaxWind_m_per_s = 55.0;
constexpr double kWarmCore_k = 8.0;
constexpr double kStormMotionX_m_per_s = -4.0;  ///< north-westward drift
constexpr double kStormMotionY_m_per_s = 3.0;
constexpr double kBandRotation_rad_per_h = 0.35;
constexpr double kSpiralPitch_rad = 18.0 * kPi / 180.0;
constexpr int kSpiralArms = 2;

// ---- the cellular hurricane (WrfCase::HurricaneCells; kilometres) ---------------------------
// What a 2–4 km convection-permitting run of a mature hurricane shows (Muth 2026 §3.2: the regimes
// a renderer must tell apart are convective towers and stratiform layers; both are here, in data).
constexpr double kCellsEyewallRadius_km = 36.0;      ///< eyewall centre at the surface
constexpr double kCellsEyewallTilt_km_per_km = 1.2;  ///< outward slope with height (the stadium)
constexpr double kCellsEyeRadius_km = 22.0;          ///< clear eye at the surface, widening with the tilt
constexpr double kCellsBandPitch_rad = 16.0 * kPi / 180.0;
constexpr double kCellsOutflowPitch_rad = 55.0 * kPi / 180.0;  ///< outflow cirrus: nearly radial
constexpr double kCellsCanopyRadius_km = 320.0;
constexpr double kCellsShear_rad = 0.6;  ///< convection is favoured on this side (downshear-left)
constexpr double kCellsCumulusSpacing_km = 9.0;

// ---- particle sizes for the two-moment variant: N = q / (4/3 pi r^3 rho_p) ------------------
struct ParticleClass {
  const char* q_name;
  const char* n_name;
  const char* q_description;
  const char* n_description;
  double radius_m;
  double density_kg_per_m3;
};
// Mean radii/densities typical of the Thompson scheme's assumptions (Thompson et al. 2008,
// Mon. Wea. Rev. 136): cloud 10 µm water, rain 0.5 mm, ice 30 µm (rho 890), snow 0.5 mm with
// bulk density 100 kg/m3, graupel 1 mm (rho 400), hail 2.5 mm (rho 900).
constexpr ParticleClass kCloud{"QCLOUD", "QNCLOUD", "Cloud water mixing ratio", "cloud water Number concentration",
                               10e-6,    1000.0};
constexpr ParticleClass kRain{"QRAIN", "QNRAIN", "Rain water mixing ratio", "Rain Number concentration",
                              0.5e-3,  1000.0};
constexpr ParticleClass kIce{"QICE", "QNICE", "Ice mixing ratio", "Ice Number concentration", 30e-6, 890.0};
constexpr ParticleClass kSnow{"QSNOW", "QNSNOW", "Snow mixing ratio", "Snow Number concentration", 0.5e-3, 100.0};
constexpr ParticleClass kGraupel{"QGRAUP", "QNGRAUPEL", "Graupel mixing ratio", "Graupel Number concentration",
                                 1.0e-3,   400.0};
constexpr ParticleClass kHail{"QHAIL", "QNHAIL", "Hail mixing ratio", "Hail Number concentration", 2.5e-3, 900.0};

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
double gaussian(double x, double centre, double width) {
  const double d = (x - centre) / width;
  return std::exp(-d * d);
}
/// Smooth bump that is 1 between lo and hi and falls off over `edge` outside.
double layer(double z, double lo, double hi, double edge) {
  return smoothstep(lo - edge, lo, z) * (1.0 - smoothstep(hi, hi + edge, z));
}

struct ProjectionSetup {
  int map_proj = 0;
  std::string proj_definition;  // empty for Cartesian
  bool geographic = false;
  double truelat1 = 0.0, truelat2 = 0.0, stand_lon = 0.0, pole_lat = 90.0, pole_lon = 0.0;
  std::string name;
};

// The projection's parameters follow the domain centre (WrfHurricaneSpec::centre_*): the
// defaults (−75°, 25°) give TRUELAT1/2 = 20°/30° and STAND_LON = −77° as always, so every file
// written before the centre could move is written bit for bit the same.
ProjectionSetup projectionSetup(WrfProjection p, double cen_lon, double cen_lat) {
  ProjectionSetup s;
  const double r = kWrfEarthRadius_m;
  const double stand_lon = cen_lon - 2.0;
  // The generator deliberately uses a different but equivalent parameterisation from the loader
  // (lat_0 = TRUELAT1 instead of MOAD_CEN_LAT, CF-style rotated pole), so that a test comparing
  // the loader's georeference with XLAT/XLONG checks the loader rather than repeating it.
  switch (p) {
    case WrfProjection::Lambert: {
      const double t1 = cen_lat - 5.0, t2 = cen_lat + 5.0;
      s = {1, "", false, t1, t2, stand_lon, 90.0, 0.0, "Lambert Conformal"};
      s.proj_definition = fmt::format("+proj=lcc +lat_1={} +lat_2={} +lat_0={} +lon_0={} +R={} +units=m +no_defs", t1,
                                      t2, t1, stand_lon, r);
      break;
    }
    case WrfProjection::PolarStereographic:
      s = {2, "", false, 60.0, 0.0, stand_lon, 90.0, 0.0, "Polar Stereographic"};
      s.proj_definition =
          fmt::format("+proj=stere +lat_0=90 +lat_ts=60 +lon_0={} +R={} +units=m +no_defs", stand_lon, r);
      break;
    case WrfProjection::Mercator:
      s = {3, "", false, cen_lat - 2.5, 0.0, stand_lon, 90.0, 0.0, "Mercator"};
      s.proj_definition =
          fmt::format("+proj=merc +lat_ts={} +lon_0={} +R={} +units=m +no_defs", cen_lat - 2.5, stand_lon, r);
      break;
    case WrfProjection::LatLon:
      s = {6, "", true, 0.0, 0.0, 0.0, 90.0, 0.0, "Cylindrical Equidistant"};
      s.proj_definition = fmt::format("+proj=longlat +R={} +no_defs", r);
      break;
    case WrfProjection::RotatedLatLon:
      // WPS convention for a rotated grid centred on (lat0, lon0): POLE_LAT = 90 - lat0,
      // POLE_LON = 180, STAND_LON = 180 - lon0. As CF grid_mapping: grid_north_pole_latitude =
      // 90 - lat0, grid_north_pole_longitude = lon0 - 180, i.e. PROJ o_lat_p = 90 - lat0, lon_0 = lon0.
      s = {6, "", true, 0.0, 0.0, 180.0 - cen_lon, 90.0 - cen_lat, 180.0, "Cylindrical Equidistant"};
      s.proj_definition = fmt::format("+proj=ob_tran +o_proj=longlat +o_lat_p={} +o_lon_p=0 +lon_0={} +R={} +no_defs",
                                      90.0 - cen_lat, cen_lon, r);
      break;
    case WrfProjection::Cartesian: s = {0, "", false, 0.0, 0.0, 0.0, 90.0, 0.0, "Cartesian"}; break;
  }
  return s;
}

/// Column state shared by all variables of one timestep.
struct Grid {
  int nx, ny, nz;
  std::size_t n2() const { return std::size_t(nx) * std::size_t(ny); }
  std::size_t n3() const { return n2() * std::size_t(nz); }
  std::size_t at(int i, int j, int k) const {
    return (std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx) + std::size_t(i);
  }
};

class Writer {
 public:
  Writer(const WrfHurricaneSpec& spec, const std::string& path)
      : spec_(spec),
        nc_(path, spec.format),
        proj_(projectionSetup(spec.projection, spec.centre_lon_deg, spec.centre_lat_deg)),
        noise_(spec.seed) {}

  WrfTruth run();

 private:
  void defineFile();
  int defField(const std::string& name, const std::vector<int>& dims, const std::string& memory_order,
               const std::string& description, const std::string& units, const std::string& stagger);
  void writeTimestep(int t);
  void put3d(const std::string& name, int t, const std::vector<float>& data, int nz_var, int ny_var, int nx_var);
  void put2d(const std::string& name, int t, const std::vector<float>& data);

  // Storm position of timestep t in metres from grid point (0, 0).
  void stormCentre(int t, double& x_m, double& y_m) const;

  // ---- the coarse storm (WrfCase::CoarseStorm) ----
  struct StormCell {
    double x_km, y_km, radius_km, top_km, strength;
  };
  struct StormPoint {
    double q_cloud = 0, q_rain = 0, q_ice = 0, q_snow = 0, q_graupel = 0, w_m_per_s = 0, tke_m2_per_s2 = 0;
  };
  std::vector<StormCell> stormCells(double hours) const;

  // ---- the cellular hurricane (WrfCase::HurricaneCells) ----
  /// Per-column (nx*ny) structure of one timestep; every point's hydrometeors follow from it and
  /// the height, so the 3-D loop stays as cheap as the smooth hurricane's.
  struct CellularColumns {
    std::vector<float> eyewall, eyewall_top_km;                ///< tower strength at the column's azimuth, domed top
    std::vector<float> cell, cell_top_km, cell_depth;          ///< dominant band/moat/cumulus cell; deep weight
    std::vector<float> shield, shield_top_km;                  ///< stratiform shield
    std::vector<float> canopy, canopy_top_km, canopy_base_km;  ///< outflow cirrus
  };
  CellularColumns cellularColumns(double hours, double cx_m, double cy_m) const;
  struct CellularPoint {
    double q_cloud = 0, q_rain = 0, q_ice = 0, q_snow = 0, q_graupel = 0, q_hail = 0, w_m_per_s = 0, tke_m2_per_s2 = 0;
  };
  static CellularPoint cellularPoint(const CellularColumns& col, std::size_t c, double r_km, double z_m,
                                     double terrain_m, double temperature_k);
  StormPoint stormPoint(const std::vector<StormCell>& cells, int i, int j, double x_km, double y_km, double z_m,
                        double terrain_m, double temperature_k, double hours) const;

  const WrfHurricaneSpec& spec_;
  NcWriter nc_;
  ProjectionSetup proj_;
  ValueNoise noise_;
  Grid g_{0, 0, 0};
  std::vector<double> znw_, znu_;
  std::vector<double> terrain_m_;
  std::vector<float> lat_, lon_;
  std::map<std::string, int> var_;
  WrfTruth truth_;
  AlpineTerrain alpine_;  ///< WrfCase::AlpineStorm only
  geo::UtcTime start_ = geo::UtcTime::fromCivil(2026, 9, 1, 12);
};

void Writer::stormCentre(int t, double& x_m, double& y_m) const {
  const double hours = spec_.first_hour + t;
  const double lx = (g_.nx - 1) * spec_.dx_m, ly = (g_.ny - 1) * spec_.dx_m;
  // Starts south-east of the domain centre and drifts north-west across it over 6 hours.
  x_m = 0.5 * lx + (hours - 2.5) * 3600.0 * kStormMotionX_m_per_s;
  y_m = 0.5 * ly + (hours - 2.5) * 3600.0 * kStormMotionY_m_per_s;
}

// The coarse storm: a mesoscale convective system as a 10-km model resolves it. Deep cells are
// 7–16 km in radius, so each fills one to three grid columns; their summits (7.5–12.5 km) end
// within a few hundred metres, i.e. inside one model level, and their tops fall towards the flanks
// (domed towers; the tallest spread an anvil). A stratiform ice/snow shield (a 260 × 170 km
// ellipse, thinning to a lens at its rim) has a top that varies by a few hundred metres from column
// to column, so it ends at different model levels in neighbouring columns: the terraces of real
// coarse output. Every field carries a per-column (2Δx) factor, as model output does. (Before
// issue 13's shape work the cells were flat-topped cylinders and the shield a flat disc with a
// vertical rim: no renderer can make those look like clouds.)
std::vector<Writer::StormCell> Writer::stormCells(double hours) const {
  const double lx_km = (g_.nx - 1) * spec_.dx_m / 1000.0, ly_km = (g_.ny - 1) * spec_.dx_m / 1000.0;
  constexpr int kCells = 28;
  std::vector<StormCell> cells;
  for (int c = 0; c < kCells; ++c) {
    const double a = noise_.hash(c, 1, 0), b = noise_.hash(c, 2, 0), h = noise_.hash(c, 3, 0);
    // Half the cells on a south-west → north-east squall line, the rest scattered.
    const bool line = c % 2 == 0;
    const double x = line ? lx_km * (0.2 + 0.6 * a) : lx_km * (0.15 + 0.7 * a);
    const double y = line ? ly_km * (0.25 + 0.5 * a) + 25.0 * (b - 0.5) : ly_km * (0.15 + 0.7 * b);
    // Cells move with the mean wind and grow/decay over a 3-hour life cycle.
    const double life = std::sin(kPi * std::fmod(hours / 3.0 + h, 1.0));
    cells.push_back({x + hours * 3.6 * kStormMotionX_m_per_s, y + hours * 3.6 * kStormMotionY_m_per_s,
                     7.0 + 9.0 * noise_.hash(c, 4, 0), 7.5 + 5.0 * noise_.hash(c, 5, 0), 0.5 + 0.5 * life});
  }
  return cells;
}

Writer::StormPoint Writer::stormPoint(const std::vector<StormCell>& cells, int i, int j, double x_km, double y_km,
                                      double z_m, double terrain_m, double temperature_k, double hours) const {
  StormPoint p;
  const double zk = z_m / 1000.0;
  const auto hour = static_cast<std::int64_t>(std::floor(hours));
  const double column = 0.7 + 0.6 * noise_.hash(i, j, 1000 + hour);  // grid-scale noise
  double cell = 0.0, top_km = 0.0, profile = 0.0, anvil = 0.0, anvil_top_km = 0.0;
  for (const StormCell& s : cells) {
    const double r_km = std::hypot(x_km - s.x_km, y_km - s.y_km);
    const double g = gaussian(r_km, 0.0, s.radius_km);
    if (s.strength * g > cell) {
      cell = s.strength * g;
      profile = g;
      top_km = s.top_km;
    }
    // The tallest cells (tops above 9.5 km) spread an anvil at their top, 2.5× their radius.
    const double a = s.top_km > 9.5 ? s.strength * gaussian(r_km, 0.0, 2.5 * s.radius_km) : 0.0;
    if (a > anvil) {
      anvil = a;
      anvil_top_km = s.top_km;
    }
  }
  cell = cell < 0.05 ? 0.0 : cell * column;
  anvil = anvil < 0.1 ? 0.0 : anvil;
  // A cell's top falls from its summit towards its flanks (profile^0.35: 0.78 of the height at
  // half the peak, 0.35 at the 0.05 cut), so a cell is a tower with a domed summit and lower
  // flanking turrets, not a flat-topped cylinder; its anvil thins towards its rim (top 0.8 km lower,
  // base 1.2 km higher).
  top_km = 1.2 + (top_km - 1.2) * std::pow(profile, 0.35);
  const double anvil_rim = 1.0 - std::min(anvil / 0.6, 1.0);
  const double anvil_layer =
      anvil > 0.0 ? layer(zk, anvil_top_km - 2.0 + 1.2 * anvil_rim, anvil_top_km - 0.2 - 0.8 * anvil_rim, 0.2) : 0.0;
  const double ellipse = std::hypot((x_km - 0.5 * (g_.nx - 1) * spec_.dx_m / 1000.0) / 260.0,
                                    (y_km - 0.55 * (g_.ny - 1) * spec_.dx_m / 1000.0) / 170.0);
  const double shield = (1.0 - smoothstep(0.8, 1.0, ellipse)) * column;
  // The shield is a lens: its top sinks by 2.5 km and its snow base rises by 1.5 km towards the rim.
  const double shield_top_km = 8.2 + 1.6 * noise_.fbm(x_km / 90.0, y_km / 90.0, 0.2 * hours, 2) +
                               0.6 * (noise_.hash(i, j, 2000) - 0.5) - 2.5 * smoothstep(0.3, 1.0, ellipse);
  const double shield_base_km = 4.6 + 1.5 * smoothstep(0.5, 1.0, ellipse);
  const bool warm = temperature_k > kFreezingPoint_k;
  const double freezing_mix = smoothstep(kFreezingPoint_k - 25.0, kFreezingPoint_k - 2.0, temperature_k);
  // Convective cores: sharp tops (0.3 km edge) and bases at 1.2 km.
  const double core = cell * layer(zk, 1.2, top_km, 0.3);
  p.q_cloud = 1.6e-3 * core * freezing_mix + 1.2e-4 * shield * layer(zk, 3.0, 4.6, 0.2) * freezing_mix;
  p.q_rain = (2.2e-3 * cell + 1.2e-4 * shield) * layer(zk, -1.0, 4.2, 0.6) * (warm ? 1.0 : 0.2);
  p.q_graupel = 1.0e-3 * cell * layer(zk, 4.5, std::min(top_km, 9.0), 0.5);
  p.q_ice = warm ? 0.0
                 : 4.0e-4 * core * smoothstep(6.0, 8.0, zk) + 8.0e-5 * shield * layer(zk, 6.0, shield_top_km, 0.05) +
                       1.5e-4 * anvil * anvil_layer;
  p.q_snow = warm ? 0.0
                  : 6.0e-4 * core * smoothstep(5.0, 7.0, zk) +
                        2.5e-4 * shield * layer(zk, shield_base_km, shield_top_km, 0.05);
  // Updrafts in the cores (8 m/s at mid-levels), gentle ascent in the shield.
  p.w_m_per_s = 8.0 * cell * std::sin(kPi * std::clamp((zk - 1.0) / std::max(top_km - 1.0, 1.0), 0.0, 1.0)) +
                0.3 * shield * layer(zk, 4.6, shield_top_km, 0.5);
  // TKE: a mixed boundary layer (0.4 m²/s², ~1.5 km deep) and turbulence in the cells and shield.
  p.tke_m2_per_s2 = 0.4 * (1.0 - smoothstep(800.0, 1800.0, z_m - terrain_m)) + 4.0 * core +
                    0.5 * shield * layer(zk, 4.6, shield_top_km, 0.5);
  return p;
}

// The cellular hurricane, column by column (kilometres relative to the storm centre):
// - eyewall: a ring that is stronger downshear-left, with 14 convective towers on it whose domed
//   tops reach 13–15 km, a third of them overshooting to 16–17.5 km (the tops rise and fall hour to
//   hour); its radius grows with height (kCellsEyewallTilt_km_per_km) so the eye widens upwards;
// - spiral rainbands (two principal arms and an outer band) made of discrete cells 3.5–9 km in
//   radius every 12–24 km along the arm, with gaps (22 % of the places stay empty), tops mostly
//   8–11 km and a few towers to 16 km, lower outwards, some with a shallower feeder cell beside them;
// - a stratiform shield of varied depth (tops 6–10 km) inside the bands and trailing along them,
//   broken where its noise is low;
// - an outflow cirrus canopy (12–15 km) with a hole over the eye, radial filaments along the
//   anticyclonically curving outflow and transverse bands near its edge, thinning and breaking
//   into filaments there;
// - shallow cumulus (tops 1.5–3 km, a few congestus) in the moat and outside, clustered in fields.
Writer::CellularColumns Writer::cellularColumns(double hours, double cx_m, double cy_m) const {
  const int nx = g_.nx, ny = g_.ny;
  const std::size_t n2 = g_.n2();
  const double dx_km = spec_.dx_m / 1000.0, cx = cx_m / 1000.0, cy = cy_m / 1000.0;
  const auto hour = static_cast<std::int64_t>(std::floor(hours));
  const double spin = kBandRotation_rad_per_h * hours;
  CellularColumns col;
  for (std::vector<float>* v :
       {&col.eyewall, &col.eyewall_top_km, &col.cell, &col.cell_top_km, &col.cell_depth, &col.shield,
        &col.shield_top_km, &col.canopy, &col.canopy_top_km, &col.canopy_base_km}) {
    v->assign(n2, 0.0f);
  }
  struct Tower {
    double phi, strength, top_km, width_km;
  };
  constexpr int kTowers = 14;
  constexpr double kRingTop_km = 12.0;
  std::vector<Tower> towers;
  for (int k = 0; k < kTowers; ++k) {
    const bool overshooting = noise_.hash(k, 13, 0) < 0.35;
    const double b = noise_.hash(k, 12, hour);
    towers.push_back({2.0 * kPi * (k + 0.6 * (noise_.hash(k, 14, 0) - 0.5)) / kTowers + 1.5 * spin,
                      0.6 + 0.4 * noise_.hash(k, 11, hour), overshooting ? 16.5 + 1.5 * b : 13.0 + 2.0 * b,
                      7.0 + 6.0 * noise_.hash(k, 15, 0)});
  }
  const double eye_top_km = kCellsEyeRadius_km + kCellsEyewallTilt_km_per_km * 14.0;
  tbb::parallel_for(0, ny, [&](int j) {
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      const double x = i * dx_km - cx, y = j * dx_km - cy;
      const double r = std::hypot(x, y), phi = std::atan2(y, x);
      // Eyewall: the ring's strength and top at this azimuth, the towers' where they dominate.
      double ew = 0.45 + 0.2 * std::cos(phi - kCellsShear_rad);
      double ew_top = kRingTop_km + std::cos(phi - kCellsShear_rad);
      for (const Tower& t : towers) {
        const double arc = std::remainder(phi - t.phi, 2.0 * kPi) * (kCellsEyewallRadius_km + 8.0);
        const double g = gaussian(arc, 0.0, t.width_km);
        ew = std::max(ew, t.strength * g);
        ew_top = std::max(ew_top, kRingTop_km + (t.top_km - kRingTop_km) * std::pow(g, 0.4));
      }
      col.eyewall[c] = static_cast<float>(ew);
      col.eyewall_top_km[c] = static_cast<float>(ew_top);
      // Noise moves with the storm (storm-relative coordinates) and changes hour to hour.
      const double n_large = noise_.fbm(x / 80.0 + 50.0, y / 80.0 + 50.0, 0.1 * hours + 5.0, 3);
      const double n_mid = noise_.fbm(x / 25.0 + 50.0, y / 25.0 + 50.0, 0.3 * hours + 9.0, 2);
      const double n_edge = noise_.fbm(x / 120.0 + 50.0, y / 120.0 + 50.0, 0.05 * hours + 13.0, 2);
      // Stratiform shield: inside the bands (stronger downshear-left) and trailing along them.
      const double psi =
          phi - spin + std::log(std::max(r, 1.0) / kCellsEyewallRadius_km) / std::tan(kCellsBandPitch_rad);
      double arm = psi * kSpiralArms / (2.0 * kPi);
      arm -= std::round(arm);
      const double rw = r * (0.8 + 0.4 * n_large);  // a ragged outer edge
      const double inner = smoothstep(45.0, 75.0, r) * (1.0 - smoothstep(100.0, 180.0, rw)) *
                           (0.65 + 0.35 * std::cos(phi - kCellsShear_rad - 0.8));
      const double trailing =
          0.6 * gaussian(arm, 0.0, 0.2) * smoothstep(70.0, 110.0, r) * (1.0 - smoothstep(300.0, 420.0, rw));
      const double shield = std::max(inner, trailing) * (0.4 + 1.2 * n_mid);
      col.shield[c] = static_cast<float>(std::min(shield * smoothstep(0.25, 0.5, shield), 1.2));
      col.shield_top_km[c] =
          static_cast<float>(5.5 + 4.0 * n_large + 1.5 * (n_mid - 0.5) - 1.5 * smoothstep(120.0, 260.0, r));
      // Outflow canopy.
      const double edge = r / (kCellsCanopyRadius_km * (0.7 + 0.6 * n_edge));
      const double cover = 1.0 - smoothstep(0.4, 1.0, edge);
      const double hole = smoothstep(eye_top_km - 4.0, eye_top_km + 10.0, r);
      const double chi = phi + std::log(std::max(r, 1.0) / 60.0) / std::tan(kCellsOutflowPitch_rad) - 0.5 * spin;
      const double radial = 0.5 + 0.5 * std::cos(22.0 * chi + 4.0 * n_mid);
      const double transverse = 0.5 + 0.5 * std::cos(2.0 * kPi * r / 14.0 + 3.0 * std::sin(3.0 * phi) + 6.0 * n_large);
      double tex = (1.0 - smoothstep(100.0, 220.0, r) * (1.0 - radial * radial)) *
                   (1.0 - 0.6 * smoothstep(0.45, 0.85, edge) * (1.0 - transverse)) * (0.6 + 0.8 * n_mid);
      const double canopy = cover * hole * tex;
      // A domed top that sinks by 4.5 km and a layer that thins from 3 km to 0.2 km towards the edge.
      const double thin = smoothstep(0.2, 1.0, edge);
      const double canopy_top = 16.0 - 4.5 * thin + 1.5 * (n_mid - 0.5);
      col.canopy_top_km[c] = static_cast<float>(canopy_top);
      col.canopy_base_km[c] = static_cast<float>(canopy_top - 0.2 - 2.8 * (1.0 - thin) * (1.0 - thin));
      col.canopy[c] = static_cast<float>(canopy * smoothstep(0.12, 0.3, canopy) * (1.0 - 0.7 * thin));
    }
  });
  // Convective cells, rasterised serially (the dominant cell of a column sets its top).
  struct Cell {
    double x_km, y_km, radius_km, top_km, strength;
  };
  std::vector<Cell> cells;
  for (int a = 0; a < 3; ++a) {
    const double r0 = a < 2 ? 65.0 : 160.0, r1 = a < 2 ? 400.0 : 500.0;
    const double phi0 = a < 2 ? kPi * a : 0.5 * kPi;
    const double fade = a < 2 ? 1.0 : 0.75;
    double r = r0;
    for (int n = 0; r < r1; ++n) {
      const double h1 = noise_.hash(a, n, 21), h2 = noise_.hash(a, n, 22), h3 = noise_.hash(a, n, 23);
      const double h4 = noise_.hash(a, n, 24), h5 = noise_.hash(a, n, 25), h6 = noise_.hash(a, n, 26);
      r += (12.0 + 12.0 * h1) * std::sin(kCellsBandPitch_rad);
      if (h2 < 0.22) continue;  // a gap in the band
      const double phi =
          phi0 + spin - std::log(r / kCellsEyewallRadius_km) / std::tan(kCellsBandPitch_rad) + 10.0 * (h3 - 0.5) / r;
      const double outer = smoothstep(0.55 * r1, r1, r);
      const double life = 0.55 + 0.45 * std::sin(kPi * std::fmod(hours / 2.0 + h5, 1.0));
      const double top = 8.0 + 8.0 * std::pow(h6, 1.6) - 2.5 * outer;
      const double strength = (0.6 + 0.4 * h4) * life * fade * (1.0 - 0.4 * outer);
      cells.push_back({r * std::cos(phi), r * std::sin(phi), 3.5 + 5.5 * h4, top, strength});
      if (h3 < 0.5) {  // a feeder cell on the band's outer side
        const double rf = r + 8.0 + 5.0 * h5;
        cells.push_back(
            {rf * std::cos(phi - 0.05), rf * std::sin(phi - 0.05), 3.0 + 2.0 * h1, 4.0 + 3.0 * h2, 0.6 * strength});
      }
    }
  }
  // Shallow cumulus on a jittered lattice over the domain, clustered by a large-scale field.
  const double lx = (nx - 1) * dx_km, ly = (ny - 1) * dx_km;
  const auto p0 = static_cast<std::int64_t>(std::floor(-cx / kCellsCumulusSpacing_km)) - 1;
  const auto p1 = static_cast<std::int64_t>(std::ceil((lx - cx) / kCellsCumulusSpacing_km)) + 1;
  const auto q0 = static_cast<std::int64_t>(std::floor(-cy / kCellsCumulusSpacing_km)) - 1;
  const auto q1 = static_cast<std::int64_t>(std::ceil((ly - cy) / kCellsCumulusSpacing_km)) + 1;
  for (std::int64_t q = q0; q <= q1; ++q) {
    for (std::int64_t p = p0; p <= p1; ++p) {
      const double x = (double(p) + noise_.hash(p, q, 31)) * kCellsCumulusSpacing_km;
      const double y = (double(q) + noise_.hash(p, q, 32)) * kCellsCumulusSpacing_km;
      const double r = std::hypot(x, y);
      if (r < kCellsEyeRadius_km + 8.0) continue;  // the eye stays clear
      // A few in the moat; fields of them outside the subsiding ring around the storm, to ~650 km.
      const double field = smoothstep(0.35, 0.65, noise_.fbm(x / 200.0 + 80.0, y / 200.0 + 80.0, 3.0, 2));
      const double moat = 0.3 * smoothstep(50.0, 60.0, r) * (1.0 - smoothstep(75.0, 90.0, r));
      const double outside = (0.005 + 0.12 * field) * smoothstep(150.0, 300.0, r) * (1.0 - smoothstep(500.0, 650.0, r));
      if (noise_.hash(p, q, 33) > moat + outside) continue;
      const double h = noise_.hash(p, q, 34);
      const bool congestus = noise_.hash(p, q, 35) < 0.05;
      cells.push_back({x, y, 2.0 + 2.0 * h, congestus ? 3.5 + 1.5 * h : 1.1 + 1.0 * noise_.hash(p, q, 36),
                       0.35 + 0.25 * noise_.hash(p, q, 37)});
    }
  }
  for (const Cell& s : cells) {
    const double gi = (s.x_km + cx) / dx_km, gj = (s.y_km + cy) / dx_km, reach = 2.2 * s.radius_km / dx_km;
    const int i0 = std::max(0, static_cast<int>(std::ceil(gi - reach)));
    const int i1 = std::min(nx - 1, static_cast<int>(std::floor(gi + reach)));
    const int j0 = std::max(0, static_cast<int>(std::ceil(gj - reach)));
    const int j1 = std::min(ny - 1, static_cast<int>(std::floor(gj + reach)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
        const double g = gaussian(std::hypot(i * dx_km - cx - s.x_km, j * dx_km - cy - s.y_km), 0.0, s.radius_km);
        if (s.strength * g <= double(col.cell[c])) continue;
        col.cell[c] = static_cast<float>(s.strength * g);
        // A domed top: 0.78 of the summit's height above the base at half the peak (as the coarse storm's).
        col.cell_top_km[c] = static_cast<float>(0.6 + (s.top_km - 0.6) * std::pow(g, 0.35));
        col.cell_depth[c] = static_cast<float>(smoothstep(4.0, 8.0, s.top_km));
      }
    }
  }
  for (std::size_t c = 0; c < n2; ++c) {
    if (col.cell[c] < 0.05f) col.cell[c] = 0.0f;
  }
  return col;
}

// One point of the cellular hurricane from its column's structure (before the storm's intensity
// and the lateral boundary fade). The microphysics follow the coarse storm's: cloud water in the
// cores down to −25 °C, rain below the melting level under the deep cells and the shield, graupel
// in the deep cores, glaciated tops (ice and snow) above 6 km, the canopy ice only.
Writer::CellularPoint Writer::cellularPoint(const CellularColumns& col, std::size_t c, double r_km, double z_m,
                                            double terrain_m, double temperature_k) {
  CellularPoint p;
  const double zk = z_m / 1000.0;
  const double eye_r = kCellsEyeRadius_km + kCellsEyewallTilt_km_per_km * zk;
  const double clear_eye = smoothstep(eye_r - 3.0, eye_r + 3.0, r_km);
  const double x = r_km - (kCellsEyewallRadius_km + kCellsEyewallTilt_km_per_km * zk);
  // A sharp inner wall (the eye's edge), a wider outer flank.
  const double ew = double(col.eyewall[c]) * gaussian(x, 0.0, x < 0.0 ? 6.0 : 13.0);
  const double ew_top = col.eyewall_top_km[c], cell_top = col.cell_top_km[c];
  const double ew_core = ew * layer(zk, 0.5, ew_top, 0.4);
  const double cell = col.cell[c], depth = col.cell_depth[c];
  const double cell_core = cell * layer(zk, 0.6, cell_top, 0.3);
  const double core = std::max(ew_core, cell_core);
  const double shield_amount = col.shield[c];
  const double shield = shield_amount * layer(zk, 4.6, double(col.shield_top_km[c]), 0.3);
  const double canopy = double(col.canopy[c]) * layer(zk, col.canopy_base_km[c], col.canopy_top_km[c], 0.3);
  const bool warm = temperature_k > kFreezingPoint_k;
  const double freezing_mix = smoothstep(kFreezingPoint_k - 25.0, kFreezingPoint_k - 2.0, temperature_k);
  const double deep = std::max(ew, cell * depth);
  // Shallow cumulus are sub-grid at 2–4 km: a grid-mean cloud water of a few mg/kg (and a cloud
  // fraction below 1, from the same ramp as everywhere) instead of a deep core's 1.5 g/kg.
  const double liquid = ew_core >= cell_core ? 1.0 : 0.005 + 0.995 * depth;
  p.q_cloud = (1.5e-3 * core * liquid + 1.0e-4 * shield_amount * layer(zk, 3.0, 4.6, 0.2)) * freezing_mix;
  p.q_rain = (2.8e-3 * deep + 2.0e-4 * shield_amount) * layer(zk, -1.0, 4.6, 0.6) * (warm ? 1.0 : 0.2);
  p.q_graupel = 1.2e-3 * std::max(ew * layer(zk, 4.5, std::min(ew_top, 10.0), 0.8),
                                  cell * depth * layer(zk, 4.5, std::min(cell_top, 9.5), 0.8));
  p.q_hail = 3.0e-4 * ew * ew * layer(zk, 3.0, 7.5, 1.0);
  if (!warm) {
    p.q_ice = 4.0e-4 * core * smoothstep(6.0, 9.0, zk) + 5.0e-5 * shield * smoothstep(6.0, 8.0, zk) + 1.1e-4 * canopy;
    p.q_snow = 6.0e-4 * core * smoothstep(5.0, 7.0, zk) + 2.5e-4 * shield;  // the canopy is ice crystals only
  }
  // Updrafts in the eyewall (12 m/s) and the deep cells (8 m/s), weak ones in shallow cumulus,
  // mesoscale ascent in the shield above the melting level and descent below, subsidence in the eye.
  auto updraft = [&](double top) {
    return std::sin(kPi * std::clamp((zk - 0.5) / std::max(top - 0.5, 0.5), 0.0, 1.0));
  };
  p.w_m_per_s = 12.0 * ew * updraft(ew_top) + cell * (8.0 * depth + 1.5 * (1.0 - depth)) * updraft(cell_top) +
                0.3 * shield - 0.3 * shield_amount * layer(zk, 0.0, 4.4, 0.5) + 0.2 * canopy -
                0.8 * (1.0 - clear_eye) * layer(zk, 2.0, 14.0, 1.0);
  // TKE: the boundary layer (stronger under the eyewall's winds), the cores, the canopy and the shield.
  p.tke_m2_per_s2 =
      (0.4 + 1.2 * gaussian(r_km, kCellsEyewallRadius_km, 40.0)) * (1.0 - smoothstep(800.0, 1800.0, z_m - terrain_m)) +
      4.0 * core + 0.6 * canopy + 0.5 * shield;
  p.q_cloud *= clear_eye;
  p.q_rain *= clear_eye;
  p.q_ice *= clear_eye;
  p.q_snow *= clear_eye;
  p.q_graupel *= clear_eye;
  p.q_hail *= clear_eye;
  return p;
}

int Writer::defField(const std::string& name, const std::vector<int>& dims, const std::string& memory_order,
                     const std::string& description, const std::string& units, const std::string& stagger) {
  const int id = nc_.defVar(name, NC_FLOAT, dims);
  nc_.attInt(id, "FieldType", 104);
  nc_.attText(id, "MemoryOrder", memory_order);
  nc_.attText(id, "description", description);
  nc_.attText(id, "units", units);
  nc_.attText(id, "stagger", stagger);
  if (proj_.map_proj != 0 && dims.size() >= 3) nc_.attText(id, "coordinates", "XLONG XLAT XTIME");
  var_[name] = id;
  return id;
}

void Writer::defineFile() {
  const int d_time = nc_.defDim("Time", 0);
  const int d_str = nc_.defDim("DateStrLen", 19);
  const int d_we = nc_.defDim("west_east", std::size_t(g_.nx));
  const int d_sn = nc_.defDim("south_north", std::size_t(g_.ny));
  const int d_bt = nc_.defDim("bottom_top", std::size_t(g_.nz));
  const int d_bts = nc_.defDim("bottom_top_stag", std::size_t(g_.nz + 1));
  const int d_wes = nc_.defDim("west_east_stag", std::size_t(g_.nx + 1));
  const int d_sns = nc_.defDim("south_north_stag", std::size_t(g_.ny + 1));

  const int id_times = nc_.defVar("Times", NC_CHAR, {d_time, d_str});
  var_["Times"] = id_times;
  const int id_xtime = nc_.defVar("XTIME", NC_FLOAT, {d_time});
  nc_.attInt(id_xtime, "FieldType", 104);
  nc_.attText(id_xtime, "MemoryOrder", "0  ");
  nc_.attText(id_xtime, "description", "minutes since 2026-09-01 12:00:00");
  nc_.attText(id_xtime, "units", "minutes since 2026-09-01 12:00:00");
  nc_.attText(id_xtime, "stagger", "");
  var_["XTIME"] = id_xtime;

  if (proj_.map_proj != 0) {
    defField("XLAT", {d_time, d_sn, d_we}, "XY ", "LATITUDE, SOUTH IS NEGATIVE", "degree_north", "");
    defField("XLONG", {d_time, d_sn, d_we}, "XY ", "LONGITUDE, WEST IS NEGATIVE", "degree_east", "");
  }
  defField("ZNU", {d_time, d_bt}, "Z  ", "eta values on half (mass) levels", "", "");
  defField("ZNW", {d_time, d_bts}, "Z  ", "eta values on full (w) levels", "", "Z");
  defField("U", {d_time, d_bt, d_sn, d_wes}, "XYZ", "x-wind component", "m s-1", "X");
  defField("V", {d_time, d_bt, d_sns, d_we}, "XYZ", "y-wind component", "m s-1", "Y");
  defField("PH", {d_time, d_bts, d_sn, d_we}, "XYZ", "perturbation geopotential", "m2 s-2", "Z");
  defField("PHB", {d_time, d_bts, d_sn, d_we}, "XYZ", "base-state geopotential", "m2 s-2", "Z");
  defField("T", {d_time, d_bt, d_sn, d_we}, "XYZ", "perturbation potential temperature (theta-t0)", "K", "");
  defField("P", {d_time, d_bt, d_sn, d_we}, "XYZ", "perturbation pressure", "Pa", "");
  defField("PB", {d_time, d_bt, d_sn, d_we}, "XYZ", "BASE STATE PRESSURE", "Pa", "");
  defField("P_TOP", {d_time}, "0  ", "PRESSURE TOP OF THE MODEL", "Pa", "");
  defField("QVAPOR", {d_time, d_bt, d_sn, d_we}, "XYZ", "Water vapor mixing ratio", "kg kg-1", "");

  const bool thompson = spec_.scheme == WrfScheme::ThompsonLike;
  std::vector<const ParticleClass*> classes = {&kCloud, &kRain};
  if (thompson) {
    classes.insert(classes.end(), {&kIce, &kSnow, &kGraupel});
    if (spec_.include_hail) classes.push_back(&kHail);
  }
  for (const ParticleClass* c : classes) {
    defField(c->q_name, {d_time, d_bt, d_sn, d_we}, "XYZ", c->q_description, "kg kg-1", "");
  }
  if (thompson) {
    for (const ParticleClass* c : classes) {
      defField(c->n_name, {d_time, d_bt, d_sn, d_we}, "XYZ", c->n_description, "  kg-1", "");
    }
  }
  defField("HGT", {d_time, d_sn, d_we}, "XY ", "Terrain Height", "m", "");
  if (spec_.weather != WrfCase::Hurricane) {
    // As WRF ARW v4 writes them (Registry.EM_COMMON; TKE_PBL with a TKE-carrying PBL scheme).
    defField("W", {d_time, d_bts, d_sn, d_we}, "XYZ", "z-wind component", "m s-1", "Z");
    defField("TKE_PBL", {d_time, d_bt, d_sn, d_we}, "XYZ", "TKE from PBL", "m2 s-2", "");
    defField("CLDFRA", {d_time, d_bt, d_sn, d_we}, "XYZ", "CLOUD FRACTION", "", "");
  }

  // ---- global attributes as WRF ARW v4 writes them -------------------------------------------
  const int G = NC_GLOBAL;
  nc_.attText(G, "TITLE", " OUTPUT FROM WRF V4.5.2 MODEL");
  nc_.attText(G, "NEPHELE_SYNTHETIC",
              fmt::format("{} written by nephele-gen, seed {}",
                          spec_.weather == WrfCase::CoarseStorm      ? "coarse convective storm"
                          : spec_.weather == WrfCase::HurricaneCells ? "cellular hurricane"
                          : spec_.weather == WrfCase::AlpineStorm    ? "alpine convective storm"
                                                                     : "idealized hurricane",
                          spec_.seed));
  const std::string start = start_.wrfTimeString();
  nc_.attText(G, "START_DATE", start);
  nc_.attText(G, "SIMULATION_START_DATE", start);
  nc_.attInt(G, "WEST-EAST_GRID_DIMENSION", g_.nx + 1);
  nc_.attInt(G, "SOUTH-NORTH_GRID_DIMENSION", g_.ny + 1);
  nc_.attInt(G, "BOTTOM-TOP_GRID_DIMENSION", g_.nz + 1);
  nc_.attFloat(G, "DX", static_cast<float>(spec_.dx_m));
  nc_.attFloat(G, "DY", static_cast<float>(spec_.dx_m));
  nc_.attInt(G, "AERCU_OPT", 0);
  nc_.attText(G, "GRIDTYPE", "C");
  nc_.attInt(G, "DIFF_OPT", 1);
  nc_.attInt(G, "KM_OPT", 4);
  nc_.attInt(G, "DAMP_OPT", 3);
  nc_.attFloat(G, "DAMPCOEF", 0.2f);
  nc_.attInt(G, "MP_PHYSICS", thompson ? 8 : 3);
  nc_.attInt(G, "RA_LW_PHYSICS", 4);
  nc_.attInt(G, "RA_SW_PHYSICS", 4);
  nc_.attInt(G, "SF_SFCLAY_PHYSICS", 1);
  nc_.attInt(G, "SF_SURFACE_PHYSICS", 2);
  nc_.attInt(G, "BL_PBL_PHYSICS", spec_.weather != WrfCase::Hurricane ? 5 : 1);  // 5 = MYNN (carries TKE)
  nc_.attInt(G, "CU_PHYSICS", 0);
  nc_.attInt(G, "HYBRID_OPT", 0);
  nc_.attFloat(G, "ETAC", 0.0f);
  nc_.attInt(G, "WEST-EAST_PATCH_START_UNSTAG", 1);
  nc_.attInt(G, "WEST-EAST_PATCH_END_UNSTAG", g_.nx);
  nc_.attInt(G, "WEST-EAST_PATCH_START_STAG", 1);
  nc_.attInt(G, "WEST-EAST_PATCH_END_STAG", g_.nx + 1);
  nc_.attInt(G, "SOUTH-NORTH_PATCH_START_UNSTAG", 1);
  nc_.attInt(G, "SOUTH-NORTH_PATCH_END_UNSTAG", g_.ny);
  nc_.attInt(G, "SOUTH-NORTH_PATCH_START_STAG", 1);
  nc_.attInt(G, "SOUTH-NORTH_PATCH_END_STAG", g_.ny + 1);
  nc_.attInt(G, "BOTTOM-TOP_PATCH_START_UNSTAG", 1);
  nc_.attInt(G, "BOTTOM-TOP_PATCH_END_UNSTAG", g_.nz);
  nc_.attInt(G, "BOTTOM-TOP_PATCH_START_STAG", 1);
  nc_.attInt(G, "BOTTOM-TOP_PATCH_END_STAG", g_.nz + 1);
  nc_.attInt(G, "GRID_ID", 1);
  nc_.attInt(G, "PARENT_ID", 0);
  nc_.attInt(G, "I_PARENT_START", 1);
  nc_.attInt(G, "J_PARENT_START", 1);
  nc_.attInt(G, "PARENT_GRID_RATIO", 1);
  nc_.attFloat(G, "DT", static_cast<float>(6.0 * spec_.dx_m / 1000.0));
  const bool has_geo = proj_.map_proj != 0;
  nc_.attFloat(G, "CEN_LAT", has_geo ? static_cast<float>(spec_.centre_lat_deg) : 0.0f);
  nc_.attFloat(G, "CEN_LON", has_geo ? static_cast<float>(spec_.centre_lon_deg) : 0.0f);
  nc_.attFloat(G, "TRUELAT1", static_cast<float>(proj_.truelat1));
  nc_.attFloat(G, "TRUELAT2", static_cast<float>(proj_.truelat2));
  nc_.attFloat(G, "MOAD_CEN_LAT", has_geo ? static_cast<float>(spec_.centre_lat_deg) : 0.0f);
  nc_.attFloat(G, "STAND_LON", static_cast<float>(proj_.stand_lon));
  nc_.attFloat(G, "POLE_LAT", static_cast<float>(proj_.pole_lat));
  nc_.attFloat(G, "POLE_LON", static_cast<float>(proj_.pole_lon));
  nc_.attFloat(G, "GMT", static_cast<float>(start_.civil().hour));
  nc_.attInt(G, "JULYR", start_.civil().year);
  nc_.attInt(G, "JULDAY", start_.dayOfYear());
  nc_.attInt(G, "MAP_PROJ", proj_.map_proj);
  nc_.attText(G, "MAP_PROJ_CHAR", proj_.name);
  nc_.attText(G, "MMINLU", "MODIFIED_IGBP_MODIS_NOAH");
  nc_.attInt(G, "NUM_LAND_CAT", 21);
  nc_.attInt(G, "ISWATER", 17);
  nc_.attInt(G, "ISLAKE", 21);
  nc_.attInt(G, "ISICE", 15);
  nc_.attInt(G, "ISURBAN", 13);
  nc_.attInt(G, "ISOILWATER", 14);
  nc_.endDef();
}

void Writer::put3d(const std::string& name, int t, const std::vector<float>& data, int nz_var, int ny_var, int nx_var) {
  nc_.putFloat(var_.at(name), {std::size_t(t), 0, 0, 0},
               {1, std::size_t(nz_var), std::size_t(ny_var), std::size_t(nx_var)}, data.data());
}
void Writer::put2d(const std::string& name, int t, const std::vector<float>& data) {
  nc_.putFloat(var_.at(name), {std::size_t(t), 0, 0}, {1, std::size_t(g_.ny), std::size_t(g_.nx)}, data.data());
}

void Writer::writeTimestep(int t) {
  const int nx = g_.nx, ny = g_.ny, nz = g_.nz;
  const double dx = spec_.dx_m;
  const double hours = spec_.first_hour + t;
  double cx = 0.0, cy = 0.0;
  stormCentre(t, cx, cy);
  if (t == 0) {
    truth_.storm_centre_x_m = cx;
    truth_.storm_centre_y_m = cy;
  }
  // Intensifying hurricane; the coarse storm keeps only a weak mesoscale vortex (a third).
  // The alpine storm has none (no vortex, no warm core: the flow of alpineWind()).
  const bool alpine = spec_.weather == WrfCase::AlpineStorm;
  const double intensity = alpine ? 0.0 : (spec_.weather == WrfCase::CoarseStorm ? 0.3 : 1.0) * (0.85 + 0.05 * hours);

  const std::string time_string = start_.plusSeconds(3600.0 * double(spec_.first_hour + t)).wrfTimeString();
  truth_.times.push_back(time_string);
  nc_.putText(var_.at("Times"), {std::size_t(t), 0}, {1, 19}, time_string.c_str());
  const float xtime = static_cast<float>(60.0 * hours);
  nc_.putFloat(var_.at("XTIME"), {std::size_t(t)}, {1}, &xtime);
  const float ptop = static_cast<float>(kWrfModelTopPressure_pa);
  nc_.putFloat(var_.at("P_TOP"), {std::size_t(t)}, {1}, &ptop);
  {
    std::vector<float> znu(znu_.begin(), znu_.end()), znw(znw_.begin(), znw_.end());
    nc_.putFloat(var_.at("ZNU"), {std::size_t(t), 0}, {1, std::size_t(nz)}, znu.data());
    nc_.putFloat(var_.at("ZNW"), {std::size_t(t), 0}, {1, std::size_t(nz + 1)}, znw.data());
  }
  if (proj_.map_proj != 0) {
    put2d("XLAT", t, lat_);
    put2d("XLONG", t, lon_);
  }
  {
    std::vector<float> hgt(terrain_m_.begin(), terrain_m_.end());
    put2d("HGT", t, hgt);
  }

  // ---- thermodynamic state column by column ---------------------------------------------------
  const std::size_t n2 = g_.n2(), n3 = g_.n3();
  const std::size_t n3w = n2 * std::size_t(nz + 1);
  std::vector<float> ph(n3w), phb(n3w), p(n3), pb(n3), theta_pert(n3), qv(n3);
  std::vector<float> z_mass(n3), t_mass(n3), r_km(n2), phi_rad(n2);
  const double ptop_d = kWrfModelTopPressure_pa;
  if (spec_.keep_truth) {
    truth_.height_m.emplace_back(n3);
    truth_.pressure_pa.emplace_back(n3);
    truth_.temperature_k.emplace_back(n3);
  }
  // Columns are independent: rows in parallel (deterministic, every element written once).
  tbb::parallel_for(0, ny, [&](int j) {
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      const double ddx = i * dx - cx, ddy = j * dx - cy;
      const double r = std::hypot(ddx, ddy) / 1000.0;
      r_km[c] = static_cast<float>(r);
      phi_rad[c] = static_cast<float>(std::atan2(ddy, ddx));
      // Holland-like surface pressure deficit: dp0 (1 - exp(-(R_mw/r)^1.5)).
      const double rr = std::max(r, 1e-3);
      const double dp =
          intensity * kCentralPressureDeficit_pa * (1.0 - std::exp(-std::pow(kRadiusMaxWind_km / rr, 1.5)));
      const double hgt = terrain_m_[c];
      const double ps_base = standardPressurePa(hgt);
      const double ps = ps_base - dp;
      // Dry hydrostatic eta coordinate (Skamarock et al. 2019, WRF ARW v4 tech note §2.1, with
      // HYBRID_OPT = 0): p_d(eta) = eta (p_s - p_top) + p_top.
      const double z_surface_full = standardHeightM(ps);
      for (int k = 0; k <= nz; ++k) {
        const double pw_base = znw_[std::size_t(k)] * (ps_base - ptop_d) + ptop_d;
        const double pw = znw_[std::size_t(k)] * (ps - ptop_d) + ptop_d;
        const double zb = k == 0 ? hgt : standardHeightM(pw_base);
        // The perturbed column keeps its surface at the terrain: heights above it follow the
        // standard atmosphere's hydrostatic thickness between the perturbed pressures.
        const double z = k == 0 ? hgt : hgt + standardHeightM(pw) - z_surface_full;
        const std::size_t w = std::size_t(k) * n2 + c;
        phb[w] = static_cast<float>(kWrfGravity_m_per_s2 * zb);
        ph[w] = static_cast<float>(kWrfGravity_m_per_s2 * z - double(phb[w]));
      }
      for (int k = 0; k < nz; ++k) {
        const std::size_t m = std::size_t(k) * n2 + c;
        const double eta = znu_[std::size_t(k)];
        const double p_base = eta * (ps_base - ptop_d) + ptop_d;
        const double p_full = eta * (ps - ptop_d) + ptop_d;
        pb[m] = static_cast<float>(p_base);
        p[m] = static_cast<float>(p_full - p_base);
        // Heights of mass levels as a loader sees them: average of the staggered geopotentials.
        const double z_lo = (double(ph[m]) + double(phb[m])) / kWrfGravity_m_per_s2;
        const double z_hi = (double(ph[m + n2]) + double(phb[m + n2])) / kWrfGravity_m_per_s2;
        const double z = 0.5 * (z_lo + z_hi);
        // Warm core: +8 K at 9 km in the eye, decaying over the radius of maximum wind.
        const double temp = standardTemperatureK(z) + intensity * kWarmCore_k *
                                                          gaussian(r, 0.0, 1.5 * kRadiusMaxWind_km) *
                                                          gaussian(z, 9000.0, 3500.0);
        const double theta = temp * std::pow(kWrfReferencePressure_pa / p_full, kRdOverCp);
        theta_pert[m] = static_cast<float>(theta - kWrfThetaOffset_k);
        z_mass[m] = static_cast<float>(z);
        t_mass[m] = static_cast<float>(temp);
        // Relative humidity 90 % in the storm, 60 % outside, drying above 10 km.
        const double rh = (0.6 + 0.3 * gaussian(r, 0.0, 300.0)) * (1.0 - 0.8 * smoothstep(8000.0, 14000.0, z));
        const double e = rh * saturationVapourPressurePa(temp);
        qv[m] = static_cast<float>(kEpsilonRdOverRv * e / std::max(p_full - e, 1.0));
        if (spec_.keep_truth) {
          truth_.height_m.back()[m] = z;
          truth_.pressure_pa.back()[m] = double(pb[m]) + double(p[m]);
          // The truth is the temperature a loader recovers from the stored float fields.
          const double p_stored = double(pb[m]) + double(p[m]);
          truth_.temperature_k.back()[m] =
              (double(theta_pert[m]) + kWrfThetaOffset_k) * std::pow(p_stored / kWrfReferencePressure_pa, kRdOverCp);
        }
      }
    }
  });
  put3d("PH", t, ph, nz + 1, ny, nx);
  put3d("PHB", t, phb, nz + 1, ny, nx);
  put3d("P", t, p, nz, ny, nx);
  put3d("PB", t, pb, nz, ny, nx);
  put3d("T", t, theta_pert, nz, ny, nx);
  put3d("QVAPOR", t, qv, nz, ny, nx);
  ph = {};
  phb = {};

  // The alpine storm's columns at this step of its life cycle (their in-cloud wind is written next).
  const AlpineStage alpine_stage = alpine ? alpineStage(t, spec_.ntimes) : AlpineStage{};
  AlpineColumns alpine_columns;
  if (alpine) alpine_columns = alpineColumns(alpine_, noise_, alpine_stage);

  // ---- winds: Rankine-like tangential wind, cyclonic, decaying with height ---------------------
  auto tangential = [&](double x_m, double y_m, double z_m, double& u, double& v) {
    if (spec_.steering_wind_only) {
      u = kStormMotionX_m_per_s;
      v = kStormMotionY_m_per_s;
      return;
    }
    const double ddx = x_m - cx, ddy = y_m - cy;
    const double r = std::max(std::hypot(ddx, ddy) / 1000.0, 1e-3);
    const double vt = intensity * kMaxWind_m_per_s *
                      (r < kRadiusMaxWind_km ? r / kRadiusMaxWind_km : std::pow(kRadiusMaxWind_km / r, 0.6)) *
                      std::max(0.0, 1.0 - z_m / 16000.0);
    const double phi = std::atan2(ddy, ddx);
    u = -vt * std::sin(phi) + kStormMotionX_m_per_s;
    v = vt * std::cos(phi) + kStormMotionY_m_per_s;
    if (alpine) alpineWind(z_m, u, v);
  };
  {
    std::vector<float> u(std::size_t(nx + 1) * std::size_t(ny) * std::size_t(nz));
    std::vector<float> v(std::size_t(nx) * std::size_t(ny + 1) * std::size_t(nz));
    for (int k = 0; k < nz; ++k) {
      for (int j = 0; j < ny; ++j) {
        for (int i = 0; i <= nx; ++i) {
          const double z = z_mass[g_.at(std::min(i, nx - 1), j, k)];
          double uu = 0, vv = 0;
          tangential((i - 0.5) * dx, j * dx, z, uu, vv);
          if (alpine_stage.life_cycle) {
            alpineCloudWind(alpine_columns, std::size_t(j) * std::size_t(nx) + std::size_t(std::min(i, nx - 1)), z, uu,
                            vv);
          }
          u[(std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx + 1) + std::size_t(i)] =
              static_cast<float>(uu);
        }
      }
      for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i < nx; ++i) {
          const double z = z_mass[g_.at(i, std::min(j, ny - 1), k)];
          double uu = 0, vv = 0;
          tangential(i * dx, (j - 0.5) * dx, z, uu, vv);
          if (alpine_stage.life_cycle) {
            alpineCloudWind(alpine_columns, std::size_t(std::min(j, ny - 1)) * std::size_t(nx) + std::size_t(i), z, uu,
                            vv);
          }
          v[(std::size_t(k) * std::size_t(ny + 1) + std::size_t(j)) * std::size_t(nx) + std::size_t(i)] =
              static_cast<float>(vv);
        }
      }
    }
    put3d("U", t, u, nz, ny, nx + 1);
    put3d("V", t, v, nz, ny + 1, nx);
  }

  // ---- hydrometeors ---------------------------------------------------------------------------
  // Structural weights per mass point, from which every class is shaped.
  std::vector<float> qc(n3), qr(n3), qi(n3), qs(n3), qg(n3), qh(n3);
  // Lateral boundary zone: WRF's outer rows are forced towards the driving model (specified and
  // relaxation zones, spec_bdy_width = 5 by default), which for an idealised run carries no
  // condensate; hydrometeors fade to zero over the outer 10 % of the domain (at least five rows),
  // so a storm wider than the domain ends softly instead of being cut by the box.
  const double lx_km = (nx - 1) * dx / 1000.0, ly_km = (ny - 1) * dx / 1000.0;
  // (The alpine storm's valleys reach the domain's edge: its zone is the five rows alone.)
  const double boundary_km = alpine ? 5.0 * dx / 1000.0 : std::max(5.0 * dx / 1000.0, 0.1 * std::min(lx_km, ly_km));
  const bool storm = spec_.weather == WrfCase::CoarseStorm;
  const bool cellular = spec_.weather == WrfCase::HurricaneCells;
  std::vector<float> w_stag, tke, cldfra;
  std::vector<StormCell> cells;
  CellularColumns columns;
  if (cellular) columns = cellularColumns(hours, cx, cy);
  if (storm || cellular || alpine) {
    if (storm) cells = stormCells(hours);
    w_stag.assign(n2 * std::size_t(nz + 1), 0.0f);
    tke.assign(n3, 0.0f);
    cldfra.assign(n3, 0.0f);
  }
  tbb::parallel_for(0, nz, [&](int k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
        const std::size_t m = g_.at(i, j, k);
        // The cases with W/TKE_PBL/CLDFRA: every class scaled (intensity and the boundary fade),
        // W by the fade alone.
        auto store = [&](const auto& pt, double scale, double w_scale, double hail) {
          qc[m] = static_cast<float>(scale * pt.q_cloud);
          qr[m] = static_cast<float>(scale * pt.q_rain);
          qi[m] = static_cast<float>(scale * pt.q_ice);
          qs[m] = static_cast<float>(scale * pt.q_snow);
          qg[m] = static_cast<float>(scale * pt.q_graupel);
          qh[m] = static_cast<float>(hail);
          tke[m] = static_cast<float>(pt.tke_m2_per_s2);
          // Cloud fraction from the condensate (WRF's cloud-fraction schemes ramp it with the
          // cloud water and ice content): 1 in resolved cloud, a ramp over 1e-6 .. 5e-5 kg/kg.
          cldfra[m] = static_cast<float>(smoothstep(1e-6, 5e-5, double(qc[m]) + double(qi[m]) + double(qs[m])));
          // W on the staggered level below this mass point (and the model top above the last).
          w_stag[std::size_t(k) * n2 + c] = static_cast<float>(w_scale * pt.w_m_per_s);
        };
        if (storm || alpine || cellular) {
          const double x_km = i * dx / 1000.0, y_km = j * dx / 1000.0;
          const double inside = smoothstep(0.0, boundary_km, std::min({x_km, lx_km - x_km, y_km, ly_km - y_km}));
          if (storm) {
            store(stormPoint(cells, i, j, x_km, y_km, z_mass[m], terrain_m_[c], t_mass[m], hours), inside, inside, 0.0);
          } else if (alpine) {
            store(alpinePoint(alpine_columns, c, z_mass[m], terrain_m_[c], t_mass[m]), inside, inside, 0.0);
          } else {
            const CellularPoint cp = cellularPoint(columns, c, r_km[c], z_mass[m], terrain_m_[c], t_mass[m]);
            const double scale = intensity * inside;
            store(cp, scale, inside, spec_.include_hail ? scale * cp.q_hail : 0.0);
          }
          continue;
        }
        const double r = r_km[c], phi = phi_rad[c];
        const double z = z_mass[m];  // m above MSL
        const double zk = z / 1000.0;
        const double temp = t_mass[m];
        const double x_km = i * dx / 1000.0, y_km = j * dx / 1000.0;
        const double n = noise_.fbm(x_km / 30.0, y_km / 30.0, 0.35 * hours + zk / 4.0, 3);
        const double texture = 0.55 + 0.9 * n;

        const double eye = smoothstep(kEyeClearRadius_km * 0.6, kEyeClearRadius_km * 1.4, r);
        const double r_eyewall = kRadiusMaxWind_km + kEyewallTilt_km_per_km * zk;
        const double eyewall = eye * gaussian(r, r_eyewall, 14.0) * (0.75 + 0.25 * std::cos(phi - 0.3 * hours));
        // Logarithmic spiral rainbands: phase psi = phi - omega t - ln(r / R_mw) / tan(pitch).
        const double psi = phi - kBandRotation_rad_per_h * hours -
                           std::log(std::max(r, 1.0) / kRadiusMaxWind_km) / std::tan(kSpiralPitch_rad);
        double arm = psi * kSpiralArms / (2.0 * kPi);
        arm -= std::round(arm);
        const double bands = gaussian(arm, 0.0, 0.13) * smoothstep(60.0, 95.0, r) * gaussian(r, 0.0, 260.0);
        const double stratiform = 0.25 * smoothstep(50.0, 80.0, r) * gaussian(r, 0.0, 180.0);
        const double convective = std::max(eyewall, 0.8 * bands * texture);

        const bool warm = temp > kFreezingPoint_k;
        const double freezing_mix = smoothstep(kFreezingPoint_k - 25.0, kFreezingPoint_k - 2.0, temp);  // 1 when warm
        double q_cloud = 1.3e-3 * convective * layer(zk, 0.9, convective == eyewall ? 9.0 : 6.0, 0.6) * freezing_mix;
        q_cloud += 2.5e-4 * (1.0 - eye) * gaussian(r, 0.0, 25.0) * layer(zk, 0.8, 1.6, 0.3);  // eye stratocumulus
        double q_rain = (2.6e-3 * convective + 1.5e-4 * stratiform * texture) * layer(zk, -1.0, 4.3, 0.7);
        if (!warm) q_rain *= 0.2;
        const double q_graupel = 1.4e-3 * eyewall * texture * layer(zk, 4.5, 8.5, 1.0);
        // Central dense overcast: an outflow anvil of ~200 km e-folding radius, thinning towards
        // the eye so the eye stays open from above (the storm's signature in satellite imagery).
        // Rising ice tops reach the standard heights at the file's last timestep.
        const double rise_km = spec_.anvil_rise_km_per_h * (hours - double(spec_.first_hour + spec_.ntimes - 1));
        const double anvil = eye * gaussian(r, 0.0, 200.0) * (0.65 + 0.35 * std::cos(phi + r / 90.0 - 0.2 * hours)) *
                             layer(zk, 11.0 + rise_km, 13.8 + rise_km, 1.0) * texture;
        const double q_ice =
            (3.0e-4 * eyewall * layer(zk, 7.0, 14.5 + rise_km, 1.0) + 1.6e-4 * anvil) * (warm ? 0.0 : 1.0);
        const double q_snow = (7.0e-4 * convective * layer(zk, 5.5, 11.0, 1.0) +
                               2.0e-4 * stratiform * layer(zk, 5.0, 9.0, 1.0) + 0.6e-4 * anvil) *
                              (warm ? 0.0 : 1.0);
        const double q_hail = spec_.include_hail ? 3.0e-4 * eyewall * eyewall * layer(zk, 3.0, 7.5, 1.0) : 0.0;

        const double inside = smoothstep(0.0, boundary_km, std::min({x_km, lx_km - x_km, y_km, ly_km - y_km}));
        const double scale = intensity * inside;
        qc[m] = static_cast<float>(scale * q_cloud);
        qr[m] = static_cast<float>(scale * q_rain);
        qi[m] = static_cast<float>(scale * q_ice);
        qs[m] = static_cast<float>(scale * q_snow);
        qg[m] = static_cast<float>(scale * q_graupel);
        qh[m] = static_cast<float>(scale * q_hail);
      }
    }
  });
  if (storm || cellular || alpine) {
    put3d("W", t, w_stag, nz + 1, ny, nx);
    put3d("TKE_PBL", t, tke, nz, ny, nx);
    put3d("CLDFRA", t, cldfra, nz, ny, nx);
  }
  if (spec_.scheme == WrfScheme::Wsm3Like) {
    // WSM3 (Hong et al. 2004) carries no separate ice: QCLOUD holds cloud ice and QRAIN holds
    // snow (and everything precipitating) below 0 °C.
    for (std::size_t m = 0; m < n3; ++m) {
      qc[m] += qi[m];
      qr[m] += qs[m] + qg[m] + qh[m];
    }
    put3d("QCLOUD", t, qc, nz, ny, nx);
    put3d("QRAIN", t, qr, nz, ny, nx);
    return;
  }
  struct Out {
    const ParticleClass* cls;
    const std::vector<float>* q;
  };
  std::vector<Out> outs = {{&kCloud, &qc}, {&kRain, &qr}, {&kIce, &qi}, {&kSnow, &qs}, {&kGraupel, &qg}};
  if (spec_.include_hail) outs.push_back({&kHail, &qh});
  std::vector<float> number(n3);
  for (std::size_t o = 0; o < outs.size(); ++o) {
    const Out& out = outs[o];
    put3d(out.cls->q_name, t, *out.q, nz, ny, nx);
    // N = q / m_p with m_p = 4/3 pi r^3 rho_p; the radius varies +-20 % with deterministic noise.
    tbb::parallel_for(std::size_t(0), n3, [&](std::size_t m) {
      const double q = (*out.q)[m];
      if (q <= 0.0) {
        number[m] = 0.0f;
        return;
      }
      const double jitter = 0.8 + 0.4 * noise_.hash(static_cast<std::int64_t>(m), static_cast<std::int64_t>(o), t);
      const double radius = out.cls->radius_m * jitter;
      const double particle_mass = 4.0 / 3.0 * kPi * radius * radius * radius * out.cls->density_kg_per_m3;
      number[m] = static_cast<float>(q / particle_mass);
    });
    put3d(out.cls->n_name, t, number, nz, ny, nx);
  }
}

WrfTruth Writer::run() {
  g_ = Grid{spec_.nx, spec_.ny, spec_.nz};
  truth_.nx = g_.nx;
  truth_.ny = g_.ny;
  truth_.nz = g_.nz;
  truth_.ntimes = spec_.ntimes;
  truth_.map_proj = proj_.map_proj;
  truth_.mp_physics = spec_.scheme == WrfScheme::ThompsonLike ? 8 : 3;
  truth_.generator_proj_definition = proj_.proj_definition;

  // Eta levels, thinner near the ground: eta(s) = 1 - (0.55 s + 0.45 s^2), s = k / nz.
  znw_.resize(std::size_t(g_.nz + 1));
  for (int k = 0; k <= g_.nz; ++k) {
    const double s = double(k) / g_.nz;
    znw_[std::size_t(k)] = 1.0 - (0.55 * s + 0.45 * s * s);
  }
  znw_.back() = 0.0;
  znu_.resize(std::size_t(g_.nz));
  for (int k = 0; k < g_.nz; ++k) znu_[std::size_t(k)] = 0.5 * (znw_[std::size_t(k)] + znw_[std::size_t(k + 1)]);

  // A small island with a 700 m peak west of the storm track.
  terrain_m_.resize(g_.n2());
  const double lx = (g_.nx - 1) * spec_.dx_m, ly = (g_.ny - 1) * spec_.dx_m;
  for (int j = 0; j < g_.ny; ++j) {
    for (int i = 0; i < g_.nx; ++i) {
      const double x = i * spec_.dx_m - 0.25 * lx, y = j * spec_.dx_m - 0.65 * ly;
      const double h = 700.0 * std::exp(-(x * x + 0.5 * y * y) / (45000.0 * 45000.0));
      terrain_m_[std::size_t(j) * std::size_t(g_.nx) + std::size_t(i)] = h < 1.0 ? 0.0 : h;
    }
  }
  if (spec_.weather == WrfCase::AlpineStorm) {
    alpine_ = alpineTerrain(g_.nx, g_.ny, spec_.dx_m, noise_);
    terrain_m_ = alpine_.height_m;
  }
  truth_.terrain_m = terrain_m_;

  // Geolocation of mass points: XLAT/XLONG computed with PROJ from the projection, the domain
  // centre ((nx-1)/2, (ny-1)/2) at (CEN_LAT, CEN_LON) as in WRF d01 domains.
  if (proj_.map_proj != 0) {
    // (the definitions of projectionSetup() name WRF's sphere, +R=kWrfEarthRadius_m)
    const geo::MapProjection projection(proj_.proj_definition);
    const glm::dvec2 centre = projection.forward({spec_.centre_lon_deg, spec_.centre_lat_deg});
    const double xc = centre.x, yc = centre.y;
    const double step = proj_.geographic ? spec_.dx_m / (kWrfEarthRadius_m * kPi / 180.0) : spec_.dx_m;
    lat_.resize(g_.n2());
    lon_.resize(g_.n2());
    truth_.lat_deg.resize(g_.n2());
    truth_.lon_deg.resize(g_.n2());
    for (int j = 0; j < g_.ny; ++j) {
      for (int i = 0; i < g_.nx; ++i) {
        const std::size_t c = std::size_t(j) * std::size_t(g_.nx) + std::size_t(i);
        const auto [lon, lat] =
            projection.inverse({xc + (i - 0.5 * (g_.nx - 1)) * step, yc + (j - 0.5 * (g_.ny - 1)) * step});
        truth_.lat_deg[c] = lat;
        truth_.lon_deg[c] = lon;
        lat_[c] = static_cast<float>(lat);
        lon_[c] = static_cast<float>(lon);
      }
    }
    // The Gaussian mountain at its lon/lat: forward through the same projection to grid metres.
    const GaussianMountain& mt = spec_.mountain;
    if (mt.height_m != 0.0) {
      const glm::dvec2 at = projection.forward({mt.lon_deg, mt.lat_deg});
      const double mx = ((at.x - xc) / step + 0.5 * (g_.nx - 1)) * spec_.dx_m;
      const double my = ((at.y - yc) / step + 0.5 * (g_.ny - 1)) * spec_.dx_m;
      for (int j = 0; j < g_.ny; ++j) {
        for (int i = 0; i < g_.nx; ++i) {
          const double r2 =
              (i * spec_.dx_m - mx) * (i * spec_.dx_m - mx) + (j * spec_.dx_m - my) * (j * spec_.dx_m - my);
          terrain_m_[std::size_t(j) * std::size_t(g_.nx) + std::size_t(i)] +=
              mt.height_m * std::exp(-r2 / (2.0 * mt.sigma_m * mt.sigma_m));
        }
      }
      truth_.terrain_m = terrain_m_;
      truth_.mountain_x_m = mx;
      truth_.mountain_y_m = my;
    }
  } else if (spec_.mountain.height_m != 0.0) {
    throw UsageError("a mountain at a lon/lat needs a map projection; the Cartesian grid has none");
  }

  defineFile();
  for (int t = 0; t < spec_.ntimes; ++t) writeTimestep(t);
  nc_.close();
  return truth_;
}

}  // namespace

WrfHurricaneSpec coarseStormSpec() {
  WrfHurricaneSpec s;
  s.nx = 72;
  s.ny = 64;
  s.nz = 30;
  s.dx_m = 10000.0;
  s.ntimes = 2;
  s.weather = WrfCase::CoarseStorm;
  s.format = NcFormat::Netcdf4Deflate;
  return s;
}

WrfHurricaneSpec alpineStormSpec() {
  WrfHurricaneSpec s;
  s.nx = 160;
  s.ny = 128;
  s.nz = 50;
  s.dx_m = 3000.0;
  s.ntimes = 1;
  s.weather = WrfCase::AlpineStorm;
  s.format = NcFormat::Netcdf4Deflate;
  s.centre_lon_deg = 10.5;
  s.centre_lat_deg = 46.4;
  return s;
}

std::pair<int, int> writeAlpineDem(const WrfHurricaneSpec& spec, double pixel_m, const std::string& path) {
  if (spec.projection == WrfProjection::Cartesian || !(pixel_m > 0.0) || pixel_m > spec.dx_m) {
    throw UsageError(fmt::format("{}: the alpine DEM needs a map projection and a pixel in (0, DX]", path));
  }
  const ProjectionSetup proj = projectionSetup(spec.projection, spec.centre_lon_deg, spec.centre_lat_deg);
  if (proj.geographic) throw UsageError(fmt::format("{}: the alpine DEM needs a projected (metre) grid", path));
  const geo::MapProjection projection(proj.proj_definition);
  const glm::dvec2 centre = projection.forward({spec.centre_lon_deg, spec.centre_lat_deg});
  // Projected metres of mass point (0, 0), as Writer::run() places XLAT/XLONG.
  const double x0 = centre.x - 0.5 * (spec.nx - 1) * spec.dx_m, y0 = centre.y - 0.5 * (spec.ny - 1) * spec.dx_m;
  const ValueNoise noise(spec.seed);
  const AlpineTerrain t = alpineTerrain(spec.nx, spec.ny, spec.dx_m, noise);
  // The pixels cover the model's cells: from half a cell west/south of the first mass point to
  // half a cell beyond the last.
  const int w = static_cast<int>(std::ceil(spec.nx * spec.dx_m / pixel_m));
  const int h = static_cast<int>(std::ceil(spec.ny * spec.dx_m / pixel_m));
  std::vector<float> heights(std::size_t(w) * std::size_t(h));
  tbb::parallel_for(0, h, [&](int j) {
    const double y_km = (spec.ny - 0.5) * spec.dx_m / 1000.0 - (j + 0.5) * pixel_m / 1000.0;  // row 0 north
    for (int i = 0; i < w; ++i) {
      const double x_km = -0.5 * spec.dx_m / 1000.0 + (i + 0.5) * pixel_m / 1000.0;
      heights[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
          static_cast<float>(sampleAlpineTerrain(t, noise, x_km, y_km, 6).height_m);
    }
  });
  const std::array<double, 6> gt = {
      x0 - 0.5 * spec.dx_m, pixel_m, 0.0, y0 + (spec.ny - 0.5) * spec.dx_m, 0.0, -pixel_m};
  writeHeightsGeoTiff(
      path, w, h, heights, gt, proj.proj_definition,
      "height above sea level (generated: nephele-gen wrf --case alpine-storm --dem)",
      fmt::format("nephele-gen wrf --case alpine-storm --seed {} (synthesis, not a survey)", spec.seed));
  return {w, h};
}

WrfTruth writeWrfHurricane(const WrfHurricaneSpec& spec, const std::string& path) {
  if (spec.nx < 1 || spec.ny < 1 || spec.nz < 1 || spec.ntimes < 1 || !(spec.dx_m > 0.0) ||
      !(spec.mountain.sigma_m > 0.0) || !std::isfinite(spec.mountain.height_m)) {
    throw UsageError(
        fmt::format("{}: hurricane grid must have nx, ny, nz, ntimes >= 1 and dx > 0; a mountain sigma > 0", path));
  }
  const double lat = spec.centre_lat_deg, lon = spec.centre_lon_deg;
  if (!(std::abs(lat) <= 80.0) || !(std::abs(lon) <= 180.0)) {
    throw UsageError(fmt::format("{}: the domain centre must be a longitude in [-180, 180] and a latitude in "
                                 "[-80, 80] (got {}, {})",
                                 path, lon, lat));
  }
  if (spec.projection == WrfProjection::Lambert && std::abs(lat) < 10.0) {
    throw UsageError(fmt::format("{}: a Lambert domain needs its centre at least 10 degrees from the equator (its "
                                 "true latitudes are 5 degrees either side; got latitude {}): use --proj mercator",
                                 path, lat));
  }
  if (spec.projection == WrfProjection::PolarStereographic && lat < 10.0) {
    throw UsageError(fmt::format(
        "{}: the polar stereographic domain is projected from the north pole: its centre needs a latitude >= 10 "
        "(got {})",
        path, lat));
  }
  Writer writer(spec, path);
  return writer.run();
}

std::pair<double, double> stormCentreLonLat(const WrfTruth& truth, double dx_m) {
  if (truth.lon_deg.empty()) return {std::nan(""), std::nan("")};
  const double fi = truth.storm_centre_x_m / dx_m, fj = truth.storm_centre_y_m / dx_m;
  const int i = static_cast<int>(std::floor(fi)), j = static_cast<int>(std::floor(fj));
  const double a = fi - i, b = fj - j;
  auto lerp = [&](const std::vector<double>& f) {
    auto at = [&](int ii, int jj) { return f[std::size_t(jj) * std::size_t(truth.nx) + std::size_t(ii)]; };
    return (1 - a) * (1 - b) * at(i, j) + a * (1 - b) * at(i + 1, j) + (1 - a) * b * at(i, j + 1) +
           a * b * at(i + 1, j + 1);
  };
  return {lerp(truth.lon_deg), lerp(truth.lat_deg)};
}

}  // namespace nph::datagen

#pragma once
// Idealized hurricane written as a convention-exact WRF ARW `wrfout` file through NetCDF-C.
// A vortex with a clear eye, an outward-tilted eyewall, two logarithmic spiral rainbands and an
// anvil of ice outflow aloft, drifting north-west and intensifying over hourly timesteps, on
// terrain-following dry-hydrostatic eta levels over a small island, in the standard atmosphere.
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "nc_writer.h"

namespace nph::datagen {

enum class WrfProjection {
  Lambert,             ///< MAP_PROJ = 1
  PolarStereographic,  ///< MAP_PROJ = 2
  Mercator,            ///< MAP_PROJ = 3
  LatLon,              ///< MAP_PROJ = 6, unrotated (POLE_LAT = 90)
  RotatedLatLon,       ///< MAP_PROJ = 6, rotated pole centred on the domain
  Cartesian            ///< MAP_PROJ = 0: idealized run without XLAT/XLONG
};

/// What the hydrometeor fields show (the grid, thermodynamics and winds are shared).
enum class WrfCase {
  Hurricane,    ///< the idealized hurricane (smooth, for the demo and the goldens)
  CoarseStorm,  ///< issue 13: convective cells + stratiform shield on a coarse grid, with W, TKE_PBL, CLDFRA
  /// issues 13/14: the hurricane as 2–4 km model output shows it (make demo): a clear eye in a tilted
  /// eyewall of convective towers with overshooting tops, spiral rainbands of discrete cells with
  /// gaps, a stratiform shield of varied depth, a banded outflow cirrus canopy thinning at its edge,
  /// shallow cumulus in the moat and outside; with W, TKE_PBL and CLDFRA
  HurricaneCells,
  /// issues 13/14: a 3 km convective storm over a generated mountain range (make demo's terrain
  /// shot, data_tools/wrf_alpine.h): HGT with ridges and draining valleys, orographic towers over
  /// the crests with anvils, a lee deck, cumulus over the slopes, valley fog; W, TKE_PBL, CLDFRA
  AlpineStorm
};

enum class WrfScheme {
  ThompsonLike,  ///< MP_PHYSICS = 8: QCLOUD QRAIN QICE QSNOW QGRAUP + number concentrations
  Wsm3Like       ///< MP_PHYSICS = 3: QCLOUD/QRAIN only, frozen condensate inside them below 0 °C
};

/// A Gaussian mountain added to the terrain (issue 14's placement test: "a generated storm over a
/// generated Gaussian mountain at a known lon/lat"): HGT += height·exp(−r²/(2σ²)), r the grid-metric
/// distance [m] from the mass-point position of (lon, lat) (through the file's own projection).
struct GaussianMountain {
  double lon_deg = 0.0, lat_deg = 0.0;
  double height_m = 0.0;  ///< 0: no mountain
  double sigma_m = 30000.0;
};

struct WrfHurricaneSpec {
  int nx = 40, ny = 36, nz = 20;  ///< mass points (west_east, south_north, bottom_top)
  int ntimes = 6;                 ///< hourly timesteps in this file
  int first_hour = 0;             ///< hours after 2026-09-01_12:00:00 of the first timestep
  double dx_m = 15000.0;          ///< grid spacing DX = DY [m]
  WrfProjection projection = WrfProjection::Lambert;
  WrfScheme scheme = WrfScheme::ThompsonLike;
  bool include_hail = false;  ///< add QHAIL/QNHAIL (zero outside the eyewall core)
  std::uint64_t seed = 1;
  NcFormat format = NcFormat::Classic64;
  bool keep_truth = false;  ///< fill WrfTruth's 3-D fields (tests; costs memory)
  WrfCase weather = WrfCase::Hurricane;
  GaussianMountain mountain;  ///< none by default (height 0); needs a projection (not Cartesian)
  /// The domain centre (CEN_LON, CEN_LAT) [deg]: the mass-point grid's middle lies there, and the
  /// projection follows it (Lambert's true latitudes 5° either side, the standard longitude 2° west,
  /// Mercator's true latitude 2.5° south). The default is the sample storm's place east of the
  /// Bahamas (over the sea); issue 14's terrain demo moves it over the Alps (`nephele-gen wrf --centre`).
  double centre_lon_deg = -75.0, centre_lat_deg = 25.0;
  /// The hurricane's ice tops (eyewall ice and outflow anvil) rise by this much per hour and
  /// reach their standard heights at the file's last timestep (0: steady tops). A series whose cloud top rises crops
  /// each timestep converted on the fly to a different column (issue 18: `animate` straight on such a wrfout).
  double anvil_rise_km_per_h = 0.0;
  /// U, V are the storm's drift alone ((−4, 3) m/s everywhere, no vortex): the wind the coarse
  /// storm's cells move with, so the file's wind describes how its cells move between timesteps
  /// (motion-compensated blending, docs/animation.md; its stratiform shield stays in place).
  bool steering_wind_only = false;
};

/// What the generator wrote, in double precision, to check loaders against.
struct WrfTruth {
  int nx = 0, ny = 0, nz = 0, ntimes = 0;
  int map_proj = 0;
  int mp_physics = 0;
  std::string generator_proj_definition;  ///< the PROJ string used to compute XLAT/XLONG
  std::vector<std::string> times;         ///< WRF Times strings
  /// Per timestep, layout (k * ny + j) * nx + i, mass points; only with keep_truth.
  std::vector<std::vector<double>> height_m, pressure_pa, temperature_k;
  std::vector<double> terrain_m;                          ///< nx*ny
  std::vector<double> lat_deg, lon_deg;                   ///< nx*ny; empty for Cartesian
  double storm_centre_x_m = 0.0, storm_centre_y_m = 0.0;  ///< first timestep, from grid point 0
  /// The mountain's summit in grid metres from mass point (0, 0) (NaN without a mountain).
  double mountain_x_m = std::numeric_limits<double>::quiet_NaN(),
         mountain_y_m = std::numeric_limits<double>::quiet_NaN();
};

/// The storm centre's (lon, lat) [deg] at the first timestep: the truth's XLONG/XLAT interpolated
/// bilinearly between the mass points around storm_centre_{x,y}_m (grid spacing `dx_m`). NaN for
/// Cartesian grids (no lon/lat).
std::pair<double, double> stormCentreLonLat(const WrfTruth& truth, double dx_m);

/// The coarse storm of issue 13 ("real model data that looks like clouds"): what operational
/// 9–12 km, 30-level runs look like to nephele — 72×64 columns at 10 km, 30 eta levels, convective
/// cells one to three columns wide under a stratiform ice shield whose top steps by whole model
/// levels from column to column, with grid-scale (2Δx) noise, plus W, TKE_PBL and CLDFRA. Two
/// hourly timesteps, NetCDF-4 with deflate (~2 MB).
WrfHurricaneSpec coarseStormSpec();

/// The alpine storm of issues 13/14 (`nephele-gen wrf --case alpine-storm`): 160×128 columns at
/// 3 km (480 × 384 km) and 50 eta levels over a generated range centred in the Central Alps
/// (10.5° E, 46.4° N), one timestep, NetCDF-4 with deflate. With ntimes ≥ 2 the timesteps are its
/// life cycle (AlpineStage in wrf_alpine.h): step 1 is the single timestep's mature storm.
WrfHurricaneSpec alpineStormSpec();

/// The alpine storm's range (WrfCase::AlpineStorm) as a DEM finer than the model: its continuous
/// height function with two more octaves of ridged relief (to 0.5 km), sampled at `pixel_m` over
/// the model's footprint and written as a Float32 GeoTIFF in the model's own projection, for
/// `"terrain": {"dem": FILE}` (make demo's terrain shot). Returns the pixel grid's size.
std::pair<int, int> writeAlpineDem(const WrfHurricaneSpec& spec, double pixel_m, const std::string& path);

/// Writes the file; throws nph::IoError when NetCDF fails.
WrfTruth writeWrfHurricane(const WrfHurricaneSpec& spec, const std::string& path);

/// WRF constants used to encode the fields (WRF share/module_model_constants.F).
inline constexpr double kWrfGravity_m_per_s2 = 9.81;
inline constexpr double kWrfGasConstantDryAir_J_per_kgK = 287.0;
inline constexpr double kWrfSpecificHeatDryAir_J_per_kgK = 7.0 * kWrfGasConstantDryAir_J_per_kgK / 2.0;
inline constexpr double kWrfReferencePressure_pa = 100000.0;
inline constexpr double kWrfThetaOffset_k = 300.0;
inline constexpr double kWrfEarthRadius_m = 6370000.0;
inline constexpr double kWrfModelTopPressure_pa = 5000.0;

}  // namespace nph::datagen

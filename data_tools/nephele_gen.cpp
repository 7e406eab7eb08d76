// nephele-gen: writes the synthetic sample data sets (WRF hurricane, ICON scene) deterministically
// from a seed. Run `nephele-gen --help` or `nephele-gen <command> --help`.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <map>
#include <string>

#include "core/error.h"
#include "dem_writer.h"
#include "grib2_writer.h"
#include "presets.h"

namespace {

using nph::datagen::SampleSize;

const std::map<std::string, SampleSize> kSizes = {{"tiny", SampleSize::Tiny}, {"realistic", SampleSize::Realistic}};
const std::map<std::string, nph::datagen::WrfProjection> kProjections = {
    {"lambert", nph::datagen::WrfProjection::Lambert},       {"polar", nph::datagen::WrfProjection::PolarStereographic},
    {"mercator", nph::datagen::WrfProjection::Mercator},     {"latlon", nph::datagen::WrfProjection::LatLon},
    {"rotated", nph::datagen::WrfProjection::RotatedLatLon}, {"cartesian", nph::datagen::WrfProjection::Cartesian}};
const std::map<std::string, nph::datagen::WrfScheme> kSchemes = {{"thompson", nph::datagen::WrfScheme::ThompsonLike},
                                                                 {"wsm3", nph::datagen::WrfScheme::Wsm3Like}};

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "nephele-gen: synthetic weather-model output for nephele, convention-exact NetCDF through "
      "NetCDF-C, deterministic from --seed.\n"
      "  wrf   idealized hurricane as a WRF ARW wrfout file (Lambert/Mercator/..., Thompson-like or WSM3-like)\n"
      "  icon  ICON cloud scene (stratus, cumulus, cirrus) on a regular lat-lon or native triangular grid\n"
      "  all   the standard set of files into a directory\n"
      "Sizes: tiny (40x36x20, for tests) or realistic (500x500x60, for benchmarks: the wrf file is ~2.2 GB\n"
      "with deflate and takes minutes; generate it on demand, never commit it)."};
  app.require_subcommand(1);

  std::string size_name = "tiny";
  std::uint64_t seed = 1;
  bool compress = false;

  auto add_common = [&](CLI::App* sub) {
    sub->add_option("--size", size_name, "tiny | realistic")->check(CLI::IsMember({"tiny", "realistic"}));
    sub->add_option("--seed", seed, "random seed; same seed, same bytes");
    sub->add_flag("--compress", compress, "write NetCDF-4 with shuffle + deflate (default for realistic)");
  };

  CLI::App* wrf = app.add_subcommand("wrf", "idealized hurricane as wrfout");
  std::string wrf_out = "wrfout_d01_2026-09-01_12:00:00";
  std::string proj_name = "lambert", scheme_name = "thompson";
  int times = 6, start_hour = 0;
  bool hail = false;
  std::string case_name = "hurricane";
  add_common(wrf);
  wrf->add_option(
         "--case", case_name,
         "hurricane (the sample storm, --size applies) | storm (issue 13's coarse storm: 72x64x30 at 10 km, "
         "convective cells, stratiform shield, W/TKE_PBL/CLDFRA, 2 timesteps, deflate; --size is ignored) | "
         "hurricane-cells (the sample storm as 2-4 km model output shows it, make demo's: eyewall towers "
         "with overshooting tops, rainbands of discrete cells, stratiform shield, banded outflow canopy, "
         "shallow cumulus; W/TKE_PBL/CLDFRA; --size applies) | alpine-storm (make demo's terrain shot: "
         "160x128x50 at 3 km over a generated range in the Central Alps, HGT with ridges and draining "
         "valleys, towers over the crests with anvils, a lee deck, cumulus over the slopes, valley fog; "
         "W/TKE_PBL/CLDFRA, deflate; --size is ignored; 1 timestep, or with --times N >= 2 an hourly life cycle: "
         "young towers at the first, mature at the second, anvils spreading downwind, the towers "
         "collapsing at the last of 3 or more, the cells moving with the 0-6 km mean wind)")
      ->check(CLI::IsMember({"hurricane", "storm", "hurricane-cells", "alpine-storm"}));
  wrf->add_option("-o,--output", wrf_out, "output file");
  wrf->add_option("--proj", proj_name,
                  "lambert (MAP_PROJ=1) | polar (2) | mercator (3) | latlon (6) | rotated (6, rotated pole) | "
                  "cartesian (0, no XLAT/XLONG)")
      ->check(CLI::IsMember({"lambert", "polar", "mercator", "latlon", "rotated", "cartesian"}));
  wrf->add_option(
         "--scheme", scheme_name,
         "thompson (MP_PHYSICS=8, separate ice, number concentrations) | wsm3 (MP_PHYSICS=3, only QCLOUD/QRAIN)")
      ->check(CLI::IsMember({"thompson", "wsm3"}));
  wrf->add_option("--times", times, "hourly timesteps in the file (>= 1)")->check(CLI::PositiveNumber);
  wrf->add_option("--start-hour", start_hour,
                  "hours after 2026-09-01_12:00:00 of the first timestep (for file series)");
  wrf->add_flag("--hail", hail, "add QHAIL/QNHAIL");
  double anvil_rise_km_per_h = 0.0;
  wrf->add_option("--anvil-rise", anvil_rise_km_per_h,
                  "KM_PER_H: the hurricane's ice tops rise by this much per hour, up to their usual heights at "
                  "the last timestep (a series whose cloud top rises; default 0)")
      ->check(CLI::Range(0.0, 3.0));
  bool steering_wind = false;
  wrf->add_flag("--steering-wind", steering_wind,
                "U, V = the storm's drift (-4, 3) m/s everywhere, no vortex: with --case storm the wind its cells "
                "move with (motion-compensated blending, docs/animation.md)");
  std::vector<double> mountain;
  wrf->add_option(
         "--mountain", mountain,
         "LON,LAT,HEIGHT_M,SIGMA_M: add a Gaussian mountain to HGT (terrain; issue 14), e.g. -76,25.3,2500,40000")
      ->expected(4)
      ->delimiter(',');
  std::string alpine_dem;
  wrf->add_option("--dem", alpine_dem,
                  "alpine-storm only: also write its range at 500 m as a GeoTIFF in the model's projection, for "
                  "\"terrain\": {\"dem\": FILE} (make demo's terrain shot; docs/terrain.md)");
  std::vector<double> centre;
  wrf->add_option("--centre", centre,
                  "LON,LAT: the domain centre (CEN_LON, CEN_LAT; default -75,25, over the sea east of the Bahamas); "
                  "the projection follows it. Put a --mountain where Blue Marble shows land: make demo's terrain "
                  "shot uses --centre 11.85,47.1 --mountain=8,46.5,3000,35000 (the Bernese Alps, docs/terrain.md)")
      ->expected(2)
      ->delimiter(',');

  CLI::App* icon = app.add_subcommand("icon", "ICON cloud scene");
  std::string icon_out = "icon_scene.nc";
  bool native = false, descending = false;
  int icon_times = 2;
  add_common(icon);
  icon->add_option("-o,--output", icon_out, "output file");
  icon->add_flag("--native", native,
                 "native triangular grid (ncells, clon/clat in radians) instead of regular lat-lon");
  icon->add_flag("--lat-descending", descending, "write latitudes north to south");
  icon->add_option("--times", icon_times, "hourly timesteps (>= 1)")->check(CLI::PositiveNumber);
  std::string grib2_dir, grib2_layout = "dwd";
  nph::datagen::Grib2WriteOptions grib2;
  icon->add_option("--grib2", grib2_dir,
                   "write the scene as GRIB2 through ecCodes into this folder instead of NetCDF (same values)");
  icon->add_option("--grib2-layout", grib2_layout,
                   "dwd (one file per variable, level and step, DWD's names; HHL/CLON/CLAT time-invariant) | "
                   "single (every message in icon_scene.grib2)")
      ->check(CLI::IsMember({"dwd", "single"}));
  icon->add_option("--grib2-packing", grib2.packing,
                   "ecCodes packingType: grid_simple (default), grid_ccsds, grid_ieee (exact floats), grid_png, ...");
  icon->add_option("--grib2-bits", grib2.bits_per_value, "bitsPerValue of the packing (default 16)");

  CLI::App* dem = app.add_subcommand(
      "dem", "generated Alpine mountain range as a Float32 GeoTIFF (EPSG:4326) for \"terrain\": {\"dem\": FILE}");
  std::string dem_out = "alps-dem.tif";
  nph::datagen::DemSpec dem_spec;
  std::vector<double> dem_region;
  dem->add_option("-o,--output", dem_out, "output GeoTIFF");
  dem->add_option("--region", dem_region,
                  "LON_MIN,LAT_MIN,LON_MAX,LAT_MAX of the raster (default 3,42,21,51: the Alps and their "
                  "foreland; the range's belt follows the real Alps' axis, its ridges are synthesis)")
      ->expected(4)
      ->delimiter(',');
  dem->add_option("--pixel-deg", dem_spec.pixel_deg, "pixel size [deg] (default 0.01, about 1 km)")
      ->check(CLI::Range(0.001, 1.0));
  dem->add_option("--peak", dem_spec.peak_m, "height of the ridges on the range's axis [m] (default 4000)")
      ->check(CLI::Range(100.0, 8000.0));
  dem->add_option("--seed", dem_spec.seed, "random seed; same seed, same bytes");

  CLI::App* all =
      app.add_subcommand("all", "standard set: wrf lambert/mercator x thompson/wsm3, icon regular + native");
  std::string dir = "sample-data";
  add_common(all);
  all->add_option("-d,--dir", dir, "output directory");

  CLI11_PARSE(app, argc, argv);

  try {
    const SampleSize size = kSizes.at(size_name);
    const auto format = [&](nph::datagen::NcFormat preset) {
      return compress ? nph::datagen::NcFormat::Netcdf4Deflate : preset;
    };
    auto write_wrf = [&](const std::string& path, nph::datagen::WrfProjection p, nph::datagen::WrfScheme s) {
      const bool alpine = case_name == "alpine-storm";
      const bool storm = case_name == "storm" || alpine;
      if (!alpine_dem.empty() && !alpine) {
        throw nph::UsageError(fmt::format("--dem {}: the DEM is written for --case alpine-storm only (got --case {})",
                                          alpine_dem, case_name));
      }
      auto spec = alpine  ? nph::datagen::alpineStormSpec()
                  : storm ? nph::datagen::coarseStormSpec()
                          : nph::datagen::wrfPreset(size);
      if (case_name == "hurricane-cells") spec.weather = nph::datagen::WrfCase::HurricaneCells;
      spec.projection = p;
      spec.scheme = s;
      spec.seed = seed;
      if (!storm || wrf->count("--times") > 0) spec.ntimes = times;
      spec.first_hour = start_hour;
      spec.include_hail = hail;
      spec.anvil_rise_km_per_h = anvil_rise_km_per_h;
      spec.steering_wind_only = steering_wind;
      if (!mountain.empty()) spec.mountain = {mountain[0], mountain[1], mountain[2], mountain[3]};
      if (!centre.empty()) {
        spec.centre_lon_deg = centre[0];
        spec.centre_lat_deg = centre[1];
      }
      spec.format = format(spec.format);
      const auto t0 = std::chrono::steady_clock::now();
      const auto truth = nph::datagen::writeWrfHurricane(spec, path);
      if (!alpine_dem.empty()) {
        const auto [w, h] = nph::datagen::writeAlpineDem(spec, 500.0, alpine_dem);
        fmt::print("{}: DEM {}x{} pixels of 500 m in the model's projection\n", alpine_dem, w, h);
      }
      fmt::print("{}: wrfout {}x{}x{} x {} times, MAP_PROJ={}, MP_PHYSICS={}, {:.2f} s\n", path, truth.nx, truth.ny,
                 truth.nz, truth.ntimes, truth.map_proj, truth.mp_physics, secondsSince(t0));
    };
    auto write_icon_grib2 = [&](const std::string& out_dir, bool nat) {
      auto spec = nph::datagen::iconPreset(size, nat);
      spec.seed = seed;
      spec.ntimes = icon_times;
      spec.lat_descending = descending;
      grib2.layout =
          grib2_layout == "single" ? nph::datagen::Grib2Layout::SingleFile : nph::datagen::Grib2Layout::DwdFiles;
      const auto t0 = std::chrono::steady_clock::now();
      const auto files = nph::datagen::writeIconSceneGrib2(spec, out_dir, grib2);
      fmt::print("{}: ICON {} GRIB2 ({}, {} {} bits), {} files, {:.2f} s\n", out_dir, nat ? "native" : "regular",
                 grib2_layout, grib2.packing, grib2.bits_per_value, files.size(), secondsSince(t0));
    };
    auto write_icon = [&](const std::string& path, bool nat) {
      auto spec = nph::datagen::iconPreset(size, nat);
      spec.seed = seed;
      spec.ntimes = icon_times;
      spec.lat_descending = descending;
      spec.format = format(spec.format);
      const auto t0 = std::chrono::steady_clock::now();
      const auto truth = nph::datagen::writeIconScene(spec, path);
      fmt::print("{}: ICON {} {}x{}x{} x {} times, {} cells with CLC=0 & QC+QI>0, {} with CLC>0 & QC+QI=0, {:.2f} s\n",
                 path, nat ? fmt::format("native ({} cells)", truth.ncells) : std::string("regular"), truth.nlon,
                 truth.nlat, truth.nz, truth.ntimes, truth.clc_zero_with_condensate, truth.clc_without_condensate,
                 secondsSince(t0));
    };
    if (dem->parsed()) {
      if (!dem_region.empty()) {
        dem_spec.lon_min_deg = dem_region[0];
        dem_spec.lat_min_deg = dem_region[1];
        dem_spec.lon_max_deg = dem_region[2];
        dem_spec.lat_max_deg = dem_region[3];
      }
      const auto t0 = std::chrono::steady_clock::now();
      const auto truth = nph::datagen::writeGeneratedDem(dem_spec, dem_out);
      fmt::print("{}: DEM {}x{} pixels of {}°, heights {:.0f}..{:.0f} m, {:.2f} s\n", dem_out, truth.width,
                 truth.height, dem_spec.pixel_deg, truth.min_m, truth.max_m, secondsSince(t0));
    } else if (wrf->parsed()) {
      write_wrf(wrf_out, kProjections.at(proj_name), kSchemes.at(scheme_name));
    } else if (icon->parsed() && !grib2_dir.empty()) {
      write_icon_grib2(grib2_dir, native);
    } else if (icon->parsed()) {
      write_icon(icon_out, native);
    } else if (all->parsed()) {
      std::filesystem::create_directories(dir);
      using nph::datagen::WrfProjection;
      using nph::datagen::WrfScheme;
      write_wrf(dir + "/wrfout_lambert_thompson.nc", WrfProjection::Lambert, WrfScheme::ThompsonLike);
      write_wrf(dir + "/wrfout_lambert_wsm3.nc", WrfProjection::Lambert, WrfScheme::Wsm3Like);
      write_wrf(dir + "/wrfout_mercator_thompson.nc", WrfProjection::Mercator, WrfScheme::ThompsonLike);
      write_wrf(dir + "/wrfout_mercator_wsm3.nc", WrfProjection::Mercator, WrfScheme::Wsm3Like);
      write_icon(dir + "/icon_regular.nc", false);
      write_icon(dir + "/icon_native.nc", true);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "nephele-gen: {}\n", e.what());
    return 1;
  }
  return 0;
}

// ICON GRIB2 input (io/grib2_*): the generated ICON scene written by ecCodes itself
// (data_tools/grib2_writer.h) in DWD's one-file-per-variable-level-and-step layout and as one
// multi-message file, against the NetCDF file of the same scene (same float values).
//   - 32-bit IEEE packing stores the NetCDF floats exactly: the loaded fields and the extinction
//     volumes must be identical, bit for bit (the two paths share icon_fields.h's assembly).
//   - n-bit packing (simple, CCSDS): a value v of a field
//     with range [min, max] is stored as R + X 2^E with integer X < 2^n and the smallest E with
//     (max - min) <= (2^n - 1) 2^E, so 2^E < 2 (max - min) / (2^n - 1) and the rounding error
//     |v' - v| <= 2^(E-1) < (max - min) / (2^n - 1) (WMO FM 92 GRIB2, data representation
//     template 5.0, with D = 0). That bound, per level, plus float rounding, is what is checked,
//     and propagated through eq. 5.3 to the extinction on model levels.
//   - Hostile data sets: every error names the file and message and says what was expected.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>

#include "core/error.h"
#include "grib2_writer.h"
#include "icon_scene.h"
#include "io/grib2_loader.h"
#include "io/model_file.h"
#include "io_test_support.h"
#include "physics/air_density.h"
#include "physics/extinction.h"
#include "physics/optics_settings.h"
#include "physics/volume_builder.h"

namespace nph::io {
namespace {

using nph::test::ScratchDir;
namespace fs = std::filesystem;

datagen::IconSceneSpec smallSpec(bool native) {
  datagen::IconSceneSpec spec;
  spec.nlon = 24;
  spec.nlat = 20;
  spec.nz = 12;
  spec.ntimes = 2;
  if (native) spec.native_divisions = 2 * 128;
  return spec;
}

std::vector<ModelTimestep> loadAll(const std::vector<std::string>& inputs) {
  const ModelSeries series = ModelSeries::open(expandModelInputs(inputs));
  std::vector<ModelTimestep> out;
  for (std::size_t t = 0; t < series.size(); ++t) out.push_back(series.load(t));
  return out;
}

void expectSameFields(const ModelTimestep& a, const ModelTimestep& b) {
  EXPECT_EQ(a.time_utc, b.time_utc);
  ASSERT_EQ(a.nx, b.nx);
  ASSERT_EQ(a.ny, b.ny);
  ASSERT_EQ(a.nz, b.nz);
  EXPECT_EQ(a.georef, b.georef);
  ASSERT_EQ(a.q_kg_per_kg.size(), b.q_kg_per_kg.size());
  for (const auto& [h, q] : a.q_kg_per_kg) EXPECT_EQ(q, b.q_kg_per_kg.at(h)) << int(h);
  EXPECT_EQ(a.temperature_k, b.temperature_k);
  EXPECT_EQ(a.pressure_pa, b.pressure_pa);
  EXPECT_EQ(a.water_vapour_kg_per_kg, b.water_vapour_kg_per_kg);
  EXPECT_EQ(a.cloud_cover_fraction, b.cloud_cover_fraction);
  EXPECT_EQ(a.height_m, b.height_m);
  EXPECT_EQ(a.terrain_height_m, b.terrain_height_m);
}

void expectSameExtinction(const ModelTimestep& a, const ModelTimestep& b) {
  const auto va = physics::buildExtinctionVolumes(a, physics::defaultOptics(), physics::VerticalGridOptions{});
  const auto vb = physics::buildExtinctionVolumes(b, physics::defaultOptics(), physics::VerticalGridOptions{});
  ASSERT_EQ(va.nz, vb.nz);
  EXPECT_EQ(va.z_bottom_m, vb.z_bottom_m);
  EXPECT_EQ(va.ice_per_m, vb.ice_per_m);
  EXPECT_EQ(va.water_per_m, vb.water_per_m);
  EXPECT_GT(*std::max_element(va.water_per_m.begin(), va.water_per_m.end()), 0.0f);  // clouds, not emptiness
  EXPECT_GT(*std::max_element(va.ice_per_m.begin(), va.ice_per_m.end()), 0.0f);
}

struct LayoutCase {
  datagen::Grib2Layout layout;
  bool native;
};

/// 32-bit IEEE packing gives the NetCDF fields and extinction bit for bit.
void expectExactlyTheNetcdfPath(const LayoutCase c) {
  ScratchDir dir("io");
  const datagen::IconSceneSpec spec = smallSpec(c.native);
  datagen::writeIconScene(spec, dir.file("icon.nc"));
  datagen::Grib2WriteOptions options;
  options.layout = c.layout;
  options.packing = "grid_ieee";
  const auto files = datagen::writeIconSceneGrib2(spec, dir.file("grib"), options);
  EXPECT_EQ(files.size(), c.layout == datagen::Grib2Layout::SingleFile
                              ? 1u
                              : std::size_t(spec.ntimes * 9 * spec.nz + spec.nz + 1 + (c.native ? 2 : 0)));
  const ModelFile nc = openModelFile(dir.file("icon.nc"));
  const auto grib = loadAll({dir.file("grib")});  // the folder, as `nephele convert DIR` takes it
  ASSERT_EQ(grib.size(), nc.timesteps().size());
  for (std::size_t t = 0; t < grib.size(); ++t) {
    SCOPED_TRACE("timestep " + std::to_string(t));
    const ModelTimestep ref = nc.load(t);
    expectSameFields(grib[t], ref);
    expectSameExtinction(grib[t], ref);
  }
}

TEST(Grib2Exact, DwdFilesRegular) { expectExactlyTheNetcdfPath({datagen::Grib2Layout::DwdFiles, false}); }
TEST(Grib2Exact, SingleFileRegular) { expectExactlyTheNetcdfPath({datagen::Grib2Layout::SingleFile, false}); }
TEST(Grib2Exact, DwdFilesNative) { expectExactlyTheNetcdfPath({datagen::Grib2Layout::DwdFiles, true}); }

TEST(Grib2Exact, IconD2GridFrom356EastIsPlacedAtMinus3Point94) {
  // ICON-D2's regular grid: first point 43.18 N, 356.06 E (GRIB2 longitudes are 0 .. 360), 0.02 deg.
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  spec.lon0_deg = -3.94;
  spec.lat0_deg = 43.18;
  spec.dlon_deg = spec.dlat_deg = 0.02;
  datagen::writeIconScene(spec, dir.file("icon.nc"));
  datagen::Grib2WriteOptions options;
  options.packing = "grid_ieee";
  const std::string one = datagen::writeIconSceneGrib2(spec, dir.file("grib"), options).front();
  EXPECT_NEAR(scanGrib2File(one).front().grid.lon_first_deg, 356.06, 1e-6);  // as stored
  const ModelTimestep nc = openModelFile(dir.file("icon.nc")).load(0);
  const ModelTimestep grib = loadAll({dir.file("grib")}).at(0);
  // Section 3 holds micro-degrees: the placement agrees to 1e-6 deg, the fields exactly.
  EXPECT_NEAR(grib.georef.x0, -3.94, 1e-6);
  EXPECT_NEAR(grib.georef.y0, 43.18, 1e-6);
  EXPECT_NEAR(grib.georef.dx_m, 0.02, 1e-6);
  for (std::size_t p = 0; p < nc.georef.lon_deg.size(); ++p) {
    ASSERT_NEAR(grib.georef.lon_deg[p], nc.georef.lon_deg[p], 1e-5) << p;
    ASSERT_NEAR(grib.georef.lat_deg[p], nc.georef.lat_deg[p], 1e-5) << p;
  }
  EXPECT_EQ(grib.q_kg_per_kg.at(Hydrometeor::Cloud), nc.q_kg_per_kg.at(Hydrometeor::Cloud));
  EXPECT_EQ(grib.height_m, nc.height_m);
}

/// Packing bound of every level of `nc` (a field on `layer` points per level): (max - min) /
/// (2^bits - 1), plus float rounding of the decoded value.
std::vector<double> packingBounds(const std::vector<float>& nc, std::size_t layer, long bits) {
  std::vector<double> bounds;
  for (std::size_t k = 0; k * layer < nc.size(); ++k) {
    const auto begin = nc.begin() + std::ptrdiff_t(k * layer), end = begin + std::ptrdiff_t(layer);
    const auto [lo, hi] = std::minmax_element(begin, end);
    bounds.push_back((double(*hi) - double(*lo)) / (std::ldexp(1.0, int(bits)) - 1.0) +
                     4.0 * double(std::numeric_limits<float>::epsilon()) *
                         double(std::max(std::abs(*hi), std::abs(*lo))));
  }
  return bounds;
}

/// |grib - nc| within the packing bound of its level of `nc`.
void expectWithinPacking(const std::vector<float>& grib, const std::vector<float>& nc, std::size_t layer, long bits,
                         const char* what) {
  ASSERT_EQ(grib.size(), nc.size()) << what;
  const std::vector<double> bound = packingBounds(nc, layer, bits);
  for (std::size_t p = 0; p < nc.size(); ++p) {
    ASSERT_LE(std::abs(double(grib[p]) - double(nc[p])), bound[p / layer])
        << what << " level " << p / layer << " point " << p % layer;
  }
}

/// 16-bit packing: every field within the packing bound of its level.
void expectWithinPackingBound(const char* packing) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::writeIconScene(spec, dir.file("icon.nc"));
  datagen::Grib2WriteOptions options;
  options.packing = packing;
  options.bits_per_value = 16;
  datagen::writeIconSceneGrib2(spec, dir.file("grib"), options);
  const ModelTimestep nc = openModelFile(dir.file("icon.nc")).load(0);
  const ModelTimestep grib = loadAll({dir.file("grib") + "/*.grib2"}).at(0);  // a pattern, unexpanded by a shell
  const std::size_t layer = std::size_t(nc.nx) * std::size_t(nc.ny);
  for (const auto& [h, q] : nc.q_kg_per_kg) expectWithinPacking(grib.q_kg_per_kg.at(h), q, layer, 16, "q");
  expectWithinPacking(grib.temperature_k, nc.temperature_k, layer, 16, "T");
  expectWithinPacking(grib.pressure_pa, nc.pressure_pa, layer, 16, "P");
  expectWithinPacking(grib.water_vapour_kg_per_kg, nc.water_vapour_kg_per_kg, layer, 16, "QV");
  expectWithinPacking(grib.cloud_cover_fraction, nc.cloud_cover_fraction, layer, 16, "CLC");
  expectWithinPacking(grib.terrain_height_m, nc.terrain_height_m, layer, 16, "HHL (lowest half level)");
  // A packed field is not the NetCDF one (the comparison above would pass for identical data).
  EXPECT_NE(grib.temperature_k, nc.temperature_k);
}

TEST(Grib2Packed, SimplePackingWithinBound) { expectWithinPackingBound("grid_simple"); }
TEST(Grib2Packed, CcsdsWithinBound) { expectWithinPackingBound("grid_ccsds"); }
// Extinction on model levels (Nes 2008 eq. 5.3, physics/extinction.h): β_f = a_f ρ q_f with
// a_f = 3 / (2 ρ_f r_f) (fixed radii: ICON has no number concentrations) and the moist density
// ρ(p, T, q_v, Σq) (physics/air_density.h), increasing in p and Σq, decreasing in T and q_v. With
// every field within its packing bound Δ of the NetCDF value, both states lie in the box
// grib ± Δ, so ρ_lo <= ρ <= ρ_hi at its corners and
//   |β_grib - β_nc| = a_f |ρ_nc (q_grib - q_nc) + q_grib (ρ_grib - ρ_nc)| <= a_f (ρ_hi Δq + q_grib (ρ_hi - ρ_lo)),
// summed over the classes of each volume. Without cloud cover (the ICON corrections off) this is
// the whole difference; float storage of β adds a relative 2^-23.
TEST(Grib2Packed, ModelLevelExtinctionWithinTheDerivedBound) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::writeIconScene(spec, dir.file("icon.nc"));
  datagen::writeIconSceneGrib2(spec, dir.file("grib"));  // 16-bit simple packing, as DWD's files
  ModelTimestep nc = openModelFile(dir.file("icon.nc")).load(0);
  ModelTimestep grib = loadAll({dir.file("grib")}).at(0);
  nc.cloud_cover_fraction.clear();  // no corrections: the optics are eq. 5.3 alone
  grib.cloud_cover_fraction.clear();
  const physics::OpticsSettings optics = physics::defaultOptics();
  const auto beta_nc = physics::modelLevelExtinction(nc, optics);
  const auto beta_grib = physics::modelLevelExtinction(grib, optics);
  const std::size_t layer = std::size_t(nc.nx) * std::size_t(nc.ny);
  const auto dp = packingBounds(nc.pressure_pa, layer, 16), dt = packingBounds(nc.temperature_k, layer, 16),
             dqv = packingBounds(nc.water_vapour_kg_per_kg, layer, 16);
  std::map<Hydrometeor, std::vector<double>> dq;
  for (const auto& [h, q] : nc.q_kg_per_kg) dq[h] = packingBounds(q, layer, 16);
  double worst = 0.0, largest_difference = 0.0;
  for (std::size_t v = 0; v < nc.voxelCount(); ++v) {
    const std::size_t k = v / layer;
    double q_sum = 0.0, dq_sum = 0.0;
    for (const auto& [h, q] : grib.q_kg_per_kg) {
      q_sum += std::max(double(q[v]), 0.0);
      dq_sum += dq.at(h)[k];
    }
    const double p = grib.pressure_pa[v], t = grib.temperature_k[v], qv = grib.water_vapour_kg_per_kg[v];
    const double rho_hi = physics::moistAirDensity(p + dp[k], t - dt[k], std::max(qv - dqv[k], 0.0), q_sum + dq_sum);
    const double rho_lo = physics::moistAirDensity(p - dp[k], t + dt[k], qv + dqv[k], std::max(q_sum - dq_sum, 0.0));
    double bound_ice = 0.0, bound_water = 0.0;
    for (const auto& [h, q] : grib.q_kg_per_kg) {
      const physics::HydrometeorOptics& o = optics[h];
      const double a = 3.0 / (2.0 * o.particle_density_kg_per_m3 * o.effective_radius_m);
      (o.ice_phase ? bound_ice : bound_water) +=
          a * (rho_hi * dq.at(h)[k] + std::max(double(q[v]), 0.0) * (rho_hi - rho_lo));
    }
    constexpr double kFloat = 1.0 / (1 << 23);
    bound_ice += kFloat * double(beta_nc.ice_per_m[v]);
    bound_water += kFloat * double(beta_nc.water_per_m[v]);
    const double d_ice = std::abs(double(beta_grib.ice_per_m[v]) - double(beta_nc.ice_per_m[v]));
    const double d_water = std::abs(double(beta_grib.water_per_m[v]) - double(beta_nc.water_per_m[v]));
    ASSERT_LE(d_ice, bound_ice) << "voxel " << v;
    ASSERT_LE(d_water, bound_water) << "voxel " << v;
    largest_difference = std::max({largest_difference, d_ice, d_water});
    if (bound_ice > 0.0) worst = std::max(worst, d_ice / bound_ice);
    if (bound_water > 0.0) worst = std::max(worst, d_water / bound_water);
  }
  EXPECT_GT(largest_difference, 0.0);  // packing did change the extinction
  std::printf("largest |beta_grib - beta_nc| %.3g /m, at most %.2f of its bound\n", largest_difference, worst);
  // For the record (not bounded here: packed heights move the levels the metric grid is
  // interpolated from): the resampled volumes, ICON corrections on.
  nc = openModelFile(dir.file("icon.nc")).load(0);
  grib = loadAll({dir.file("grib")}).at(0);
  const auto vn = physics::buildExtinctionVolumes(nc, optics, physics::VerticalGridOptions{});
  const auto vg = physics::buildExtinctionVolumes(grib, optics, physics::VerticalGridOptions{});
  if (vn.nz == vg.nz && vn.z_bottom_m == vg.z_bottom_m) {
    double max_beta = 0.0, max_difference = 0.0;
    for (std::size_t v = 0; v < vn.water_per_m.size(); ++v) {
      max_beta = std::max({max_beta, double(vn.water_per_m[v]), double(vn.ice_per_m[v])});
      max_difference = std::max({max_difference, std::abs(double(vg.water_per_m[v]) - double(vn.water_per_m[v])),
                                 std::abs(double(vg.ice_per_m[v]) - double(vn.ice_per_m[v]))});
    }
    std::printf("resampled volumes: largest difference %.3g /m = %.2g of the largest beta %.3g /m\n", max_difference,
                max_difference / max_beta, max_beta);
  }
}

// Not grid_complex(_spatial_differencing): ecCodes 2.28's encoder loses data of these fields
// (`grib_set -r -s packingType=grid_complex` on a simple-packed QC level: maximum 0.00160 ->
// 0.00127 kg/kg), so test data in that packing would test ecCodes' encoder, not the reader.

// --- hostile GRIB2 --------------------------------------------------------------------------------

void expectInputError(const std::function<void()>& fn, std::initializer_list<std::string> mentions) {
  try {
    fn();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const std::string& m : mentions) EXPECT_NE(what.find(m), std::string::npos) << "'" << m << "' in: " << what;
  }
}

std::string dwdFile(const std::string& dir, const char* kind, int step, int level, const char* var) {
  return fmt::format("{}/icon-d2_germany_regular-lat-lon_{}_2026031812_{:03d}_{}_{}.grib2", dir, kind, step, level,
                     var);
}

TEST(HostileGrib2, MemoryBudgetIsCheckedBeforeReading) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::writeIconSceneGrib2(spec, dir.file("grib"));
  LoadOptions options;
  options.memory_budget_bytes = 1000;
  const ModelSeries series = ModelSeries::open(expandModelInputs({dir.file("grib")}), options);
  expectInputError([&] { (void)series.load(0); }, {"_t.grib2", "more than the memory budget"});
}

TEST(HostileGrib2, MissingHhlNamesTheFileAndTheTimeInvariantFile) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::Grib2WriteOptions options;
  options.write_hhl = false;
  const auto files = datagen::writeIconSceneGrib2(spec, dir.file("grib"), options);
  expectInputError([&] { (void)ModelSeries::open(files); }, {files.front(), "no HHL", "13 levels", "_hhl.grib2"});
}

TEST(HostileGrib2, MissingLevelIsNamed) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::writeIconSceneGrib2(spec, dir.file("grib"));
  fs::remove(dwdFile(dir.file("grib"), "model-level", 0, 7, "qi"));
  expectInputError([&] { (void)ModelSeries::open(expandModelInputs({dir.file("grib")})); },
                   {"QI at 2026-03-18T12:00:00Z", "expected levels 1 .. 12", "missing: 7"});
}

TEST(HostileGrib2, MismatchedGridUuidOfClonClat) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(true);
  spec.ntimes = 1;
  datagen::Grib2WriteOptions options;
  options.coordinates_uuid = "ffffffffffffffffffffffffffffffff";
  datagen::writeIconSceneGrib2(spec, dir.file("grib"), options);
  expectInputError([&] { (void)ModelSeries::open(expandModelInputs({dir.file("grib")})); },
                   {"mismatched grid UUID", options.fields_uuid, "uuidOfHGrid ffffffffffffffffffffffffffffffff",
                    "_clon.grib2: message 1 (CLON"});
}

TEST(HostileGrib2, MixedGridsNameBothMessages) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::writeIconSceneGrib2(spec, dir.file("grib"));
  spec.lon0_deg += 0.5;  // the same scene shifted east
  datagen::writeIconSceneGrib2(spec, dir.file("shifted"));
  const std::string moved = dwdFile(dir.file("grib"), "model-level", 0, 3, "t");
  fs::copy_file(dwdFile(dir.file("shifted"), "model-level", 0, 3, "t"), moved, fs::copy_options::overwrite_existing);
  expectInputError(
      [&] { (void)ModelSeries::open(expandModelInputs({dir.file("grib")})); },
      {"mixed grids", moved + ": message 1 (T, level 3", "(46 N, 9.5 E)", "(46 N, 9 E)", "expected one grid"});
}

TEST(HostileGrib2, TruncatedMessageSaysWhereTheFileEnds) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::Grib2WriteOptions options;
  options.layout = datagen::Grib2Layout::SingleFile;
  const std::string path = datagen::writeIconSceneGrib2(spec, dir.file("grib"), options).front();
  const auto size = fs::file_size(path);
  fs::resize_file(path, size - 100);
  expectInputError([&] { (void)openModelFile(path); }, {path, "is truncated", "Section 0 declares"});
  fs::resize_file(path, 10);  // inside the first Section 0
  expectInputError([&] { (void)openModelFile(path); }, {path, "message 1 at byte 0 is truncated"});
}

/// Section 5 of the first message of `path`: octets 10-11 hold the data representation template.
void setDataRepresentationTemplate(const std::string& path, unsigned number) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::size_t pos = 16;  // after Section 0
  for (int guard = 0; guard < 8; ++guard) {
    unsigned char head[5];
    f.seekg(std::streamoff(pos));
    f.read(reinterpret_cast<char*>(head), 5);
    const std::size_t length = (std::size_t(head[0]) << 24) | (std::size_t(head[1]) << 16) |
                               (std::size_t(head[2]) << 8) | std::size_t(head[3]);
    if (head[4] == 5) {
      const char bytes[2] = {char(number >> 8), char(number & 0xff)};
      f.seekp(std::streamoff(pos + 9));
      f.write(bytes, 2);
      return;
    }
    pos += length;
  }
  FAIL() << "no Section 5 in " << path;
}

TEST(HostileGrib2, UnsupportedPackingIsNamed) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec = smallSpec(false);
  spec.ntimes = 1;
  datagen::writeIconSceneGrib2(spec, dir.file("grib"));
  const std::string qc = dwdFile(dir.file("grib"), "model-level", 0, 12, "qc");
  setDataRepresentationTemplate(qc, 51);  // 5.51: spherical harmonics, complex packing
  const ModelSeries series = ModelSeries::open(expandModelInputs({dir.file("grib")}));
  expectInputError([&] { (void)series.load(0); },
                   {qc + ": message 1 (QC, level 12", "(data representation template 5.51) is not supported",
                    "expected grid-point data", "grid_ccsds"});
}

TEST(HostileGrib2, NotGrib2AndEmptyFoldersAndPatterns) {
  ScratchDir dir("io");
  fs::create_directories(dir.file("empty"));
  expectInputError([&] { (void)expandModelInputs({dir.file("empty")}); },
                   {dir.file("empty"), "folder without GRIB2 or NetCDF files"});
  expectInputError([&] { (void)expandModelInputs({dir.file("nothing*.grib2")}); },
                   {dir.file("nothing*.grib2"), "matches no file"});
  {
    std::ofstream f(dir.file("edition1.grib"), std::ios::binary);
    const unsigned char s0[16] = {'G', 'R', 'I', 'B', 0, 0, 28, 1, 0, 0, 0, 0, 0, 0, 0, 0};
    f.write(reinterpret_cast<const char*>(s0), sizeof s0);
  }
  expectInputError([&] { (void)openModelFile(dir.file("edition1.grib")); },
                   {dir.file("edition1.grib"), "GRIB edition 1, expected edition 2"});
}

}  // namespace
}  // namespace nph::io

// The generators are deterministic from the seed and write the conventions loaders rely on.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <vector>

#include "icon_scene.h"
#include "io_test_support.h"
#include "wrf_hurricane.h"

namespace nph::io {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Datagen, SameSeedSameBytesOtherSeedOtherBytes) {
  nph::test::ScratchDir dir("io");
  datagen::WrfHurricaneSpec s;
  s.nx = 20;
  s.ny = 16;
  s.nz = 8;
  s.ntimes = 2;
  datagen::writeWrfHurricane(s, dir.file("a.nc"));
  datagen::writeWrfHurricane(s, dir.file("b.nc"));
  s.seed = 2;
  datagen::writeWrfHurricane(s, dir.file("c.nc"));
  EXPECT_EQ(slurp(dir.file("a.nc")), slurp(dir.file("b.nc")));
  EXPECT_NE(slurp(dir.file("a.nc")), slurp(dir.file("c.nc")));
  datagen::IconSceneSpec i;
  i.ntimes = 1;
  datagen::writeIconScene(i, dir.file("i1.nc"));
  datagen::writeIconScene(i, dir.file("i2.nc"));
  EXPECT_EQ(slurp(dir.file("i1.nc")), slurp(dir.file("i2.nc")));
}

TEST(Datagen, WrfoutCarriesWrfConventions) {
  nph::test::ScratchDir dir("io");
  datagen::WrfHurricaneSpec s;
  s.ntimes = 6;
  s.nz = 6;
  datagen::writeWrfHurricane(s, dir.file("wrfout.nc"));
  int nc = -1;
  test::ncCheck(nc_open(dir.file("wrfout.nc").c_str(), NC_NOWRITE, &nc), "open");
  std::size_t len = 0;
  int dim = -1;
  for (const auto& [name, expected] : {std::pair<const char*, std::size_t>{"Time", 6},
                                       {"DateStrLen", 19},
                                       {"west_east", 40},
                                       {"west_east_stag", 41},
                                       {"south_north", 36},
                                       {"south_north_stag", 37},
                                       {"bottom_top", 6},
                                       {"bottom_top_stag", 7}}) {
    ASSERT_EQ(nc_inq_dimid(nc, name, &dim), NC_NOERR) << name;
    nc_inq_dimlen(nc, dim, &len);
    EXPECT_EQ(len, expected) << name;
  }
  int var = -1;
  ASSERT_EQ(nc_inq_varid(nc, "PH", &var), NC_NOERR);
  char text[64] = {};
  nc_get_att_text(nc, var, "stagger", text);
  EXPECT_STREQ(text, "Z");
  std::fill(std::begin(text), std::end(text), '\0');
  nc_get_att_text(nc, var, "MemoryOrder", text);
  EXPECT_STREQ(text, "XYZ");
  int field_type = 0;
  nc_get_att_int(nc, var, "FieldType", &field_type);
  EXPECT_EQ(field_type, 104);
  for (const char* att : {"MAP_PROJ", "TRUELAT1", "TRUELAT2", "STAND_LON", "CEN_LAT", "CEN_LON", "MOAD_CEN_LAT", "DX",
                          "DY", "MP_PHYSICS", "WEST-EAST_GRID_DIMENSION", "SOUTH-NORTH_GRID_DIMENSION",
                          "BOTTOM-TOP_GRID_DIMENSION", "SIMULATION_START_DATE", "POLE_LAT", "POLE_LON"}) {
    EXPECT_EQ(nc_inq_att(nc, NC_GLOBAL, att, nullptr, nullptr), NC_NOERR) << att;
  }
  int we = 0;
  nc_get_att_int(nc, NC_GLOBAL, "WEST-EAST_GRID_DIMENSION", &we);
  EXPECT_EQ(we, 41);  // WRF counts staggered points
  ASSERT_EQ(nc_inq_varid(nc, "Times", &var), NC_NOERR);
  char times[20] = {};
  const std::size_t start[2] = {5, 0}, count[2] = {1, 19};
  nc_get_vara_text(nc, var, start, count, times);
  EXPECT_STREQ(times, "2026-09-01_17:00:00");
  nc_close(nc);
}

}  // namespace
}  // namespace nph::io

namespace nph::io {
namespace {

std::vector<float> readFloats(int nc, const char* name, std::size_t count) {
  int var = -1;
  EXPECT_EQ(nc_inq_varid(nc, name, &var), NC_NOERR) << name;
  std::vector<float> out(count);
  const std::size_t start[4] = {0, 0, 0, 0};
  int ndims = 0;
  nc_inq_varndims(nc, var, &ndims);
  int dims[4] = {};
  nc_inq_vardimid(nc, var, dims);
  std::size_t cnt[4] = {1, 1, 1, 1};
  for (int d = 1; d < ndims; ++d) nc_inq_dimlen(nc, dims[d], &cnt[d]);
  EXPECT_EQ(cnt[1] * cnt[2] * cnt[3], count) << name;
  EXPECT_EQ(nc_get_vara_float(nc, var, start, cnt, out.data()), NC_NOERR) << name;
  return out;
}

// Issue 13's coarse storm: a 10-km, 30-level wrfout with convective cells, a stratiform shield whose
// top ends on different model levels in neighbouring columns, and W / TKE_PBL / CLDFRA.
TEST(Datagen, CoarseStormHasCellsShieldAndTurbulenceFields) {
  nph::test::ScratchDir dir("io");
  datagen::WrfHurricaneSpec s = datagen::coarseStormSpec();
  s.ntimes = 1;
  datagen::writeWrfHurricane(s, dir.file("storm.nc"));
  int nc = -1;
  test::ncCheck(nc_open(dir.file("storm.nc").c_str(), NC_NOWRITE, &nc), "open");
  float dx = 0.0f;
  nc_get_att_float(nc, NC_GLOBAL, "DX", &dx);
  EXPECT_EQ(dx, 10000.0f);
  const std::size_t nx = 72, ny = 64, nz = 30, n2 = nx * ny;
  const auto w = readFloats(nc, "W", n2 * (nz + 1));
  const auto tke = readFloats(nc, "TKE_PBL", n2 * nz);
  const auto cf = readFloats(nc, "CLDFRA", n2 * nz);
  const auto qi = readFloats(nc, "QICE", n2 * nz);
  const auto qs = readFloats(nc, "QSNOW", n2 * nz);
  const auto qc = readFloats(nc, "QCLOUD", n2 * nz);
  nc_close(nc);
  EXPECT_GT(*std::max_element(w.begin(), w.end()), 4.0f) << "convective updrafts";
  EXPECT_GT(tke[n2 * 1 + (ny / 2) * nx + nx / 2], 0.1f) << "boundary-layer TKE";
  EXPECT_GT(*std::max_element(tke.begin(), tke.end()), 1.0f) << "TKE in the cells";
  for (float f : cf) ASSERT_TRUE(f >= 0.0f && f <= 1.0f) << f;
  // Per column, the highest level with snow/ice: deep cells (tops ≥ 7 km, level ≥ 18) cover a few
  // columns; the shield's top steps between neighbouring columns.
  std::vector<int> top(n2, -1);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t c = 0; c < n2; ++c) {
      const std::size_t m = k * n2 + c;
      if (qi[m] + qs[m] + qc[m] > 1e-5f) top[c] = int(k);
      if (qc[m] + qi[m] + qs[m] > 1e-4f) {
        EXPECT_GT(cf[m], 0.99f);
      }
    }
  int cloudy = 0, steps = 0;
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const int a = top[j * nx + i], b = top[j * nx + i + 1];
      if (a >= 0) ++cloudy;
      if (a >= 0 && b >= 0 && a != b) ++steps;
    }
  EXPECT_GT(cloudy, int(n2 / 10)) << "a storm, not a few cells";
  EXPECT_LT(cloudy, int(n2 / 2)) << "clear air around it";
  EXPECT_GT(steps, cloudy / 5) << "the cloud top steps by whole levels between neighbouring columns";
}

}  // namespace
}  // namespace nph::io

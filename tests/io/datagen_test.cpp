// The generators are deterministic from the seed and write the conventions loaders rely on.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <fstream>
#include <iterator>

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
  for (const auto& [name, expected] : {std::pair<const char*, std::size_t>{"Time", 6}, {"DateStrLen", 19}, {"west_east", 40},
                                       {"west_east_stag", 41}, {"south_north", 36}, {"south_north_stag", 37},
                                       {"bottom_top", 6}, {"bottom_top_stag", 7}}) {
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
  for (const char* att : {"MAP_PROJ", "TRUELAT1", "TRUELAT2", "STAND_LON", "CEN_LAT", "CEN_LON", "MOAD_CEN_LAT", "DX", "DY",
                          "MP_PHYSICS", "WEST-EAST_GRID_DIMENSION", "SOUTH-NORTH_GRID_DIMENSION",
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

// Table-driven robustness: each case writes a damaged file (NetCDF-C edits of a generated file,
// hand-written skeletons, a truncated copy, a text file) and expects an nph::InputError whose
// message names the file and the variable or attribute at fault, through the top-level API.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "core/error.h"
#include "icon_scene.h"
#include "io/icon_loader.h"
#include "io/model_file.h"
#include "io_test_support.h"
#include "wrf_hurricane.h"

namespace nph::io {
namespace {

using nph::test::ScratchDir;
using test::ncCheck;

/// A small valid wrfout to start from.
void writeSmallWrf(const std::string& path) {
  datagen::WrfHurricaneSpec s;
  s.nx = 12;
  s.ny = 10;
  s.nz = 8;
  s.ntimes = 1;
  datagen::writeWrfHurricane(s, path);
}
void writeSmallIcon(const std::string& path) {
  datagen::IconSceneSpec s;
  s.nlon = 12;
  s.nlat = 10;
  s.nz = 8;
  s.ntimes = 1;
  datagen::writeIconScene(s, path);
}

/// Opens `path` for editing, runs `edit(ncid)`, closes.
void edit(const std::string& path, const std::function<void(int)>& fn) {
  int ncid = -1;
  ncCheck(nc_open(path.c_str(), NC_WRITE, &ncid), "open for edit");
  fn(ncid);
  ncCheck(nc_close(ncid), "close after edit");
}
int varid(int ncid, const char* name) {
  int id = -1;
  EXPECT_EQ(nc_inq_varid(ncid, name, &id), NC_NOERR) << name;
  return id;
}
void putValue(int ncid, const char* var, std::size_t element, float value) {
  const int id = varid(ncid, var);
  int ndims = 0;
  nc_inq_varndims(ncid, id, &ndims);
  std::vector<int> dims(std::size_t(ndims), 0);
  nc_inq_vardimid(ncid, id, dims.data());
  std::vector<std::size_t> index(std::size_t(ndims), 0);
  // Unravel `element` over the variable's shape (last dimension fastest).
  for (int d = ndims - 1; d >= 0; --d) {
    std::size_t len = 0;
    nc_inq_dimlen(ncid, dims[std::size_t(d)], &len);
    index[std::size_t(d)] = element % len;
    element /= len;
  }
  ncCheck(nc_put_var1_float(ncid, id, index.data(), &value), var);
}
void setGlobalFloat(int ncid, const char* name, float value) {
  ncCheck(nc_redef(ncid), "redef");
  ncCheck(nc_put_att_float(ncid, NC_GLOBAL, name, NC_FLOAT, 1, &value), name);
  ncCheck(nc_enddef(ncid), "enddef");
}
void renameVar(int ncid, const char* from, const char* to) {
  ncCheck(nc_redef(ncid), "redef");
  ncCheck(nc_rename_var(ncid, varid(ncid, from), to), from);
  ncCheck(nc_enddef(ncid), "enddef");
}
/// Replaces `name` with a new variable of the given dimensions (the original is renamed away).
void replaceVar(int ncid, const char* name, nc_type type, const std::vector<const char*>& dim_names) {
  ncCheck(nc_redef(ncid), "redef");
  ncCheck(nc_rename_var(ncid, varid(ncid, name), (std::string(name) + "_orig").c_str()), name);
  std::vector<int> dims;
  for (const char* d : dim_names) {
    int id = -1;
    ncCheck(nc_inq_dimid(ncid, d, &id), d);
    dims.push_back(id);
  }
  int id = -1;
  ncCheck(nc_def_var(ncid, name, type, int(dims.size()), dims.data(), &id), name);
  ncCheck(nc_enddef(ncid), "enddef");
}

/// A hand-written wrfout skeleton with the given sizes (NetCDF-4: a dimension of length 0 is an
/// unlimited one without data; with write_data = false only one value is written, so huge declared
/// sizes cost no disk space).
void writeSkeletonWrf(const std::string& path, std::size_t nx, std::size_t ny, std::size_t nz, std::size_t nt,
                      bool write_data) {
  int ncid = -1;
  ncCheck(nc_create(path.c_str(), NC_CLOBBER | NC_NETCDF4, &ncid), "create");
  int d_t = -1, d_z = -1, d_zs = -1, d_y = -1, d_x = -1;
  ncCheck(nc_def_dim(ncid, "Time", NC_UNLIMITED, &d_t), "Time");
  ncCheck(nc_def_dim(ncid, "bottom_top", nz, &d_z), "bottom_top");
  ncCheck(nc_def_dim(ncid, "bottom_top_stag", nz + 1, &d_zs), "bottom_top_stag");
  ncCheck(nc_def_dim(ncid, "south_north", ny, &d_y), "south_north");
  ncCheck(nc_def_dim(ncid, "west_east", nx, &d_x), "west_east");
  const int mass[4] = {d_t, d_z, d_y, d_x};
  const int stag[4] = {d_t, d_zs, d_y, d_x};
  std::map<std::string, int> ids;
  for (const char* v : {"QCLOUD", "P", "PB", "T"}) ncCheck(nc_def_var(ncid, v, NC_FLOAT, 4, mass, &ids[v]), v);
  for (const char* v : {"PH", "PHB"}) ncCheck(nc_def_var(ncid, v, NC_FLOAT, 4, stag, &ids[v]), v);
  const float dx = 3000.0f;
  ncCheck(nc_put_att_float(ncid, NC_GLOBAL, "DX", NC_FLOAT, 1, &dx), "DX");
  ncCheck(nc_put_att_float(ncid, NC_GLOBAL, "DY", NC_FLOAT, 1, &dx), "DY");
  const int map_proj = 0;
  ncCheck(nc_put_att_int(ncid, NC_GLOBAL, "MAP_PROJ", NC_INT, 1, &map_proj), "MAP_PROJ");
  ncCheck(nc_enddef(ncid), "enddef");
  if (!write_data && nt > 0 && nx > 0 && ny > 0 && nz > 0) {
    // One value extends Time to a record; HDF5 stores only that chunk.
    const std::size_t index[4] = {0, 0, 0, 0};
    const float zero = 0.0f;
    ncCheck(nc_put_var1_float(ncid, ids["P"], index, &zero), "P");
  }
  if (write_data && nt > 0) {
    const std::size_t n = nx * ny * nz, nw = nx * ny * (nz + 1);
    const std::size_t start[4] = {0, 0, 0, 0};
    const std::size_t count[4] = {1, nz, ny, nx};
    const std::size_t count_w[4] = {1, nz + 1, ny, nx};
    std::vector<float> zero(n, 0.0f), qc(n, 1e-4f), pb(n, 85000.0f), phb(nw);
    for (std::size_t k = 0; k <= nz; ++k)
      for (std::size_t c = 0; c < nx * ny; ++c) phb[k * nx * ny + c] = float(9.81 * 1000.0 * double(k));
    ncCheck(nc_put_vara_float(ncid, ids["QCLOUD"], start, count, qc.data()), "QCLOUD");
    ncCheck(nc_put_vara_float(ncid, ids["P"], start, count, zero.data()), "P");
    ncCheck(nc_put_vara_float(ncid, ids["PB"], start, count, pb.data()), "PB");
    ncCheck(nc_put_vara_float(ncid, ids["T"], start, count, zero.data()), "T");
    std::vector<float> zero_w(nw, 0.0f);
    ncCheck(nc_put_vara_float(ncid, ids["PH"], start, count_w, zero_w.data()), "PH");
    ncCheck(nc_put_vara_float(ncid, ids["PHB"], start, count_w, phb.data()), "PHB");
  }
  ncCheck(nc_close(ncid), "close");
}

struct BadFileCase {
  const char* name;
  std::function<void(const std::string&)> make;  // writes the bad file at the given path
  std::vector<const char*> message_mentions;     // besides the file name
};

void PrintTo(const BadFileCase& c, std::ostream* os) { *os << c.name; }

const std::vector<BadFileCase>& badFileCases() {
  static const std::vector<BadFileCase> cases = {
      {"missing_variable",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { renameVar(nc, "PH", "PH_gone"); });
       },
       {"PH", "missing"}},
      {"wrong_rank",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { replaceVar(nc, "QCLOUD", NC_FLOAT, {"Time", "south_north", "west_east"}); });
       },
       {"QCLOUD has 3 dims, expected 4 (Time, bottom_top, south_north, west_east)"}},
      {"wrong_dimension_order",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { replaceVar(nc, "T", NC_FLOAT, {"Time", "south_north", "bottom_top", "west_east"}); });
       },
       {"T has dims (Time, south_north, bottom_top, west_east)", "expected"}},
      {"char_typed_field",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { replaceVar(nc, "QRAIN", NC_CHAR, {"Time", "bottom_top", "south_north", "west_east"}); });
       },
       {"QRAIN", "non-numeric"}},
      {"zero_length_dimension",
       [](const std::string& p) { writeSkeletonWrf(p, 0, 4, 3, 1, false); },
       {"west_east", "length 0"}},
      {"no_timesteps", [](const std::string& p) { writeSkeletonWrf(p, 4, 4, 3, 0, false); }, {"Time", "length 0"}},
      {"nan_in_pressure",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { putValue(nc, "P", 17, std::numeric_limits<float>::quiet_NaN()); });
       },
       {"P contains NaN", "finite"}},
      {"inf_in_cloud",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { putValue(nc, "QCLOUD", 5, std::numeric_limits<float>::infinity()); });
       },
       {"QCLOUD contains Inf"}},
      {"missing_value_in_temperature",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) {
           const float mv = -999.0f;
           ncCheck(nc_redef(nc), "redef");
           ncCheck(nc_put_att_float(nc, varid(nc, "T"), "missing_value", NC_FLOAT, 1, &mv), "missing_value");
           ncCheck(nc_enddef(nc), "enddef");
           putValue(nc, "T", 3, mv);
         });
       },
       {"T has 1 missing values"}},
      {"absurd_stand_lon",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { setGlobalFloat(nc, "STAND_LON", 1e20f); });
       },
       {"STAND_LON", "absurd"}},
      {"zero_dx",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { setGlobalFloat(nc, "DX", 0.0f); });
       },
       {"DX"}},
      {"negative_dy",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { setGlobalFloat(nc, "DY", -3000.0f); });
       },
       {"DY"}},
      {"unknown_map_proj",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) {
           const int v = 99;
           ncCheck(nc_redef(nc), "redef");
           ncCheck(nc_put_att_int(nc, NC_GLOBAL, "MAP_PROJ", NC_INT, 1, &v), "MAP_PROJ");
           ncCheck(nc_enddef(nc), "enddef");
         });
       },
       {"MAP_PROJ = 99"}},
      {"geopotential_not_increasing",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { putValue(nc, "PHB", 12 * 10 * 4 + 7, 1.0f); });
       },
       {"PH+PHB", "increas"}},
      {"absurd_temperature",
       [](const std::string& p) {
         writeSmallWrf(p);
         edit(p, [](int nc) { putValue(nc, "T", 9, 5000.0f); });
       },
       {"T", "temperature"}},
      {"declared_size_beyond_memory",
       [](const std::string& p) { writeSkeletonWrf(p, 200000, 200000, 90, 1, false); },
       {"memory budget", "GiB"}},
      {"truncated_file",
       [](const std::string& p) {
         writeSmallWrf(p + ".full");
         const auto size = std::filesystem::file_size(p + ".full");
         std::filesystem::copy_file(p + ".full", p);
         std::filesystem::resize_file(p, size / 2);
       },
       {"truncated"}},
      {"text_file",
       [](const std::string& p) { std::ofstream(p) << "This is not NetCDF, it is a README.\n"; },
       {"not a NetCDF file"}},
      {"empty_file", [](const std::string& p) { std::ofstream{p}; }, {"NetCDF"}},
      {"netcdf_but_neither_wrf_nor_icon",
       [](const std::string& p) {
         int nc = -1;
         ncCheck(nc_create(p.c_str(), NC_CLOBBER, &nc), "create");
         int d = -1, v = -1;
         ncCheck(nc_def_dim(nc, "station", 3, &d), "dim");
         ncCheck(nc_def_var(nc, "rainfall", NC_FLOAT, 1, &d, &v), "var");
         ncCheck(nc_close(nc), "close");
       },
       {"neither WRF", "ICON"}},
      {"icon_missing_z_ifc",
       [](const std::string& p) {
         writeSmallIcon(p);
         edit(p, [](int nc) { renameVar(nc, "z_ifc", "z_gone"); });
       },
       {"z_ifc", "missing"}},
      {"icon_clc_wrong_rank",
       [](const std::string& p) {
         writeSmallIcon(p);
         edit(p, [](int nc) { replaceVar(nc, "clc", NC_FLOAT, {"time", "lat", "lon"}); });
       },
       {"clc has 3 dims"}},
      {"icon_uneven_longitudes",
       [](const std::string& p) {
         writeSmallIcon(p);
         edit(p, [](int nc) {
           const double v = 9.95;
           const std::size_t index = 5;
           ncCheck(nc_put_var1_double(nc, varid(nc, "lon"), &index, &v), "lon");
         });
       },
       {"lon is not evenly spaced"}},
      {"icon_nan_in_qc",
       [](const std::string& p) {
         writeSmallIcon(p);
         edit(p, [](int nc) { putValue(nc, "qc", 11, std::numeric_limits<float>::quiet_NaN()); });
       },
       {"qc contains NaN"}},
      {"icon_missing_temperature",
       [](const std::string& p) {
         writeSmallIcon(p);
         edit(p, [](int nc) { renameVar(nc, "temp", "tmp_"); });
       },
       {"temp", "missing"}},
  };
  return cases;
}

class BadFile : public ::testing::TestWithParam<BadFileCase> {};

TEST_P(BadFile, IsAnInputErrorNamingFileAndVariable) {
  const BadFileCase& c = GetParam();
  ScratchDir dir("io");
  const std::string path = dir.file(std::string("bad_") + c.name + ".nc");
  c.make(path);
  try {
    const ModelFile file = openModelFile(path);
    ASSERT_FALSE(file.timesteps().empty());
    (void)file.load(0);
    FAIL() << "no InputError for " << c.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << "message does not name the file: " << message;
    for (const char* m : c.message_mentions) {
      EXPECT_NE(message.find(m), std::string::npos) << "message lacks '" << m << "': " << message;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Robustness, BadFile, ::testing::ValuesIn(badFileCases()),
                         [](const ::testing::TestParamInfo<BadFileCase>& param_info) {
                           return std::string(param_info.param.name);
                         });

TEST(Robustness, MissingFileIsAnInputError) { EXPECT_THROW(openModelFile("/nonexistent/wrfout_d01.nc"), InputError); }

TEST(Robustness, NegativeMixingRatiosAreClampedAndCounted) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_negative.nc");
  writeSmallWrf(path);
  edit(path, [](int nc) {
    putValue(nc, "QRAIN", 3, -1e-5f);
    putValue(nc, "QSNOW", 40, -2e-7f);
    putValue(nc, "QSNOW", 41, -2e-7f);
  });
  const ModelTimestep ts = openModelFile(path).load(0);
  EXPECT_EQ(ts.repairs.negative_clamped, 3);
  EXPECT_EQ(ts.q_kg_per_kg.at(Hydrometeor::Rain)[3], 0.0f);
  EXPECT_EQ(ts.q_kg_per_kg.at(Hydrometeor::Snow)[41], 0.0f);
}

TEST(Robustness, FillValuesInCondensateReadAsZeroAndCounted) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_fill.nc");
  writeSmallWrf(path);
  constexpr float kFill = 9.96921e36f;  // NetCDF's default float fill (NC_FILL_FLOAT)
  edit(path, [&](int nc) {
    const float fv = -1.0f;
    ncCheck(nc_redef(nc), "redef");
    ncCheck(nc_put_att_float(nc, varid(nc, "QICE"), "missing_value", NC_FLOAT, 1, &fv), "missing_value");
    ncCheck(nc_enddef(nc), "enddef");
    putValue(nc, "QICE", 100, fv);
    putValue(nc, "QCLOUD", 7, kFill);
  });
  const ModelTimestep ts = openModelFile(path).load(0);
  EXPECT_EQ(ts.repairs.missing_as_zero, 2);
  EXPECT_EQ(ts.repairs.negative_clamped, 0);
  EXPECT_EQ(ts.q_kg_per_kg.at(Hydrometeor::Ice)[100], 0.0f);
  EXPECT_EQ(ts.q_kg_per_kg.at(Hydrometeor::Cloud)[7], 0.0f);
}

TEST(Robustness, LengthOneDimensionsLoad) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_1x1x1.nc");
  writeSkeletonWrf(path, 1, 1, 1, 1, true);
  const ModelTimestep ts = openModelFile(path).load(0);
  EXPECT_EQ(ts.voxelCount(), 1u);
  EXPECT_NEAR(ts.height_m[0], 500.0f, 0.01f);  // midway between w levels at 0 and 1000 m
  EXPECT_NEAR(ts.pressure_pa[0], 85000.0f, 0.01f);
  EXPECT_EQ(ts.q_kg_per_kg.size(), 1u);
}

TEST(Robustness, SmallMemoryBudgetRejectsBeforeAllocating) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout.nc");
  writeSmallWrf(path);
  LoadOptions options;
  options.memory_budget_bytes = 1000;
  try {
    (void)openModelFile(path, options).load(0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("memory budget"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nph::io

namespace nph::io {
namespace {

TEST(Robustness, PackedShortFieldsWithFillValueAreUnpacked) {
  // cdo and DWD tools may write packed data: short with scale_factor/add_offset and _FillValue.
  ScratchDir dir("io");
  const std::string path = dir.file("icon_packed.nc");
  writeSmallIcon(path);
  const ModelTimestep original = loadIconTimestep(path, 0);
  const std::size_t n = original.voxelCount();
  std::vector<float> clc_percent(n);
  int ncid = -1;
  ncCheck(nc_open(path.c_str(), NC_NOWRITE, &ncid), "open");
  ncCheck(nc_get_var_float(ncid, varid(ncid, "clc"), clc_percent.data()), "clc");
  nc_close(ncid);
  edit(path, [&](int nc) {
    replaceVar(nc, "clc", NC_SHORT, {"time", "height", "lat", "lon"});
    const int id = varid(nc, "clc");
    const float scale = 0.01f, offset = 0.0f;
    const short fill = -1;
    ncCheck(nc_redef(nc), "redef");
    ncCheck(nc_put_att_float(nc, id, "scale_factor", NC_FLOAT, 1, &scale), "scale_factor");
    ncCheck(nc_put_att_float(nc, id, "add_offset", NC_FLOAT, 1, &offset), "add_offset");
    ncCheck(nc_put_att_short(nc, id, "_FillValue", NC_SHORT, 1, &fill), "_FillValue");
    const char* units = "%";
    ncCheck(nc_put_att_text(nc, id, "units", 1, units), "units");
    ncCheck(nc_enddef(nc), "enddef");
    std::vector<short> packed(n);
    for (std::size_t v = 0; v < n; ++v) packed[v] = static_cast<short>(std::lround(clc_percent[v] / 0.01f));
    packed[3] = fill;
    ncCheck(nc_put_var_short(nc, id, packed.data()), "put clc");
  });
  const ModelTimestep ts = loadIconTimestep(path, 0);
  EXPECT_EQ(ts.repairs.missing_as_zero, 1);
  ASSERT_EQ(ts.cloud_cover_fraction.size(), n);
  EXPECT_GT(*std::max_element(original.cloud_cover_fraction.begin(), original.cloud_cover_fraction.end()), 0.5f);
  int differing = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const float diff = std::abs(ts.cloud_cover_fraction[v] - original.cloud_cover_fraction[v]);
    if (diff > 1e-4f) ++differing;  // packing quantises to 0.01 % = 1e-4
  }
  EXPECT_LE(differing, 1);  // only the filled element may differ
}

TEST(Robustness, IconSeriesAcrossFilesIsTimeOrdered) {
  ScratchDir dir("io");
  datagen::IconSceneSpec s;
  s.nlon = 8;
  s.nlat = 6;
  s.nz = 4;
  s.ntimes = 2;
  datagen::writeIconScene(s, dir.file("a.nc"));
  const ModelSeries series = ModelSeries::open({dir.file("a.nc"), dir.file("a.nc")});
  ASSERT_EQ(series.size(), 4u);
  EXPECT_EQ(nph::geo::isoOrEmpty(series.at(0).time_utc), "2026-03-18T12:00:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(series.at(3).time_utc), "2026-03-18T13:00:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(series.load(3).time_utc), "2026-03-18T13:00:00Z");
}

}  // namespace
}  // namespace nph::io

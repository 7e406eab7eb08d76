// Real-world wrfout variants (issue 13 item 3): files that went through xarray, NCO, CDO or salem
// differ from raw WRF output. Each variant here is a real file, rewritten from a generated wrfout
// through NetCDF-C the way those tools change it, and must load to the same fields as the original:
//   - static fields (HGT, XLAT, XLONG) without the Time dimension (xarray/salem),
//   - a single-timestep file without any Time dimension (ds.isel(Time=0), ncwa -a Time),
//   - every variable in double (xarray's default encoding of float64, CDO -b F64),
//   - a cropped window (ncks -d west_east,...; salem subset) that keeps the parent's CEN_LAT/CEN_LON:
//     the loader places the grid by XLAT/XLONG and says so,
//   - variable attributes stripped and global ones missing or added (CDO/NCO history),
// and the sub-grid fields CLDFRA, TKE_PBL (or MYNN's QKE = 2 TKE), W, U, V are read when present.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "geo/grid_georeference.h"
#include "geo/map_projection.h"
#include "io/model_file.h"
#include "io/wrf_loader.h"
#include "io_test_support.h"
#include "wrf_hurricane.h"

namespace nph::io {
namespace {

using nph::test::ScratchDir;

struct Variant {
  bool static_without_time = false;  ///< HGT, XLAT, XLONG lose Time
  bool no_time = false;              ///< every variable loses Time (the source must have 1 timestep)
  bool doubles = false;              ///< NC_FLOAT variables become NC_DOUBLE
  bool strip_attributes = false;     ///< no variable attributes; MOAD_CEN_LAT, TRUELAT2, DT dropped
  bool extra_attributes = false;     ///< global history, per-variable coordinates/long_name
  bool qke = false;                  ///< TKE_PBL written as QKE = 2 TKE (MYNN)
  int crop_i0 = 0, crop_j0 = 0, crop_nx = 0, crop_ny = 0;  ///< window of mass points (0: none)
};

void nc(int status, const std::string& what) {
  if (status != NC_NOERR) throw std::runtime_error(what + ": " + nc_strerror(status));
}

/// Copies `src` to `dst` (NetCDF-4) through NetCDF-C, changed as `v` says.
void rewrite(const std::string& src, const std::string& dst, const Variant& v) {
  int in = -1, out = -1;
  nc(nc_open(src.c_str(), NC_NOWRITE, &in), "open " + src);
  nc(nc_create(dst.c_str(), NC_CLOBBER | NC_NETCDF4, &out), "create " + dst);
  int ndims = 0, unlimited = -1;
  nc_inq_ndims(in, &ndims);
  nc_inq_unlimdim(in, &unlimited);
  std::vector<int> dimOut(std::size_t(ndims), -1);
  const std::size_t nd_all = std::size_t(ndims);
  std::vector<std::size_t> inLen(nd_all), outLen(nd_all), offset(nd_all, 0);
  for (int d = 0; d < ndims; ++d) {
    char name[NC_MAX_NAME + 1] = {};
    nc_inq_dim(in, d, name, &inLen[std::size_t(d)]);
    const std::string n = name;
    std::size_t len = inLen[std::size_t(d)];
    if (v.crop_nx > 0 && (n == "west_east" || n == "west_east_stag")) {
      len = std::size_t(v.crop_nx) + (n == "west_east_stag" ? 1 : 0);
      offset[std::size_t(d)] = std::size_t(v.crop_i0);
    }
    if (v.crop_ny > 0 && (n == "south_north" || n == "south_north_stag")) {
      len = std::size_t(v.crop_ny) + (n == "south_north_stag" ? 1 : 0);
      offset[std::size_t(d)] = std::size_t(v.crop_j0);
    }
    outLen[std::size_t(d)] = len;
    if (v.no_time && n == "Time") continue;
    nc(nc_def_dim(out, name, d == unlimited ? NC_UNLIMITED : len, &dimOut[std::size_t(d)]), "def dim " + n);
  }
  int ngatts = 0, nvars = 0;
  nc_inq_natts(in, &ngatts);
  for (int a = 0; a < ngatts; ++a) {
    char name[NC_MAX_NAME + 1] = {};
    nc_inq_attname(in, NC_GLOBAL, a, name);
    const std::string n = name;
    if (v.strip_attributes && (n == "MOAD_CEN_LAT" || n == "TRUELAT2" || n == "DT")) continue;
    nc(nc_copy_att(in, NC_GLOBAL, name, out, NC_GLOBAL), "copy global " + n);
  }
  if (v.extra_attributes) {
    const std::string history = "Tue Dec  1 12:00:00 2026: ncks -O -d west_east,0, wrfout.nc out.nc";
    nc(nc_put_att_text(out, NC_GLOBAL, "history", history.size(), history.c_str()), "history");
  }
  nc_inq_nvars(in, &nvars);
  struct Var {
    int id_in, id_out;
    std::vector<int> dims_in;
    std::vector<bool> kept;
    nc_type type;
  };
  std::vector<Var> vars;
  const std::set<std::string> statics = {"HGT", "XLAT", "XLONG"};
  for (int id = 0; id < nvars; ++id) {
    char name[NC_MAX_NAME + 1] = {};
    nc_type type = NC_NAT;
    int nd = 0, natts = 0;
    int dims[NC_MAX_VAR_DIMS] = {};
    nc_inq_var(in, id, name, &type, &nd, dims, &natts);
    std::string n = name;
    Var var{id, -1, std::vector<int>(dims, dims + nd), {}, type};
    std::vector<int> outDims;
    for (int k = 0; k < nd; ++k) {
      char dn[NC_MAX_NAME + 1] = {};
      nc_inq_dimname(in, dims[k], dn);
      const bool drop = std::string(dn) == "Time" && (v.no_time || (v.static_without_time && statics.count(n) > 0));
      var.kept.push_back(!drop);
      if (!drop) outDims.push_back(dimOut[std::size_t(dims[k])]);
    }
    if (v.qke && n == "TKE_PBL") n = "QKE";
    const nc_type outType = v.doubles && type == NC_FLOAT ? NC_DOUBLE : type;
    nc(nc_def_var(out, n.c_str(), outType, int(outDims.size()), outDims.data(), &var.id_out), "def var " + n);
    for (int a = 0; a < natts && !v.strip_attributes; ++a) {
      char an[NC_MAX_NAME + 1] = {};
      nc_inq_attname(in, id, a, an);
      nc(nc_copy_att(in, id, an, out, var.id_out), "copy attribute " + n + ":" + an);
    }
    if (v.extra_attributes) {
      nc(nc_put_att_text(out, var.id_out, "long_name", n.size(), n.c_str()), "long_name");
    }
    var.type = type;
    vars.push_back(var);
  }
  nc(nc_enddef(out), "enddef");
  for (const Var& var : vars) {
    const std::size_t nd = var.dims_in.size();
    std::size_t total = 1;
    for (int d : var.dims_in) total *= inLen[std::size_t(d)];
    std::vector<std::size_t> outShape;
    for (std::size_t k = 0; k < nd; ++k) {
      if (var.kept[k]) outShape.push_back(outLen[std::size_t(var.dims_in[k])]);
    }
    std::size_t outTotal = 1;
    for (std::size_t s : outShape) outTotal *= s;
    // Output element → input element: kept dims offset by the crop, dropped dims (Time) at 0.
    auto inputIndex = [&](std::size_t o) {
      std::vector<std::size_t> idx(nd, 0);
      for (std::size_t k = nd, ko = outShape.size(); k-- > 0;) {
        if (!var.kept[k]) continue;
        --ko;
        idx[k] = o % outShape[ko] + offset[std::size_t(var.dims_in[k])];
        o /= outShape[ko];
      }
      std::size_t i = 0;
      for (std::size_t k = 0; k < nd; ++k) i = i * inLen[std::size_t(var.dims_in[k])] + idx[k];
      return i;
    };
    if (var.type == NC_CHAR) {
      std::vector<char> a(total), b(outTotal);
      nc(nc_get_var_text(in, var.id_in, a.data()), "get text");
      for (std::size_t o = 0; o < outTotal; ++o) b[o] = a[inputIndex(o)];
      std::vector<std::size_t> start(outShape.size(), 0);
      nc(nc_put_vara_text(out, var.id_out, start.data(), outShape.data(), b.data()), "put text");
      continue;
    }
    std::vector<double> a(total), b(outTotal);
    nc(nc_get_var_double(in, var.id_in, a.data()), "get");
    const bool isQke = v.qke && var.id_in >= 0 && [&] {
      char name[NC_MAX_NAME + 1] = {};
      nc_inq_varname(in, var.id_in, name);
      return std::string(name) == "TKE_PBL";
    }();
    for (std::size_t o = 0; o < outTotal; ++o) b[o] = a[inputIndex(o)] * (isQke ? 2.0 : 1.0);
    // Unlimited Time: put with explicit counts (nc_put_var on an unlimited dimension writes 0 records).
    std::vector<std::size_t> start(outShape.size(), 0);
    nc(nc_put_vara_double(out, var.id_out, start.data(), outShape.data(), b.data()), "put");
  }
  nc_close(in);
  nc(nc_close(out), "close " + dst);
}

struct Files {
  ScratchDir dir{"io"};
  std::string original;
  explicit Files(int ntimes, datagen::WrfCase weather = datagen::WrfCase::Hurricane) {
    datagen::WrfHurricaneSpec s =
        weather == datagen::WrfCase::CoarseStorm ? datagen::coarseStormSpec() : datagen::WrfHurricaneSpec{};
    s.ntimes = ntimes;
    if (weather == datagen::WrfCase::Hurricane) {
      s.nx = 30;
      s.ny = 24;
      s.nz = 10;
    }
    original = dir.file("wrfout_d01.nc");
    datagen::writeWrfHurricane(s, original);
  }
  std::string variant(const Variant& v, const std::string& name) {
    const std::string path = dir.file(name);
    rewrite(original, path, v);
    return path;
  }
};

void expectSameFields(const ModelTimestep& a, const ModelTimestep& b) {
  EXPECT_EQ(a.time_utc, b.time_utc);
  EXPECT_EQ(a.pressure_pa, b.pressure_pa);
  EXPECT_EQ(a.temperature_k, b.temperature_k);
  EXPECT_EQ(a.height_m, b.height_m);
  EXPECT_EQ(a.terrain_height_m, b.terrain_height_m);
  EXPECT_EQ(a.q_kg_per_kg, b.q_kg_per_kg);
  EXPECT_EQ(a.georef.lat_deg, b.georef.lat_deg);
  EXPECT_EQ(a.georef.lon_deg, b.georef.lon_deg);
  EXPECT_EQ(a.georef.x0, b.georef.x0);
  EXPECT_EQ(a.georef.y0, b.georef.y0);
}

TEST(WrfVariants, StaticFieldsWithoutTime) {
  Files f(2);
  Variant v;
  v.static_without_time = true;
  const std::string path = f.variant(v, "static.nc");
  ASSERT_EQ(listWrfTimes(path).size(), 2u);
  for (std::int64_t t = 0; t < 2; ++t) expectSameFields(loadWrfTimestep(path, t), loadWrfTimestep(f.original, t));
}

TEST(WrfVariants, SingleTimestepWithoutTimeDimension) {
  Files f(1);
  Variant v;
  v.no_time = true;
  const std::string path = f.variant(v, "notime.nc");
  ASSERT_EQ(listWrfTimes(path), listWrfTimes(f.original));
  expectSameFields(loadWrfTimestep(path, 0), loadWrfTimestep(f.original, 0));
  EXPECT_THROW((void)loadWrfTimestep(path, 1), InputError);
}

TEST(WrfVariants, VariablesInDouble) {
  Files f(1);
  Variant v;
  v.doubles = true;
  expectSameFields(loadWrfTimestep(f.variant(v, "double.nc"), 0), loadWrfTimestep(f.original, 0));
}

TEST(WrfVariants, MissingAndExtraAttributes) {
  Files f(1);
  Variant v;
  v.strip_attributes = true;
  v.extra_attributes = true;
  const ModelTimestep a = loadWrfTimestep(f.variant(v, "attributes.nc"), 0), b = loadWrfTimestep(f.original, 0);
  // The generator writes MOAD_CEN_LAT = CEN_LAT and TRUELAT2 ≠ TRUELAT1 (Lambert 20/30): without
  // TRUELAT2 the projection is tangent at TRUELAT1, and XLAT/XLONG then place the grid.
  EXPECT_EQ(a.pressure_pa, b.pressure_pa);
  EXPECT_EQ(a.q_kg_per_kg, b.q_kg_per_kg);
  EXPECT_EQ(a.georef.lat_deg, b.georef.lat_deg);
}

// A window cropped out of the domain keeps the parent's CEN_LAT/CEN_LON. The loader places the
// grid by XLAT/XLONG: the projected lon/lat of every mass point matches XLAT/XLONG, and the window's
// origin is the parent's shifted by the crop offset.
TEST(WrfVariants, CroppedWindowIsPlacedByXlatXlong) {
  Files f(1);
  Variant v;
  v.crop_i0 = 7;
  v.crop_j0 = 5;
  v.crop_nx = 16;
  v.crop_ny = 12;
  const ModelTimestep crop = loadWrfTimestep(f.variant(v, "crop.nc"), 0);
  const ModelTimestep full = loadWrfTimestep(f.original, 0);
  ASSERT_EQ(crop.nx, 16);
  ASSERT_EQ(crop.ny, 12);
  // 0.01 grid cells: XLAT/XLONG are float (~1e-5 deg, ~1 m of a 15 km cell).
  EXPECT_NEAR(crop.georef.x0, full.georef.x0 + 7 * full.georef.dx_m, 0.01 * full.georef.dx_m);
  EXPECT_NEAR(crop.georef.y0, full.georef.y0 + 5 * full.georef.dy_m, 0.01 * full.georef.dy_m);
  const geo::MapProjection projection(crop.georef.proj_definition);
  for (int j = 0; j < crop.ny; j += 3)
    for (int i = 0; i < crop.nx; i += 3) {
      const auto [lon, lat] = geo::gridLonLat(projection, crop.georef, i, j);
      const std::size_t c = std::size_t(j) * std::size_t(crop.nx) + std::size_t(i);
      EXPECT_NEAR(lat, crop.georef.lat_deg[c], 1e-4);
      EXPECT_NEAR(lon, crop.georef.lon_deg[c], 1e-4);
    }
  const auto& qc = crop.q_kg_per_kg.at(Hydrometeor::Cloud);
  const auto& qf = full.q_kg_per_kg.at(Hydrometeor::Cloud);
  for (int k = 0; k < crop.nz; ++k)
    for (int j = 0; j < crop.ny; ++j)
      for (int i = 0; i < crop.nx; ++i) ASSERT_EQ(qc[crop.index(i, j, k)], qf[full.index(i + 7, j + 5, k)]);
}

// CLDFRA, TKE_PBL (or QKE / 2), W, U and V on mass points when the file has them.
TEST(WrfVariants, SubgridFieldsAreReadWhenPresent) {
  Files f(1, datagen::WrfCase::CoarseStorm);
  const ModelTimestep ts = loadWrfTimestep(f.original, 0);
  for (const auto* field :
       {&ts.cloud_fraction, &ts.tke_m2_per_s2, &ts.wind_u_m_per_s, &ts.wind_v_m_per_s, &ts.wind_w_m_per_s}) {
    ASSERT_EQ(field->size(), ts.voxelCount());
  }
  EXPECT_GT(*std::max_element(ts.wind_w_m_per_s.begin(), ts.wind_w_m_per_s.end()), 3.0f);
  EXPECT_GT(*std::max_element(ts.tke_m2_per_s2.begin(), ts.tke_m2_per_s2.end()), 1.0f);
  EXPECT_EQ(*std::max_element(ts.cloud_fraction.begin(), ts.cloud_fraction.end()), 1.0f);
  EXPECT_GT(*std::max_element(ts.wind_u_m_per_s.begin(), ts.wind_u_m_per_s.end()), 0.0f);
  Variant v;
  v.qke = true;
  const ModelTimestep q = loadWrfTimestep(f.variant(v, "qke.nc"), 0);
  ASSERT_EQ(q.tke_m2_per_s2.size(), ts.voxelCount());
  for (std::size_t m = 0; m < ts.voxelCount(); m += 97) EXPECT_FLOAT_EQ(q.tke_m2_per_s2[m], ts.tke_m2_per_s2[m]);
  // The hurricane case has none of them: the fields stay empty.
  Files h(1);
  const ModelTimestep plain = loadWrfTimestep(h.original, 0);
  EXPECT_TRUE(plain.cloud_fraction.empty());
  EXPECT_TRUE(plain.tke_m2_per_s2.empty());
  EXPECT_TRUE(plain.wind_w_m_per_s.empty());
  EXPECT_EQ(plain.wind_u_m_per_s.size(), plain.voxelCount());  // the generator always writes U, V
}

// The detail fields deferred (LoadOptions::defer_detail, `convert`'s and the quick look's load;
// issue 19, peak memory): left out of the first load and marked, then read by loadDeferredDetail
// into the same timestep — bit for bit the fields of a whole load, on a static-field variant too
// (the deferred read finds each variable's Time dimension again). A file whose grid changed
// between the two reads is refused.
TEST(WrfVariants, DeferredDetailFieldsAreTheWholeLoads) {
  Files f(2, datagen::WrfCase::CoarseStorm);
  Variant sv;
  sv.static_without_time = true;
  for (const std::string& path : {f.original, f.variant(sv, "static.nc")}) {
    SCOPED_TRACE(path);
    LoadOptions defer;
    defer.defer_detail = true;
    const ModelTimestep whole = loadWrfTimestep(path, 1);
    ModelTimestep part = loadWrfTimestep(path, 1, defer);
    EXPECT_TRUE(part.detail_deferred);
    EXPECT_FALSE(whole.detail_deferred);
    for (const auto* field : {&part.cloud_fraction, &part.tke_m2_per_s2, &part.wind_u_m_per_s, &part.wind_v_m_per_s,
                              &part.wind_w_m_per_s}) {
      EXPECT_TRUE(field->empty());
    }
    expectSameFields(part, whole);
    loadDeferredDetail(part);
    EXPECT_FALSE(part.detail_deferred);
    ASSERT_EQ(part.cloud_fraction.size(), whole.voxelCount());
    EXPECT_EQ(part.cloud_fraction, whole.cloud_fraction);
    EXPECT_EQ(part.tke_m2_per_s2, whole.tke_m2_per_s2);
    EXPECT_EQ(part.wind_u_m_per_s, whole.wind_u_m_per_s);
    EXPECT_EQ(part.wind_v_m_per_s, whole.wind_v_m_per_s);
    EXPECT_EQ(part.wind_w_m_per_s, whole.wind_w_m_per_s);
    expectSameFields(part, whole);
    loadDeferredDetail(part);  // nothing deferred any more: a no-op
    EXPECT_EQ(part.wind_u_m_per_s, whole.wind_u_m_per_s);
  }
  LoadOptions defer;
  defer.defer_detail = true;
  ModelTimestep part = loadWrfTimestep(f.original, 0, defer);
  Variant crop;
  crop.crop_nx = 16;
  crop.crop_ny = 12;
  part.source_file = f.variant(crop, "changed.nc");  // the file "changed" under the timestep
  try {
    loadDeferredDetail(part);
    FAIL() << "a changed grid must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the file changed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nph::io

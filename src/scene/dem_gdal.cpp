// A user DEM through GDAL (scene/dem.h): opening and checking the raster, and the warp of its
// heights onto the flat view's world grids with GDAL's warper — the basemap's transformer chain
// (scene/gdal_support.h: destination pixel -> lon/lat through SceneGeoreference -> source pixel
// through GDAL's GenImgProj), one band, bilinear, the source's nodata honoured.
#include <cpl_conv.h>
#include <cpl_string.h>
#include <fmt/format.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdalwarper.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/input_file.h"
#include "core/log.h"
#include "io/field_checks.h"
#include "scene/dem.h"
#include "scene/gdal_support.h"
#include "scene/scene_setup.h"

namespace nph::scene {
using namespace gdal_detail;

struct DemRaster::Impl {
  std::string name;
  DatasetPtr dataset;
  int width = 0, height = 0;
  bool has_nodata = false;
  double nodata = 0.0;
};

const std::string& DemRaster::name() const { return impl_->name; }
int DemRaster::width() const { return impl_->width; }
int DemRaster::height() const { return impl_->height; }
bool DemRaster::hasNoData() const { return impl_->has_nodata; }

namespace {

/// What a DEM is, for the messages.
constexpr const char* kDemExpected =
    "a georeferenced raster GDAL reads (GeoTIFF/COG, VRT, ...) with one band of heights in metres above sea level";

/// Whether `unit` (GDALGetRasterUnitType) says metres; "" (unset) is taken as metres, the usual case.
bool unitIsMetres(std::string unit) {
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return unit.empty() || unit == "m" || unit == "metre" || unit == "metres" || unit == "meter" || unit == "meters";
}

}  // namespace

DemRaster DemRaster::open(const std::string& path) {
  registerGdal();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw InputError(fmt::format("{}: DEM not found (expected {})", path, kDemExpected));
  }
  requireRegularFile(path, "a DEM raster");
  auto impl = std::make_shared<Impl>();
  impl->name = path;
  GdalErrors errors;
  impl->dataset.reset(
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr));
  GDALDatasetH ds = impl->dataset.get();
  if (!ds) {
    throw InputError(fmt::format("{}: cannot read the DEM: not a raster GDAL reads ({}); expected {}", path,
                                 errors.message("no driver recognised it"), kDemExpected));
  }
  impl->width = GDALGetRasterXSize(ds);
  impl->height = GDALGetRasterYSize(ds);
  const int bands = GDALGetRasterCount(ds);
  if (bands != 1) {
    throw InputError(fmt::format("{}: DEM has {} bands, expected one band of heights [m]", path, bands));
  }
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  const GDALDataType type = GDALGetRasterDataType(band);
  switch (type) {
    case GDT_Int16:
    case GDT_UInt16:
    case GDT_Int32:
    case GDT_UInt32:
    case GDT_Float32:
    case GDT_Float64: break;
    default:
      throw InputError(fmt::format("{}: DEM band is {}, expected heights [m] as Int16, UInt16, Int32, UInt32, Float32 "
                                   "or Float64 (an 8-bit raster is a picture, not heights)",
                                   path, GDALGetDataTypeName(type)));
  }
  if (GDALGetRasterColorTable(band) != nullptr) {
    throw InputError(fmt::format("{}: DEM band has a colour palette; expected heights [m], not a picture", path));
  }
  const char* unit = GDALGetRasterUnitType(band);
  if (!unitIsMetres(unit ? unit : "")) {
    throw InputError(fmt::format("{}: DEM heights are in '{}', expected metres (convert with gdal_calc.py)", path,
                                 unit ? unit : ""));
  }
  const char* wkt = GDALGetProjectionRef(ds);
  std::array<double, 6> gt{};
  const bool hasGeoTransform = GDALGetGeoTransform(ds, gt.data()) == CE_None;
  const bool hasGcps = GDALGetGCPCount(ds) > 0 && GDALGetGCPProjection(ds) && *GDALGetGCPProjection(ds);
  if ((!wkt || !*wkt) && !hasGcps) {
    throw InputError(fmt::format("{}: DEM ({}x{} pixels) has no coordinate reference system; expected {} (GeoTIFF "
                                 "keys, a .prj/.aux.xml, a VRT with its SRS)",
                                 path, impl->width, impl->height, kDemExpected));
  }
  if (!hasGeoTransform && !hasGcps) {
    throw InputError(fmt::format("{}: DEM has a coordinate reference system but no geotransform (no pixel to map "
                                 "coordinates); expected {}",
                                 path, kDemExpected));
  }
  int hasNoData = 0;
  impl->nodata = GDALGetRasterNoDataValue(band, &hasNoData);
  impl->has_nodata = hasNoData != 0;
  DemRaster r;
  r.impl_ = std::move(impl);
  log::debug("DEM {}: {}x{} pixels, {} through GDAL", path, r.width(), r.height(), GDALGetDataTypeName(type));
  return r;
}

std::vector<float> warpDem(const DemRaster& dem, const SceneGeoreference& geo, const WorldRect& rect, int width,
                           int height) {
  if (width <= 0 || height <= 0 || !(rect.max_m.x > rect.min_m.x) || !(rect.max_m.y > rect.min_m.y)) {
    throw UsageError(fmt::format("warpDem: empty request ({}x{} pixels)", width, height));
  }
  registerGdal();
  const DemRaster::Impl& src = dem.impl();
  GdalErrors errors;
  // Band 1: height as read; band 2: coverage (the warper's alpha: the share of the bilinear
  // weight that fell on pixels with data).
  DatasetPtr dst(GDALCreate(GDALGetDriverByName("MEM"), "", width, height, 2, GDT_Float32, nullptr));
  const WorldGrid grid(geo, rect, width, height);
  ChainArg chain;
  chain.destination = &grid;
  const char* toLonLat[] = {"DST_SRS=+proj=longlat +datum=WGS84 +no_defs", nullptr};
  chain.lonlat_to_source = GDALCreateGenImgProjTransformer2(src.dataset.get(), nullptr, const_cast<char**>(toLonLat));
  if (!chain.lonlat_to_source) {
    throw InputError(fmt::format("{}: cannot transform the DEM's coordinate reference system to lon/lat: {}", src.name,
                                 errors.message("GDAL gave no reason")));
  }
  void* approx = GDALCreateApproxTransformer(chainTransform, &chain, kApproxError_px);
  GDALWarpOptions* wo = GDALCreateWarpOptions();
  wo->hSrcDS = src.dataset.get();
  wo->hDstDS = dst.get();
  wo->nBandCount = 1;
  wo->panSrcBands = static_cast<int*>(CPLMalloc(sizeof(int)));
  wo->panDstBands = static_cast<int*>(CPLMalloc(sizeof(int)));
  wo->panSrcBands[0] = 1;
  wo->panDstBands[0] = 1;
  wo->nDstAlphaBand = 2;
  if (src.has_nodata) {
    wo->padfSrcNoDataReal = static_cast<double*>(CPLMalloc(sizeof(double)));
    wo->padfSrcNoDataReal[0] = src.nodata;
  }
  // As the basemap's warp (gdal_support.h): beyond 2 source pixels per output pixel the bilinear
  // kernel is widened to the footprint — an average of the heights, not a point sample of a 30 m
  // DEM every 4 km.
  setSharedWarpOptions(wo, chain, approx, width, height);
  GDALWarpOperationH op = GDALCreateWarpOperation(wo);
  CPLErr err = op ? GDALChunkAndWarpImage(op, 0, 0, width, height) : CE_Failure;
  if (op) GDALDestroyWarpOperation(op);
  GDALDestroyWarpOptions(wo);
  GDALDestroyApproxTransformer(approx);
  GDALDestroyGenImgProjTransformer(chain.lonlat_to_source);
  std::vector<float> warped(std::size_t(width) * std::size_t(height) * 2);
  if (err == CE_None) {
    err = GDALDatasetRasterIO(dst.get(), GF_Read, 0, 0, width, height, warped.data(), width, height, GDT_Float32, 2,
                              nullptr, 2 * int(sizeof(float)), 2 * int(sizeof(float)) * width, int(sizeof(float)));
  }
  if (err != CE_None || errors.failed()) {
    throw InputError(fmt::format("{}: cannot read the DEM's heights (truncated or damaged file?): {}", src.name,
                                 errors.message("GDAL's warper failed")));
  }
  // Rows flipped to south first; coverage below a half is "no data" (the bilinear weights of the
  // DEM's own edge or of its nodata holes).
  std::vector<float> out(std::size_t(width) * std::size_t(height), NAN);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const std::size_t from = std::size_t(height - 1 - j) * std::size_t(width) + std::size_t(i);
      const float a = warped[2 * from + 1];
      if (!(a >= 0.5f)) continue;
      const float h_m = warped[2 * from];
      if (!(double(h_m) >= io::kLowestHeight_m && double(h_m) <= io::kHighestTerrain_m)) {
        const LonLat ll = geo.lonLatFromWorld(worldFromBasemapPixel(rect, width, height, i, height - 1 - j));
        throw InputError(fmt::format("{}: DEM height {} m at lon {:.4f}, lat {:.4f}; expected metres above sea level "
                                     "in [{}, {}] (io::kLowestHeight_m, io::kHighestTerrain_m) — a DEM in feet or "
                                     "centimetres, or an undeclared nodata value?",
                                     src.name, h_m, ll.lon_deg, ll.lat_deg, io::kLowestHeight_m,
                                     io::kHighestTerrain_m));
      }
      out[std::size_t(j) * std::size_t(width) + std::size_t(i)] = h_m;
    }
  }
  return out;
}

int demRefinementFor(const DemRaster& dem, const SceneGeoreference& geo, const volume::VolumeFrame& frame) {
  registerGdal();
  const DemRaster::Impl& src = dem.impl();
  const char* toLonLat[] = {"DST_SRS=+proj=longlat +datum=WGS84 +no_defs", nullptr};
  void* t = GDALCreateGenImgProjTransformer2(src.dataset.get(), nullptr, const_cast<char**>(toLonLat));
  if (!t) return 1;
  // The footprint's centre -> the DEM's pixel there -> its neighbours one pixel east and north ->
  // the world frame: the DEM's pixel size in world metres where the clouds are.
  const glm::dvec3 size = frame.size_m();
  const LonLat c = geo.lonLatFromWorld({0.5 * size.x, 0.5 * size.y});
  double x[3] = {c.lon_deg, 0.0, 0.0}, y[3] = {c.lat_deg, 0.0, 0.0}, z[3] = {0.0, 0.0, 0.0};
  int ok[3] = {0, 0, 0};
  int refine = 1;
  if (GDALGenImgProjTransform(t, TRUE, 1, x, y, z, ok) && ok[0] && x[0] >= 0.0 && y[0] >= 0.0 && x[0] <= src.width &&
      y[0] <= src.height) {
    x[1] = x[0] + 1.0, y[1] = y[0];
    x[2] = x[0], y[2] = y[0] + 1.0;
    if (GDALGenImgProjTransform(t, FALSE, 3, x, y, z, ok) && ok[0] && ok[1] && ok[2]) {
      const glm::dvec2 p0 = geo.worldFromLonLat({x[0], y[0]});
      const double pixel_m = std::min(glm::length(geo.worldFromLonLat({x[1], y[1]}) - p0),
                                      glm::length(geo.worldFromLonLat({x[2], y[2]}) - p0));
      const double cell_m = std::min(frame.voxel_size_m.x, frame.voxel_size_m.y);
      if (pixel_m > 0.0 && std::isfinite(pixel_m)) {
        const int side = std::max(frame.voxels.x, frame.voxels.y);
        refine = int(std::clamp(std::lround(cell_m / pixel_m), 1L, long(volume::kMaxTerrainRefine)));
        refine = std::max(1, std::min(refine, 4096 / side));
      }
    }
  }
  GDALDestroyGenImgProjTransformer(t);
  return refine;
}

volume::DemHeights demHeightsFor(const DemRaster& dem, const SceneGeoreference& geo, const volume::VolumeFrame& frame,
                                 bool far_field, int refine) {
  volume::DemHeights d;
  d.source = dem.name();
  if (refine < 1 || refine > volume::kMaxTerrainRefine) {
    throw UsageError(
        fmt::format("{}: DEM lattice refined {} times, expected 1 to {}", d.source, refine, volume::kMaxTerrainRefine));
  }
  d.refine = refine;
  const glm::dvec3 size = frame.size_m();
  d.model_m =
      warpDem(dem, geo, WorldRect{{0.0, 0.0}, {size.x, size.y}}, refine * frame.voxels.x, refine * frame.voxels.y);
  if (far_field) {
    const WorldRect far = farBasemapRectangle(frame);
    d.far_size = glm::ivec2(kFarBasemapPixels);
    d.far_min_m = far.min_m;
    d.far_max_m = far.max_m;
    d.far_m = warpDem(dem, geo, far, kFarBasemapPixels, kFarBasemapPixels);
  }
  const auto covered = [](const std::vector<float>& v) {
    return std::count_if(v.begin(), v.end(), [](float h) { return !std::isnan(h); });
  };
  log::info("DEM {}: heights on {} of {} lattice points ({}x the model's cell), {} of {} far pixels", dem.name(),
            covered(d.model_m), d.model_m.size(), refine, covered(d.far_m), d.far_m.size());
  return d;
}

}  // namespace nph::scene

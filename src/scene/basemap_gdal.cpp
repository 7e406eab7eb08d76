// Basemap imagery through GDAL (issue 14 item 3; scene/basemap.h): opening any raster GDAL reads,
// its georeference, and the warp into the data's map frame or onto the whole Earth.
//
// The warp is GDAL's own warper (gdalwarper.h: GDALChunkAndWarpImage, bilinear) driven by one
// transformer chain, destination pixel -> lon/lat -> source pixel:
//   * destination pixel -> lon/lat is ours: the flat view's world rectangle goes through
//     SceneGeoreference (the data's PROJ projection, the rotated pole, the manual offset of Nes 2008
//     §5.5.1), which no single CRS of GDAL's could express; the globe's is plate carrée;
//   * lon/lat -> source pixel is GDAL's GenImgProj transformer (the source's CRS and geotransform).
// GDAL's approximating transformer wraps the chain, as gdalwarp does, so PROJ runs only where a
// row is not linear to within kApproxError_px (the hand-written code this replaces projected
// 8-pixel cell corners for the same reason: PROJ costs ~0.3 µs a point).
#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <fmt/format.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdal_vrt.h>
#include <gdalwarper.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>

#include "core/error.h"
#include "core/input_file.h"
#include "core/limits.h"
#include "core/log.h"
#include "scene/basemap.h"
#include "scene/gdal_support.h"
#include "scene/image_codec.h"

namespace nph::scene {
using namespace gdal_detail;
namespace {

/// Lon/lat as the chain's middle CRS: WGS84 in lon, lat order whatever the GDAL/PROJ axis rules.
/// The data's lon/lat are those of its projection's sphere, used as WGS84 (scene/georeference.h).
constexpr const char* kLonLatSrs = "+proj=longlat +datum=WGS84 +no_defs";

/// How a band's values become linear radiometric reflectance-like values (header comment: Colour).
enum class Encoding { Srgb8, Srgb16, Linear };

std::string lonLatWkt() {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRSetFromUserInput(srs, kLonLatSrs);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  return out;
}

}  // namespace

struct BasemapRaster::Impl {
  std::string name;
  std::vector<DatasetPtr> keep;    ///< the opened file, then the VRT wrapping it (if any)
  GDALDatasetH dataset = nullptr;  ///< what the warper reads (the last of `keep`)
  int width = 0, height = 0;       ///< of the source itself (not the wrap VRT)
  std::vector<int> colour_bands;   ///< 3 band indices (grey: the same band thrice)
  int alpha_band = 0;              ///< 0: none
  Encoding encoding = Encoding::Linear;
  bool whole_earth = false;
  std::vector<float> memory;  ///< fromEquirectangular: the pixels a MEM dataset points at
  /// The file's reduced-resolution levels (GeoTIFF/COG overviews, .ovr files): width of each,
  /// finest first; empty for sources without (or from memory). See overviewFor.
  std::vector<int> overview_widths;
  int overview_level = -1;  ///< this raster is the file at that overview level (-1: full resolution)

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    while (!keep.empty()) keep.pop_back();  // the VRT before the dataset its sources read
  }
};

const std::string& BasemapRaster::name() const { return impl_->name; }
int BasemapRaster::width() const { return impl_->width; }
int BasemapRaster::height() const { return impl_->height; }
bool BasemapRaster::wholeEarth() const { return impl_->whole_earth; }
bool BasemapRaster::integerCoded() const { return impl_->encoding != Encoding::Linear; }
const std::vector<int>& BasemapRaster::overviewWidths() const { return impl_->overview_widths; }
int BasemapRaster::overviewLevel() const { return impl_->overview_level; }

namespace {

bool geographicSrs(const char* wkt) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(wkt);
  const bool geographic = srs && OSRIsGeographic(srs);
  if (srs) OSRDestroySpatialReference(srs);
  return geographic;
}

/// Whole-Earth lon/lat sources: a VRT three source widths wide (the image at −540, −180 and 180°),
/// so the bilinear warp across the antimeridian sees the pixels on both sides, as the GPU's
/// GL_REPEAT does on the globe.
DatasetPtr wrapAroundTheEarth(GDALDatasetH src, const std::array<double, 6>& gt, const std::string& wkt, int w, int h) {
  VRTDatasetH vrt = VRTCreate(3 * w, h);
  for (int b = 1; b <= GDALGetRasterCount(src); ++b) {
    GDALRasterBandH sb = GDALGetRasterBand(src, b);
    GDALAddBand(vrt, GDALGetRasterDataType(sb), nullptr);
    auto* vb = static_cast<VRTSourcedRasterBandH>(GDALGetRasterBand(vrt, b));
    GDALSetRasterColorInterpretation(vb, GDALGetRasterColorInterpretation(sb));
    for (int copy = 0; copy < 3; ++copy) {
      VRTAddSimpleSource(vb, sb, 0, 0, w, h, copy * w, 0, w, h, "near", VRT_NODATA_UNSET);
    }
  }
  std::array<double, 6> wrapped = gt;
  wrapped[0] -= 360.0;
  GDALSetGeoTransform(vrt, wrapped.data());
  GDALSetProjection(vrt, wkt.c_str());
  return DatasetPtr(vrt);
}

/// Bands, encoding, CRS and whole-Earth test of `impl.dataset` (just opened), wrapping it when it
/// covers the Earth. `what` names the source in messages.
void describe(BasemapRaster::Impl& impl) {
  GDALDatasetH ds = impl.dataset;
  const std::string& path = impl.name;
  impl.width = GDALGetRasterXSize(ds);
  impl.height = GDALGetRasterYSize(ds);
  limits::requireProductWithin(path, "basemap width x height",
                               {std::uint64_t(std::max(impl.width, 0)), std::uint64_t(std::max(impl.height, 0))},
                               limits::kMaxBasemapSourcePixels,
                               "limits::kMaxBasemapSourcePixels; downsample the raster or cut the region needed");
  const int bands = GDALGetRasterCount(ds);
  if (bands < 1 || bands > 4) {
    throw InputError(fmt::format("{}: basemap has {} bands, expected 1-4 (grey, grey+alpha, RGB, RGBA)", path, bands));
  }
  GDALRasterBandH first = GDALGetRasterBand(ds, 1);
  if (GDALGetRasterColorTable(first) != nullptr) {
    throw InputError(fmt::format("{}: basemap has a colour palette; expected grey or RGB bands (expand it: "
                                 "gdal_translate -expand rgb)",
                                 path));
  }
  const GDALDataType type = GDALGetRasterDataType(first);
  switch (type) {
    case GDT_Byte: impl.encoding = Encoding::Srgb8; break;
    case GDT_UInt16: impl.encoding = Encoding::Srgb16; break;
    case GDT_Float32:
    case GDT_Float64: impl.encoding = Encoding::Linear; break;
    default:
      throw InputError(
          fmt::format("{}: basemap bands are {}, expected Byte or UInt16 (sRGB) or Float32/Float64 (linear)", path,
                      GDALGetDataTypeName(type)));
  }
  const bool hasAlpha =
      bands == 2 || bands == 4 || GDALGetRasterColorInterpretation(GDALGetRasterBand(ds, bands)) == GCI_AlphaBand;
  const int colour = hasAlpha ? bands - 1 : bands;
  impl.alpha_band = hasAlpha ? bands : 0;
  impl.colour_bands = colour >= 3 ? std::vector<int>{1, 2, 3} : std::vector<int>{1, 1, 1};

  std::array<double, 6> gt{};
  const bool hasGeoTransform = GDALGetGeoTransform(ds, gt.data()) == CE_None;
  const char* wktC = GDALGetProjectionRef(ds);
  std::string wkt = wktC ? wktC : "";
  const bool hasCrs = !wkt.empty();
  const bool hasGcps = GDALGetGCPCount(ds) > 0 && GDALGetGCPProjection(ds) && *GDALGetGCPProjection(ds);
  if (!hasCrs && !hasGcps) {
    // Georeferenced without a CRS is a defect; no georeference at all on a 2:1 image is the
    // documented whole-Earth plate carrée (Blue Marble).
    if (hasGeoTransform || std::abs(impl.width - 2 * impl.height) > 1) {
      throw InputError(fmt::format(
          "{}: basemap ({}x{} pixels) has no coordinate reference system{}; expected a georeferenced raster "
          "(GeoTIFF keys, a world file with its .aux.xml, a VRT with its SRS) or a whole-Earth equirectangular "
          "image without georeference, covering 360°×180° (width = 2·height)",
          path, impl.width, impl.height, hasGeoTransform ? " (it has a geotransform, but in what?)" : ""));
    }
    gt = {-180.0, 360.0 / impl.width, 0.0, 90.0, 0.0, -180.0 / impl.height};
    wkt = lonLatWkt();
  } else if (!hasGeoTransform && !hasGcps) {
    throw InputError(fmt::format("{}: basemap has a coordinate reference system but no geotransform (no pixel to "
                                 "map coordinates); expected a georeferenced raster",
                                 path));
  }
  const double span = gt[1] * impl.width;
  impl.whole_earth = hasGeoTransform || !hasCrs ? (gt[2] == 0.0 && gt[4] == 0.0 && geographicSrs(wkt.c_str()) &&
                                                   std::abs(std::abs(span) - 360.0) < std::abs(gt[1]))
                                                : false;
  if (impl.whole_earth) {
    impl.keep.push_back(wrapAroundTheEarth(ds, gt, wkt, impl.width, impl.height));
    impl.dataset = impl.keep.back().get();
  }
}

/// The pre-GDAL reader, for what GDAL cannot open: linear RGB of a float image OpenImageIO reads
/// (EXR, HDR), or nullopt (integer images are GDAL's: PNG, JPEG, TIFF).
std::optional<LinearRgbImage> loadWithOpenImageIo(const std::string& path) {
  // Through the image codec module (scene/image_codec.h): OpenImageIO is loaded only here.
  auto raw = image_codec::readFloat(path, [&](int w, int h) {
    limits::requireProductWithin(path, "basemap width x height",
                                 {std::uint64_t(std::max(w, 0)), std::uint64_t(std::max(h, 0))},
                                 limits::kMaxBasemapPixels, "limits::kMaxBasemapPixels; downsample the image");
  });
  if (!raw) return std::nullopt;
  const std::size_t n = std::size_t(raw->width) * std::size_t(raw->height);
  const std::size_t nc = std::size_t(raw->channels);
  LinearRgbImage img{raw->width, raw->height, std::vector<float>(n * 3)};
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t c = 0; c < 3; ++c) img.rgb[p * 3 + c] = raw->pixels[p * nc + (nc >= 3 ? c : 0)];
  }
  return img;
}

}  // namespace

BasemapRaster BasemapRaster::open(const std::string& path) {
  registerGdal();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw InputError(fmt::format("{}: basemap image not found (expected a raster GDAL reads: GeoTIFF, VRT, MBTiles, "
                                 "PNG/JPEG with a world file, or a whole-Earth equirectangular image such as Blue "
                                 "Marble from Debian's marble-qt-data)",
                                 path));
  }
  requireRegularFile(path, "a basemap image");  // a FIFO would block the decoder forever
  auto impl = std::make_shared<Impl>();
  impl->name = path;
  GdalErrors errors;
  GDALDatasetH ds =
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr);
  if (!ds) {
    // Formats Debian's GDAL has no driver for (OpenEXR, Radiance HDR: linear whole-Earth images)
    // are read with OpenImageIO, as before issue 14, and go through the same warper from memory.
    if (auto image = loadWithOpenImageIo(path)) return fromEquirectangular(*image, path);
    throw InputError(fmt::format("{}: cannot read the basemap image: not a raster GDAL reads ({})", path,
                                 errors.message("no driver recognised it")));
  }
  impl->keep.emplace_back(ds);
  impl->dataset = ds;
  describe(*impl);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  for (int i = 0; i < GDALGetOverviewCount(band); ++i) {
    if (GDALRasterBandH o = GDALGetOverview(band, i)) impl->overview_widths.push_back(GDALGetRasterBandXSize(o));
  }
  BasemapRaster r;
  r.impl_ = std::move(impl);
  log::debug("basemap {}: {}x{} pixels through GDAL ({}){}", path, r.width(), r.height(),
             GDALGetDriverShortName(GDALGetDatasetDriver(ds)), r.wholeEarth() ? ", whole Earth" : "");
  return r;
}

BasemapRaster BasemapRaster::atOverview(int level) const {
  if (level < 0 || std::size_t(level) >= impl_->overview_widths.size()) {
    throw UsageError(
        fmt::format("{}: no overview level {} (the file has {})", impl_->name, level, impl_->overview_widths.size()));
  }
  auto impl = std::make_shared<Impl>();
  impl->name = impl_->name;
  impl->overview_level = level;
  const std::string option = fmt::format("OVERVIEW_LEVEL={}", level);
  const char* options[] = {option.c_str(), nullptr};
  GdalErrors errors;
  GDALDatasetH ds = GDALOpenEx(impl_->name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, nullptr,
                               options, nullptr);
  if (!ds) {
    throw InputError(fmt::format("{}: cannot open its overview level {}: {}", impl_->name, level,
                                 errors.message("GDAL gave no reason")));
  }
  impl->keep.emplace_back(ds);
  impl->dataset = ds;
  describe(*impl);
  BasemapRaster r;
  r.impl_ = std::move(impl);
  return r;
}

BasemapRaster BasemapRaster::fromEquirectangular(const LinearRgbImage& image, const std::string& name) {
  registerGdal();
  // The same 2:1 contract as EquirectangularImage (a MEM dataset has no georeference).
  (void)EquirectangularImage(image, name);
  auto impl = std::make_shared<Impl>();
  impl->name = name;
  impl->memory = image.rgb;
  GDALDriverH mem = GDALGetDriverByName("MEM");
  GDALDatasetH ds = GDALCreate(mem, "", image.width, image.height, 0, GDT_Float32, nullptr);
  for (int b = 0; b < 3; ++b) {
    // Bands point into `memory` (pixel-interleaved RGB), no copy.
    const std::string ptr = fmt::format("DATAPOINTER={:p}", static_cast<void*>(impl->memory.data() + b));
    const std::string pixelOffset = fmt::format("PIXELOFFSET={}", 3 * sizeof(float));
    const std::string lineOffset = fmt::format("LINEOFFSET={}", 3 * sizeof(float) * std::size_t(image.width));
    const char* options[] = {ptr.c_str(), pixelOffset.c_str(), lineOffset.c_str(), nullptr};
    GDALAddBand(ds, GDT_Float32, const_cast<char**>(options));
  }
  impl->keep.emplace_back(ds);
  impl->dataset = ds;
  describe(*impl);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  for (int i = 0; i < GDALGetOverviewCount(band); ++i) {
    if (GDALRasterBandH o = GDALGetOverview(band, i)) impl->overview_widths.push_back(GDALGetRasterBandXSize(o));
  }
  BasemapRaster r;
  r.impl_ = std::move(impl);
  return r;
}

namespace {

/// The globe: the whole Earth in plate carrée, pixel-is-area (equirectUv's convention).
class EquirectangularGrid final : public DestinationGrid {
 public:
  EquirectangularGrid(int w, int h) : w_(w), h_(h) {}
  void lonLatFromPixel(double* x, double* y, int n) const override {
    for (int i = 0; i < n; ++i) {
      x[i] = -180.0 + x[i] / w_ * 360.0;
      y[i] = 90.0 - y[i] / h_ * 180.0;
    }
  }
  bool pixelFromLonLat(double& x, double& y) const override {
    x = (x + 180.0) / 360.0 * w_;
    y = (90.0 - y) / 180.0 * h_;
    return true;
  }

 private:
  int w_, h_;
};

/// The overview of `raster` to read for `ratio` source pixels per destination pixel: the coarsest
/// whose reduction factor (full width / its width) is at most the smaller ratio, so the output
/// still gets at least one source pixel per pixel — gdalwarp's `-ovr AUTO` rule; -1 = full
/// resolution. The rest of the reduction is the warper's widened bilinear kernel (XSCALE/YSCALE).
int overviewFor(const BasemapRaster& raster, const std::array<double, 2>& ratio) {
  const double wanted = std::min(ratio[0], ratio[1]);
  int best = -1;
  double bestFactor = 1.0;
  const std::vector<int>& widths = raster.overviewWidths();
  for (std::size_t i = 0; i < widths.size(); ++i) {
    const double factor = double(raster.width()) / double(std::max(widths[i], 1));
    if (factor <= wanted * (1.0 + 1e-9) && factor > bestFactor) {
      best = int(i);
      bestFactor = factor;
    }
  }
  return best;
}

/// Warps `layers` (bottom first) onto `grid` into `rgb` (w·h·3, pixel-interleaved, linear).
/// Returns the number of pixels no layer covered.
std::size_t warpInto(const std::vector<BasemapRaster>& layers, const DestinationGrid& grid, int w, int h,
                     std::vector<float>& rgb) {
  registerGdal();
  GDALDriverH memDriver = GDALGetDriverByName("MEM");
  // Bands 1-3: colour as read (codes or linear values); band 4: coverage (the warper's alpha).
  DatasetPtr dst(GDALCreate(memDriver, "", w, h, 4, GDT_Float32, nullptr));
  std::vector<float> decoded(std::size_t(w) * std::size_t(h) * 3, 0.0f), coverage(std::size_t(w) * std::size_t(h));
  for (const BasemapRaster& fullLayer : layers) {
    GdalErrors errors;
    const char* toLonLat[] = {"DST_SRS=+proj=longlat +datum=WGS84 +no_defs", nullptr};
    const auto transformerOf = [&](const BasemapRaster::Impl& raster) {
      void* t = GDALCreateGenImgProjTransformer2(raster.dataset, nullptr, const_cast<char**>(toLonLat));
      if (!t) {
        throw InputError(fmt::format("{}: cannot transform the basemap's coordinate reference system to lon/lat: {}",
                                     raster.name, errors.message("GDAL gave no reason")));
      }
      return t;
    };
    ChainArg chain;
    chain.destination = &grid;
    chain.lonlat_to_source = transformerOf(fullLayer.impl());
    // Imagery LOD (issue 14 item 3): read the coarsest overview that still has a source pixel per
    // output pixel (gdalwarp -ovr AUTO), not the full resolution to filter it down here.
    BasemapRaster layer = fullLayer;
    const int level = overviewFor(fullLayer, sourcePerDestination(chain, w, h));
    if (level >= 0) {
      layer = fullLayer.atOverview(level);
      GDALDestroyGenImgProjTransformer(chain.lonlat_to_source);
      chain.lonlat_to_source = transformerOf(layer.impl());
      log::info("basemap {}: read at overview level {} ({} pixels wide, {} at full resolution)", layer.name(), level,
                layer.width(), fullLayer.width());
    }
    const BasemapRaster::Impl& src = layer.impl();
    void* genImg = chain.lonlat_to_source;
    void* approx = GDALCreateApproxTransformer(chainTransform, &chain, kApproxError_px);

    GDALWarpOptions* wo = GDALCreateWarpOptions();
    wo->hSrcDS = src.dataset;
    wo->hDstDS = dst.get();
    wo->nBandCount = 3;
    wo->panSrcBands = static_cast<int*>(CPLMalloc(sizeof(int) * 3));
    wo->panDstBands = static_cast<int*>(CPLMalloc(sizeof(int) * 3));
    for (int b = 0; b < 3; ++b) {
      wo->panSrcBands[b] = src.colour_bands[std::size_t(b)];
      wo->panDstBands[b] = b + 1;
    }
    wo->nSrcAlphaBand = src.alpha_band;
    wo->nDstAlphaBand = 4;
    // Each layer starts from a blank destination and is composited below, by its coverage.
    setSharedWarpOptions(wo, chain, approx, w, h);
    if (src.alpha_band != 0) {
      const char* alphaMax = src.encoding == Encoding::Srgb8 ? "255" : src.encoding == Encoding::Srgb16 ? "65535" : "1";
      wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "SRC_ALPHA_MAX", alphaMax);
    }
    GDALWarpOperationH op = GDALCreateWarpOperation(wo);
    CPLErr err = op ? GDALChunkAndWarpImage(op, 0, 0, w, h) : CE_Failure;
    if (op) GDALDestroyWarpOperation(op);
    GDALDestroyWarpOptions(wo);  // frees the band lists, not the transformer
    GDALDestroyApproxTransformer(approx);
    GDALDestroyGenImgProjTransformer(genImg);
    std::vector<float> layerRgb(std::size_t(w) * std::size_t(h) * 4);
    if (err == CE_None) {
      err = GDALDatasetRasterIO(dst.get(), GF_Read, 0, 0, w, h, layerRgb.data(), w, h, GDT_Float32, 4, nullptr,
                                4 * int(sizeof(float)), 4 * int(sizeof(float)) * w, int(sizeof(float)));
    }
    if (err != CE_None || errors.failed()) {
      throw InputError(fmt::format("{}: cannot read the basemap's pixels (truncated or damaged file?): {}", src.name,
                                   errors.message("GDAL's warper failed")));
    }
    // Decode (header comment: Colour). Integer rasters were interpolated as codes; the curve is
    // applied to the interpolated code through a 4097-entry table (max error < 1e-6 against pow).
    static const std::array<float, 4097> srgbTable = [] {
      std::array<float, 4097> t{};
      for (std::size_t i = 0; i < t.size(); ++i) t[i] = srgbToLinear(float(i) / 4096.0f);
      return t;
    }();
    const float scale = src.encoding == Encoding::Srgb8 ? 1.0f / 255.0f : 1.0f / 65535.0f;
    auto decode = [&](float v) {
      if (src.encoding == Encoding::Linear) return v;
      const float e = std::clamp(v * scale, 0.0f, 1.0f) * 4096.0f;
      const auto i = std::min(static_cast<std::size_t>(e), std::size_t(4095));
      return srgbTable[i] + (e - float(i)) * (srgbTable[i + 1] - srgbTable[i]);
    };
    for (std::size_t p = 0; p < coverage.size(); ++p) {
      // The warper's alpha is the share of the filter's weight that fell on source data; colour
      // was normalised by it, so a layer replaces what is below in proportion to it.
      const float a = std::clamp(layerRgb[p * 4 + 3], 0.0f, 1.0f);
      if (a <= 0.0f) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        decoded[p * 3 + c] = (1.0f - a) * decoded[p * 3 + c] + a * decode(layerRgb[p * 4 + c]);
      }
      coverage[p] = std::max(coverage[p], a);
    }
  }
  rgb = std::move(decoded);
  return std::size_t(std::count(coverage.begin(), coverage.end(), 0.0f));
}

bool allIntegerCoded(const std::vector<BasemapRaster>& layers) {
  return std::all_of(layers.begin(), layers.end(), [](const BasemapRaster& l) { return l.integerCoded(); });
}

}  // namespace

LinearRgbImage reprojectBasemap(const std::vector<BasemapRaster>& layers, const SceneGeoreference& geo,
                                const WorldRect& rect, int width, int height) {
  if (width <= 0 || height <= 0 || !(rect.max_m.x > rect.min_m.x) || !(rect.max_m.y > rect.min_m.y) || layers.empty()) {
    throw UsageError(
        fmt::format("reprojectBasemap: empty request ({}x{} pixels, {} layers)", width, height, layers.size()));
  }
  LinearRgbImage out{width, height, {}, allIntegerCoded(layers)};
  const WorldGrid grid(geo, rect, width, height);
  const std::size_t uncovered = warpInto(layers, grid, width, height, out.rgb);
  if (uncovered > 0) {
    log::debug("basemap {}: {} of {} pixels have no imagery (outside the raster or the projection '{}') and are black",
               layers.back().name(), uncovered, std::size_t(width) * std::size_t(height),
               geo.projection().definition());
  }
  return out;
}

LinearRgbImage reprojectEquirectangular(const std::vector<BasemapRaster>& layers, int width, int height) {
  if (width <= 0 || height <= 0 || layers.empty()) {
    throw UsageError(
        fmt::format("reprojectEquirectangular: empty request ({}x{} pixels, {} layers)", width, height, layers.size()));
  }
  limits::requireProductWithin(layers.back().name(), "whole-Earth basemap width x height",
                               {std::uint64_t(width), std::uint64_t(height)}, limits::kMaxBasemapPixels,
                               "limits::kMaxBasemapPixels");
  LinearRgbImage out{width, height, {}, allIntegerCoded(layers)};
  const EquirectangularGrid grid(width, height);
  (void)warpInto(layers, grid, width, height, out.rgb);
  return out;
}

glm::ivec2 equirectangularSizeFor(const BasemapRaster& raster) {
  constexpr int kMaxWidth = 8192;  // × 4096 = limits::kMaxBasemapPixels
  int w = raster.width();
  if (!raster.wholeEarth()) {
    // The source's own resolution in degrees, from GDAL's suggestion for a lon/lat output.
    GdalErrors errors;
    const char* toLonLat[] = {"DST_SRS=+proj=longlat +datum=WGS84 +no_defs", nullptr};
    void* genImg = GDALCreateGenImgProjTransformer2(raster.impl().dataset, nullptr, const_cast<char**>(toLonLat));
    double gt[6] = {};
    int sw = 0, sh = 0;
    if (!genImg ||
        GDALSuggestedWarpOutput(raster.impl().dataset, GDALGenImgProjTransform, genImg, gt, &sw, &sh) != CE_None) {
      if (genImg) GDALDestroyGenImgProjTransformer(genImg);
      throw InputError(fmt::format("{}: cannot find the basemap's extent in lon/lat: {}", raster.name(),
                                   errors.message("GDAL gave no reason")));
    }
    GDALDestroyGenImgProjTransformer(genImg);
    w = static_cast<int>(std::min(double(kMaxWidth), std::ceil(360.0 / std::max(gt[1], 1e-9))));
  }
  w = std::clamp(w, 2, kMaxWidth);
  w += w % 2;
  return {w, w / 2};
}

EquirectangularImage EquirectangularImage::load(const std::string& path) {
  const BasemapRaster raster = BasemapRaster::open(path);
  const glm::ivec2 size = equirectangularSizeFor(raster);
  return EquirectangularImage(reprojectEquirectangular({raster}, size.x, size.y), path);
}

}  // namespace nph::scene

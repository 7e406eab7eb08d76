#pragma once
// GDAL plumbing shared by the basemap (scene/basemap_gdal.cpp) and the DEM (scene/dem_gdal.cpp):
// error capture, dataset ownership and the warper's transformer chain, destination pixel -> lon/lat
// -> source pixel (the header comment of basemap_gdal.cpp). Internal to the scene module.
#include <cpl_error.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdalwarper.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "scene/basemap.h"
#include "scene/georeference.h"

namespace nph::scene::gdal_detail {

/// Largest error [source pixels] the approximating transformer may make; GDAL's gdalwarp uses
/// 0.125. 0.01 keeps the error of a lon/lat-coded test image within 1e-4° at 0.25°/pixel... and far
/// below anything bilinear filtering shows.
inline constexpr double kApproxError_px = 0.0005;
/// The warper's working memory (it splits the output into chunks that fit).
inline constexpr double kWarpMemory_bytes = 256.0 * 1024 * 1024;

/// GDALAllRegister, once per process.
void registerGdal();

/// Collects GDAL's error messages while alive (thread-local handler stack), for InputErrors that
/// say what GDAL said.
class GdalErrors {
 public:
  GdalErrors() {
    CPLPushErrorHandlerEx(&GdalErrors::handler, this);
    CPLErrorReset();
  }
  ~GdalErrors() { CPLPopErrorHandler(); }
  GdalErrors(const GdalErrors&) = delete;
  GdalErrors& operator=(const GdalErrors&) = delete;
  /// The first failure's message, or `fallback` when GDAL gave none.
  std::string message(const char* fallback) const { return first_.empty() ? std::string(fallback) : first_; }
  bool failed() const { return !first_.empty(); }

 private:
  static void CPL_STDCALL handler(CPLErr level, CPLErrorNum, const char* msg) {
    auto* self = static_cast<GdalErrors*>(CPLGetErrorHandlerUserData());
    if (level >= CE_Failure && self->first_.empty()) self->first_ = msg ? msg : "";
    if (level == CE_Warning) log::debug("GDAL: {}", msg ? msg : "");
  }
  std::string first_;
};

struct DatasetCloser {
  void operator()(void* ds) const {
    if (ds) GDALClose(static_cast<GDALDatasetH>(ds));
  }
};
using DatasetPtr = std::unique_ptr<void, DatasetCloser>;

/// Destination pixel (x, y continuous, (0, 0) = top-left corner) <-> lon/lat [deg].
class DestinationGrid {
 public:
  virtual ~DestinationGrid() = default;
  /// In place: x, y -> lon, lat; NaN where there is none.
  virtual void lonLatFromPixel(double* x, double* y, int n) const = 0;
  /// In place: lon, lat -> x, y; false where there is none.
  virtual bool pixelFromLonLat(double& x, double& y) const = 0;
};

/// The flat view: a world rectangle of the data's frame (row 0 = north edge, as worldFromBasemapPixel).
class WorldGrid final : public DestinationGrid {
 public:
  WorldGrid(const SceneGeoreference& geo, const WorldRect& rect, int w, int h) : geo_(geo), rect_(rect), w_(w), h_(h) {}
  void lonLatFromPixel(double* x, double* y, int n) const override {
    xy_.resize(std::size_t(n) * 2);
    const glm::dvec2 ext = rect_.max_m - rect_.min_m;
    for (int i = 0; i < n; ++i) {
      xy_[2 * std::size_t(i)] = rect_.min_m.x + x[i] / w_ * ext.x;
      xy_[2 * std::size_t(i) + 1] = rect_.max_m.y - y[i] / h_ * ext.y;
    }
    geo_.lonLatFromWorldBatch(xy_.data(), std::size_t(n));
    for (int i = 0; i < n; ++i) {
      x[i] = xy_[2 * std::size_t(i)];
      y[i] = xy_[2 * std::size_t(i) + 1];
    }
  }
  bool pixelFromLonLat(double& x, double& y) const override {
    try {
      const glm::dvec2 wxy = geo_.worldFromLonLat({x, y});
      const glm::dvec2 ext = rect_.max_m - rect_.min_m;
      x = (wxy.x - rect_.min_m.x) / ext.x * w_;
      y = (rect_.max_m.y - wxy.y) / ext.y * h_;
      return std::isfinite(x) && std::isfinite(y);
    } catch (const Error&) {
      return false;
    }
  }

 private:
  const SceneGeoreference& geo_;
  WorldRect rect_;
  int w_, h_;
  mutable std::vector<double> xy_;
};

/// The transformer chain's argument. GDAL reads a transformer argument's first bytes for a
/// signature (GDALTransformerInfo) to recognise its own kinds; ours starts with a zeroed one.
struct ChainArg {
  GDALTransformerInfo info{};
  const DestinationGrid* destination = nullptr;
  void* lonlat_to_source = nullptr;  ///< GenImgProj: "dst" = lon/lat, "src" = source pixel
};

/// The chain as a GDALTransformerFunc (`arg` is a ChainArg).
int chainTransform(void* arg, int dstToSrc, int n, double* x, double* y, double* z, int* ok);

/// Source pixels per destination pixel along the destination's x and y at its centre, through
/// `chain` (1 where the chain fails there).
std::array<double, 2> sourcePerDestination(ChainArg& chain, int w, int h);

/// The settings the basemap's and the DEM's warps share, into `wo`: bilinear in float, the memory
/// limit, the approximating transformer `approx` (over `chain`), a blank destination (INIT_DEST 0)
/// whose alpha band is the coverage in [0, 1], the source window from a grid of points, and the
/// filter's footprint measured through `chain` at the centre of the `w` × `h` destination.
void setSharedWarpOptions(GDALWarpOptions* wo, ChainArg& chain, void* approx, int w, int h);

}  // namespace nph::scene::gdal_detail

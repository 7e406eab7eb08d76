// GDAL plumbing shared by the basemap and the DEM (scene/gdal_support.h).
#include "scene/gdal_support.h"

#include <cpl_string.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <mutex>

namespace nph::scene::gdal_detail {

void registerGdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

int chainTransform(void* arg, int dstToSrc, int n, double* x, double* y, double* z, int* ok) {
  const auto* c = static_cast<const ChainArg*>(arg);
  if (dstToSrc) {
    c->destination->lonLatFromPixel(x, y, n);
    std::vector<int> mask(std::size_t(std::max(n, 0)), 1);
    for (int i = 0; i < n; ++i) {
      if (std::isnan(x[i]) || std::isnan(y[i])) {
        mask[std::size_t(i)] = 0;
        x[i] = y[i] = 0.0;  // a finite point for GDAL; marked failed below
      }
      y[i] = std::clamp(y[i], -90.0, 90.0);  // PROJ may return the pole a few ulp beyond it
    }
    GDALGenImgProjTransform(c->lonlat_to_source, TRUE, n, x, y, z, ok);
    for (int i = 0; i < n; ++i) ok[i] = ok[i] && mask[std::size_t(i)];
    return TRUE;
  }
  GDALGenImgProjTransform(c->lonlat_to_source, FALSE, n, x, y, z, ok);
  for (int i = 0; i < n; ++i) {
    if (ok[i]) ok[i] = c->destination->pixelFromLonLat(x[i], y[i]) ? 1 : 0;
  }
  return TRUE;
}

std::array<double, 2> sourcePerDestination(ChainArg& chain, int w, int h) {
  double x[3] = {0.5 * w, 0.5 * w + 1.0, 0.5 * w}, y[3] = {0.5 * h, 0.5 * h, 0.5 * h + 1.0}, z[3] = {};
  int ok[3] = {};
  chainTransform(&chain, TRUE, 3, x, y, z, ok);
  return {ok[0] && ok[1] ? std::hypot(x[1] - x[0], y[1] - y[0]) : 1.0,
          ok[0] && ok[2] ? std::hypot(x[2] - x[0], y[2] - y[0]) : 1.0};
}

void setSharedWarpOptions(GDALWarpOptions* wo, ChainArg& chain, void* approx, int w, int h) {
  wo->eResampleAlg = GRA_Bilinear;
  wo->eWorkingDataType = GDT_Float32;
  wo->dfWarpMemoryLimit = kWarpMemory_bytes;
  wo->pfnTransformer = GDALApproxTransform;
  wo->pTransformerArg = approx;
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "INIT_DEST", "0");
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "DST_ALPHA_MAX", "1");
  // The source window of each chunk from a grid of points inside it, not only its edges: around
  // a pole (a polar stereographic grid) the northernmost lon/lat of a chunk lies inside it.
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "SAMPLE_GRID", "YES");
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "SOURCE_EXTRA", "2");
  // The filter's footprint: GDAL widens bilinear by the chunk's source-window/destination size
  // ratio, which a window across the antimeridian (both ends of a whole-Earth raster) makes
  // absurd. Give it the real ratio, measured at the destination's centre: source pixels per
  // destination pixel along each axis. Up to 2 the plain (point-sampled) bilinear sees every
  // source pixel; beyond, the kernel is widened to the footprint (antialiasing) — GDAL's widened
  // kernel is not exact on a linear ramp (its discrete weights are not centred: a bias up to
  // ~0.1 source pixel, measured), so it is kept for where it is needed.
  const auto scale = [](double sourcePerDestination) {
    return fmt::format("{:.9g}", sourcePerDestination > 2.0 ? 1.0 / sourcePerDestination : 1.0);
  };
  const std::array<double, 2> ratio = sourcePerDestination(chain, w, h);
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "XSCALE", scale(ratio[0]).c_str());
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "YSCALE", scale(ratio[1]).c_str());
}

}  // namespace nph::scene::gdal_detail

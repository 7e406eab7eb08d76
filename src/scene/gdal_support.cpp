// GDAL plumbing shared by the basemap and the DEM (scene/gdal_support.h).
#include "scene/gdal_support.h"

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

}  // namespace nph::scene::gdal_detail

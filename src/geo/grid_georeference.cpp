#include "geo/grid_georeference.h"

namespace nph::geo {

LonLat gridLonLat(const MapProjection& projection, const GridGeoreference& georef, double i, double j) {
  return projection.inverse(georef.projectedAt(i, j));
}

}  // namespace nph::geo

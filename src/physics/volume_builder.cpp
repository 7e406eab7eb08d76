#include "physics/volume_builder.h"

#include "physics/extinction.h"

namespace nph::physics {

GridGeoreference toGridGeoreference(const io::Georeference& g) {
  GridGeoreference out;
  out.proj_definition = g.proj_definition;
  out.dx_m = g.dx_m;
  out.dy_m = g.dy_m;
  out.x0 = g.x0;
  out.y0 = g.y0;
  out.geographic = g.geographic;
  out.lat_deg = g.lat_deg;
  out.lon_deg = g.lon_deg;
  return out;
}

ExtinctionVolumes buildExtinctionVolumes(const io::ModelTimestep& ts,
                                         const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical) {
  const ModelLevelExtinction beta = modelLevelExtinction(ts, optics);
  const VerticalGrid grid = planVerticalGrid(ts, beta, vertical);
  ExtinctionVolumes v;
  resampleVertically(ts, beta, grid, v);
  v.georef = toGridGeoreference(ts.georef);
  v.time_utc = ts.time_utc;
  v.source_file = ts.source_file;
  v.source_time_index = ts.time_index;
  v.updateMaxima();
  return v;
}

}  // namespace nph::physics

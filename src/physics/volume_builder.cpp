#include "physics/volume_builder.h"

#include "physics/extinction.h"

namespace nph::physics {

ExtinctionVolumes buildExtinctionVolumes(const io::ModelTimestep& ts,
                                         const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical) {
  const ModelLevelExtinction beta = modelLevelExtinction(ts, optics);
  const VerticalGrid grid = planVerticalGrid(ts, beta, vertical);
  ExtinctionVolumes v;
  resampleVertically(ts, beta, grid, v);
  v.georef = ts.georef;
  v.terrain_height_m = ts.terrain_height_m;  // checked against nx×ny by planVerticalGrid
  v.time_utc = ts.time_utc;
  v.source_file = ts.source_file;
  v.source_time_index = ts.time_index;
  v.updateMaxima();
  return v;
}

}  // namespace nph::physics

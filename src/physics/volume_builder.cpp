#include "physics/volume_builder.h"

#include "physics/extinction.h"
#include "volume/detail.h"

namespace nph::physics {

ExtinctionVolumes buildExtinctionVolumes(const io::ModelTimestep& ts, const OpticsSettings& optics,
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
  // The fields that steer the sub-grid detail (issue 13; volume/detail.h), where the file has them.
  v.tke_m2_per_s2 = resampleFieldVertically(ts, ts.tke_m2_per_s2, "TKE", grid);
  v.cloud_fraction = resampleFieldVertically(
      ts, ts.cloud_fraction.empty() ? ts.cloud_cover_fraction : ts.cloud_fraction, "cloud fraction", grid);
  v.wind_w_m_per_s = resampleFieldVertically(ts, ts.wind_w_m_per_s, "W", grid);
  v.wind_u_m_per_s = resampleFieldVertically(ts, ts.wind_u_m_per_s, "U", grid);
  v.wind_v_m_per_s = resampleFieldVertically(ts, ts.wind_v_m_per_s, "V", grid);
  v.detail_clock_s = volume::detailClock_s(v.time_utc);  // the noise's advection clock (volume/detail.h)
  v.updateMaxima();
  return v;
}

}  // namespace nph::physics

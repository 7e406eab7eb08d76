#include "physics/volume_builder.h"

#include <fmt/format.h>

#include "core/error.h"
#include "physics/extinction.h"
#include "volume/detail.h"

namespace nph::physics {

namespace {

/// Frees a field's memory (clear() keeps the capacity).
void release(std::vector<float>& field) { std::vector<float>().swap(field); }

/// Both overloads: `owned` is the timestep when the caller gave it up (its fields are freed as
/// they are done with), nullptr when it is only read.
ExtinctionVolumes build(const io::ModelTimestep& ts, io::ModelTimestep* owned, const OpticsSettings& optics,
                        const VerticalGridOptions& vertical,
                        const std::function<void(io::ModelTimestep&)>& loadDetail) {
  if (ts.detail_deferred && (owned == nullptr || !loadDetail)) {
    throw UsageError(fmt::format("{}: timestep {} was loaded without its detail fields (defer_detail) and nothing "
                                 "loads them",
                                 ts.source_file, ts.time_index));
  }
  ModelLevelExtinction beta = modelLevelExtinction(ts, optics);
  if (owned != nullptr) {  // what only the optics read (heights, terrain and ICON's clc stay)
    owned->q_kg_per_kg.clear();
    owned->number_per_kg.clear();
    release(owned->water_vapour_kg_per_kg);
    release(owned->pressure_pa);
    release(owned->temperature_k);
    // The detail fields left out of the load, now into the memory the optics' fields gave back.
    if (owned->detail_deferred) {
      loadDetail(*owned);
      if (owned->detail_deferred)
        throw UsageError(fmt::format("{}: the detail fields were not loaded", ts.source_file));
    }
  }
  const VerticalGrid grid = planVerticalGrid(ts, beta, vertical);
  ExtinctionVolumes v;
  resampleVertically(ts, beta, grid, v);
  beta = ModelLevelExtinction{};
  v.georef = ts.georef;
  v.terrain_height_m = ts.terrain_height_m;  // checked against nx×ny by planVerticalGrid
  v.time_utc = ts.time_utc;
  v.source_file = ts.source_file;
  v.source_time_index = ts.time_index;
  // The fields that steer the sub-grid detail (issue 13; volume/detail.h), where the file has them.
  using Field = std::vector<float> io::ModelTimestep::*;
  auto resampled = [&](Field field, const char* name) {
    std::vector<float> out = resampleFieldVertically(ts, ts.*field, name, grid);
    if (owned != nullptr) release(owned->*field);
    return out;
  };
  v.tke_m2_per_s2 = resampled(&io::ModelTimestep::tke_m2_per_s2, "TKE");
  v.cloud_fraction = resampled(
      ts.cloud_fraction.empty() ? &io::ModelTimestep::cloud_cover_fraction : &io::ModelTimestep::cloud_fraction,
      "cloud fraction");
  v.wind_w_m_per_s = resampled(&io::ModelTimestep::wind_w_m_per_s, "W");
  v.wind_u_m_per_s = resampled(&io::ModelTimestep::wind_u_m_per_s, "U");
  v.wind_v_m_per_s = resampled(&io::ModelTimestep::wind_v_m_per_s, "V");
  v.detail_clock_s = volume::detailClock_s(v.time_utc);  // the noise's advection clock (volume/detail.h)
  v.updateMaxima();
  return v;
}

}  // namespace

ExtinctionVolumes buildExtinctionVolumes(const io::ModelTimestep& ts, const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical) {
  return build(ts, nullptr, optics, vertical, {});
}

ExtinctionVolumes buildExtinctionVolumes(io::ModelTimestep&& ts, const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical,
                                         const std::function<void(io::ModelTimestep&)>& loadDetail) {
  return build(ts, &ts, optics, vertical, loadDetail);
}

}  // namespace nph::physics

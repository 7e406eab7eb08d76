#pragma once
// ModelTimestep (io/) -> ExtinctionVolumes (cache/), the georeference passed on as it is (one
// geo::GridGeoreference type on both sides): optics on model levels (extinction.h), then
// vertical resampling with the crop (vertical_resampling.h). One call per timestep; a conversion
// of several timesteps fixes z_bottom after the first so all share one vertical grid.
#include <functional>

#include "io/model_fields.h"
#include "physics/optics_settings.h"
#include "physics/vertical_resampling.h"
#include "volume/extinction_volumes.h"

namespace nph::physics {

ExtinctionVolumes buildExtinctionVolumes(const io::ModelTimestep& ts, const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical);

/// The same volumes from a timestep the caller gives up (`nephele convert`): each model field is
/// freed as soon as the last stage that reads it is done — the hydrometeors, pressure, temperature
/// and vapour after the optics, the model-level extinction after its resampling, each detail field
/// after its own — so the output volumes reuse their memory instead of adding to it (issue 19:
/// peak −25 % and a quarter fewer fresh pages on the demo storm's conversion). Bit for bit the
/// const overload's result.
///
/// A timestep loaded with io::LoadOptions::defer_detail (`detail_deferred`: WRF's CLDFRA, TKE, W,
/// U, V not read yet) gets them from `loadDetail` (io::loadDeferredDetail) once the optics' fields
/// are freed, so they reuse that memory (issue 19: five fields less at the peak). UsageError when
/// such a timestep comes without `loadDetail`.
ExtinctionVolumes buildExtinctionVolumes(io::ModelTimestep&& ts, const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical,
                                         const std::function<void(io::ModelTimestep&)>& loadDetail = {});

}  // namespace nph::physics

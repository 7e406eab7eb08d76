#pragma once
// ModelTimestep (io/) -> ExtinctionVolumes (cache/), the georeference passed on as it is (one
// geo::GridGeoreference type on both sides): optics on model levels (extinction.h), then
// vertical resampling with the crop (vertical_resampling.h). One call per timestep; a conversion
// of several timesteps fixes z_bottom after the first so all share one vertical grid.
#include "io/model_fields.h"
#include "physics/optics_settings.h"
#include "physics/vertical_resampling.h"
#include "volume/extinction_volumes.h"

namespace nph::physics {

ExtinctionVolumes buildExtinctionVolumes(const io::ModelTimestep& ts, const OpticsSettings& optics,
                                         const VerticalGridOptions& vertical);

}  // namespace nph::physics

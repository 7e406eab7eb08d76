#include "cache/extinction_volumes.h"

#include <algorithm>

namespace nph {

void ExtinctionVolumes::updateMaxima() {
  max_ice_per_m = ice_per_m.empty() ? 0.0f : *std::max_element(ice_per_m.begin(), ice_per_m.end());
  max_water_per_m =
      water_per_m.empty() ? 0.0f : *std::max_element(water_per_m.begin(), water_per_m.end());
  max_ice_per_m = std::max(max_ice_per_m, 0.0f);
  max_water_per_m = std::max(max_water_per_m, 0.0f);
}

}  // namespace nph

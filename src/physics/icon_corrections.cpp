#include "physics/icon_corrections.h"

#include <algorithm>

#include "physics/constants.h"

namespace nph::physics {

IconCellCondensate correctIconCell(double qc, double qi, double cloud_cover, double t, double p,
                                   const IconCorrections& s) {
  IconCellCondensate c{qc, qi, std::clamp(cloud_cover, 0.0, 1.0)};
  const double q_crit = s.critical_condensate_kg_per_kg;
  if (s.diagnose_cloud_cover) {  // Muth eq. 3.1
    const double diagnosed = std::min((qc + qi) / q_crit, 1.0);
    c.cloud_cover = std::max(c.cloud_cover, diagnosed);
  }
  if (s.reconstruct_condensate && t > s.min_temperature_k && p > s.min_pressure_pa && c.cloud_cover > 0.0) {
    const double q_min = q_crit * c.cloud_cover;
    const double f_ice = std::clamp(-(t - kFreezingPointK) / s.ice_ramp_k, 0.0, 1.0);
    c.cloud_kg_per_kg = std::max(c.cloud_kg_per_kg, (1.0 - f_ice) * q_min);
    c.ice_kg_per_kg = std::max(c.ice_kg_per_kg, f_ice * q_min);
  }
  return c;
}

}  // namespace nph::physics

#pragma once
// ICON-D2 condensate consistency corrections (Muth 2026 §3.3.1, fig. 3.2), per grid cell.
//
// ICON's cloud cover CLC and its grid-mean condensate qc, qi disagree in two ways:
//  1. CLC = 0 where qc + qi > 0. With Tompkins' exponential total-water distribution,
//       CLC_diag = min(q_w / Q_crit, 1),  Q_crit = 3e-5 kg/kg,  q_w = qc + qi     (Muth eq. 3.1)
//     and CLC_eff = max(CLC, CLC_diag).
//  2. CLC > 0 where qc + qi ≈ 0 (the cloud scheme keeps cover after the microphysics removed the
//     condensate). Inverting eq. 3.1 gives a minimum q_w = Q_crit · CLC_eff, split into liquid
//     and ice with f_ice = clamp(-(T - 273.15 K)/38 K, 0, 1); qc and qi are raised to at least
//     (1 - f_ice) q_w and f_ice q_w where T > 180 K and p > 100 Pa.
// Correction 1 only acts through correction 2 and through CLC_eff itself.
//
// Muth divides the corrected grid-mean values by CLC_eff to get in-cloud contents (eq. 3.3),
// because his detail synthesis then confines the cloud to a CLC_eff fraction of the cell.
// nephele has no sub-grid synthesis: a cell's extinction is spread over the whole cell, so the
// grid-mean value (not divided) is the one that preserves the cell's mean optical depth.
#include "physics/optics_settings.h"

namespace nph::physics {

struct IconCellCondensate {
  double cloud_kg_per_kg = 0.0;  ///< qc (grid mean)
  double ice_kg_per_kg = 0.0;    ///< qi (grid mean)
  double cloud_cover = 0.0;      ///< CLC_eff, fraction [0, 1]
};

/// Applies the enabled corrections to one cell. `cloud_cover` is CLC as a fraction [0, 1].
IconCellCondensate correctIconCell(double qc, double qi, double cloud_cover, double temperature_k, double pressure_pa,
                                   const IconCorrections& settings);

}  // namespace nph::physics

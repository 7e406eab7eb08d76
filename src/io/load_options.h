#pragma once
// Options shared by the model loaders.
#include <cstddef>

namespace nph::io {

struct LoadOptions {
  /// Largest number of bytes one loaded timestep may need. Checked against the sizes the file
  /// declares before anything is allocated. 0 = the default: NEPHELE_IO_MEMORY_BUDGET_MB from
  /// the environment, else 8 GiB.
  std::size_t memory_budget_bytes = 0;
  /// ICON native grid: spacing [degrees of latitude] of the regular grid it is resampled onto;
  /// 0 = automatic (one grid point per cell on average).
  double native_resolution_deg = 0.0;
  /// WRF: leave the sub-grid detail's fields (CLDFRA, TKE, W, U, V) out of the timestep and mark
  /// it `detail_deferred`, so that a converter reads them with loadDeferredDetail (io/model_file.h)
  /// after the optics' fields are freed — five fields less at the peak (issue 19, `convert`).
  /// ICON and GRIB2 load everything as before.
  bool defer_detail = false;
};

/// The budget in force for `options` (resolving the default).
std::size_t memoryBudgetBytes(const LoadOptions& options);

}  // namespace nph::io

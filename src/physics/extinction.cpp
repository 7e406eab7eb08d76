#include "physics/extinction.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/log.h"
#include "physics/air_density.h"
#include "physics/constants.h"
#include "physics/effective_radius.h"
#include "physics/icon_corrections.h"

namespace nph::physics {

namespace {

constexpr std::size_t idx(Hydrometeor h) { return static_cast<std::size_t>(h); }

bool splitsByTemperature(const VoxelState& v, const OpticsSettings& s) {
  return v.model == io::ModelKind::Wrf &&
         std::find(s.temperature_split_schemes.begin(), s.temperature_split_schemes.end(), v.microphysics_scheme) !=
             s.temperature_split_schemes.end();
}

}  // namespace

VoxelExtinction voxelExtinction(const VoxelState& v, const OpticsSettings& s) {
  std::array<double, io::kAllHydrometeors.size()> q{};
  for (std::size_t f = 0; f < q.size(); ++f) q[f] = std::max(v.q_kg_per_kg[f], 0.0);

  VoxelExtinction out;
  if (v.model == io::ModelKind::Wrf) {
    out.reference_density_kg_per_m3 = dryAirDensity(v.pressure_pa, v.temperature_k, std::max(v.vapour_kg_per_kg, 0.0));
  } else {
    // Condensate loading of the density from the file's own contents (the model state), before
    // the corrections below raise qc/qi.
    double condensate = 0.0;
    for (double x : q) condensate += x;
    out.reference_density_kg_per_m3 =
        moistAirDensity(v.pressure_pa, v.temperature_k, std::max(v.vapour_kg_per_kg, 0.0), condensate);
    if (std::isfinite(v.cloud_cover)) {  // Muth §3.3.1 corrections need CLC
      const IconCellCondensate c = correctIconCell(q[idx(Hydrometeor::Cloud)], q[idx(Hydrometeor::Ice)], v.cloud_cover,
                                                   v.temperature_k, v.pressure_pa, s.icon);
      q[idx(Hydrometeor::Cloud)] = c.cloud_kg_per_kg;
      q[idx(Hydrometeor::Ice)] = c.ice_kg_per_kg;
    }
  }

  const bool frozen_split = splitsByTemperature(v, s) && v.temperature_k < kFreezingPointK;
  for (Hydrometeor h : io::kAllHydrometeors) {
    const double qf = q[idx(h)];
    if (qf <= 0.0) continue;
    // WSM3 below 0 °C: QCLOUD holds cloud ice, QRAIN holds snow (Hong et al. 2004).
    Hydrometeor optics_class = h;
    if (frozen_split && h == Hydrometeor::Cloud) optics_class = Hydrometeor::Ice;
    if (frozen_split && h == Hydrometeor::Rain) optics_class = Hydrometeor::Snow;
    const HydrometeorOptics& o = s[optics_class];
    double radius_m = o.effective_radius_m;
    if (s.use_number_concentrations && optics_class == h) {
      radius_m = effectiveRadiusFromNumber(qf, v.number_per_kg[idx(h)], o.particle_density_kg_per_m3, o.gamma_shape,
                                           o.effective_radius_m, o.min_radius_m, o.max_radius_m);
    }
    // Nes 2008 eq. 5.3
    const double beta = 3.0 * out.reference_density_kg_per_m3 * qf / (2.0 * o.particle_density_kg_per_m3 * radius_m);
    (o.ice_phase ? out.ice_per_m : out.water_per_m) += beta;
  }
  return out;
}

namespace {

/// Throws InputError when a field has the wrong size.
void requireSize(const io::ModelTimestep& ts, const std::vector<float>& field, const char* name, std::size_t expected,
                 bool optional) {
  if (optional && field.empty()) return;
  if (field.size() != expected) {
    throw InputError(fmt::format("{}: timestep {} ({}): {} has {} values, expected {} ({}x{}x{})", ts.source_file,
                                 ts.time_index, geo::isoOrEmpty(ts.time_utc), name, field.size(), expected, ts.nx,
                                 ts.ny, ts.nz));
  }
}

[[noreturn]] void badValue(const io::ModelTimestep& ts, const char* name, std::size_t n, double value,
                           const char* expected) {
  const auto i = n % std::size_t(ts.nx);
  const auto j = (n / std::size_t(ts.nx)) % std::size_t(ts.ny);
  const auto k = n / (std::size_t(ts.nx) * std::size_t(ts.ny));
  throw InputError(fmt::format("{}: timestep {} ({}): {} = {} at (i={}, j={}, k={}), expected {}", ts.source_file,
                               ts.time_index, geo::isoOrEmpty(ts.time_utc), name, value, i, j, k, expected));
}

std::string qName(const io::ModelTimestep& ts, Hydrometeor h, bool number) {
  return fmt::format("{} of {}", number ? "number concentration" : "mixing ratio", hydrometeorName(h)) +
         (ts.model == io::ModelKind::Wrf ? " (WRF)" : " (ICON)");
}

}  // namespace

ModelLevelExtinction modelLevelExtinction(const io::ModelTimestep& ts, const OpticsSettings& s) {
  if (ts.nx <= 0 || ts.ny <= 0 || ts.nz <= 0) {
    throw InputError(
        fmt::format("{}: timestep {}: empty grid {}x{}x{}", ts.source_file, ts.time_index, ts.nx, ts.ny, ts.nz));
  }
  const std::size_t n = ts.voxelCount();
  requireSize(ts, ts.pressure_pa, "pressure", n, false);
  requireSize(ts, ts.temperature_k, "temperature", n, false);
  requireSize(ts, ts.water_vapour_kg_per_kg, "water vapour", n, true);
  requireSize(ts, ts.cloud_cover_fraction, "cloud cover", n, true);
  for (const auto& [h, field] : ts.q_kg_per_kg) {
    requireSize(ts, field, qName(ts, h, false).c_str(), n, false);
  }
  for (const auto& [h, field] : ts.number_per_kg) {
    requireSize(ts, field, qName(ts, h, true).c_str(), n, false);
  }
  if (ts.water_vapour_kg_per_kg.empty()) {
    log::warn("{}: no water vapour field; air density computed for dry air", ts.source_file);
  }

  // Look-up tables: which arrays exist, so the inner loop stays branch-light.
  std::array<const float*, io::kAllHydrometeors.size()> q_ptr{}, n_ptr{};
  for (const auto& [h, field] : ts.q_kg_per_kg) q_ptr[idx(h)] = field.data();
  if (s.use_number_concentrations) {
    for (const auto& [h, field] : ts.number_per_kg) n_ptr[idx(h)] = field.data();
  }
  const float* qv = ts.water_vapour_kg_per_kg.empty() ? nullptr : ts.water_vapour_kg_per_kg.data();
  const float* clc = ts.cloud_cover_fraction.empty() ? nullptr : ts.cloud_cover_fraction.data();
  if (ts.model == io::ModelKind::Icon && clc == nullptr &&
      (s.icon.diagnose_cloud_cover || s.icon.reconstruct_condensate)) {
    log::warn("{}: no cloud cover (clc): ICON condensate corrections (Muth 2026 §3.3.1) skipped", ts.source_file);
  }

  ModelLevelExtinction out;
  out.nx = ts.nx;
  out.ny = ts.ny;
  out.nz = ts.nz;
  out.ice_per_m = hugePageFloats(n);  // tens of MB each: huge pages (core/large_buffer.h)
  out.water_per_m = hugePageFloats(n);
  const std::size_t row = std::size_t(ts.nx);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, std::size_t(ts.ny) * std::size_t(ts.nz)),
      [&](const tbb::blocked_range<std::size_t>& rows) {
        VoxelState v;
        v.model = ts.model;
        v.microphysics_scheme = ts.microphysics_scheme;
        for (std::size_t r = rows.begin(); r != rows.end(); ++r) {
          for (std::size_t m = r * row; m < (r + 1) * row; ++m) {
            v.pressure_pa = double(ts.pressure_pa[m]);
            v.temperature_k = double(ts.temperature_k[m]);
            if (!(v.pressure_pa > 0.0) || !std::isfinite(v.pressure_pa)) {
              badValue(ts, "pressure [Pa]", m, v.pressure_pa, "a finite value > 0");
            }
            if (!(v.temperature_k > 0.0) || !std::isfinite(v.temperature_k)) {
              badValue(ts, "temperature [K]", m, v.temperature_k, "a finite value > 0");
            }
            v.vapour_kg_per_kg = qv != nullptr ? double(qv[m]) : 0.0;
            if (!std::isfinite(v.vapour_kg_per_kg)) {
              badValue(ts, "water vapour", m, v.vapour_kg_per_kg, "a finite value");
            }
            for (std::size_t f = 0; f < q_ptr.size(); ++f) {
              v.q_kg_per_kg[f] = q_ptr[f] != nullptr ? double(q_ptr[f][m]) : 0.0;
              if (!std::isfinite(v.q_kg_per_kg[f])) {
                badValue(ts, qName(ts, io::kAllHydrometeors[f], false).c_str(), m, v.q_kg_per_kg[f], "a finite value");
              }
              v.number_per_kg[f] = n_ptr[f] != nullptr ? double(n_ptr[f][m]) : std::numeric_limits<double>::quiet_NaN();
            }
            v.cloud_cover = clc != nullptr ? double(clc[m]) : std::numeric_limits<double>::quiet_NaN();
            if (ts.model == io::ModelKind::Wrf &&
                std::none_of(v.q_kg_per_kg.begin(), v.q_kg_per_kg.end(), [](double q) { return q > 0.0; })) {
              // Clear air (most of a domain): no class contributes, so no density or radius is
              // needed — voxelExtinction's own result, 0, without its work (issue 19, convert
              // speed). ICON's corrections can make condensate from clc, so ICON always asks.
              out.ice_per_m[m] = 0.0f;
              out.water_per_m[m] = 0.0f;
              continue;
            }
            const VoxelExtinction e = voxelExtinction(v, s);
            out.ice_per_m[m] = static_cast<float>(e.ice_per_m);
            out.water_per_m[m] = static_cast<float>(e.water_per_m);
          }
        }
      });
  return out;
}

}  // namespace nph::physics

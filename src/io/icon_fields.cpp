#include "icon_fields.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/limits.h"
#include "core/log.h"
#include "field_checks.h"
#include "icon_loader.h"

namespace nph::io {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// Resampling of the native grid: nearest cell centre, found with a uniform bucket grid in
/// (lon cos(lat_mid), lat), so the search is O(1) per target point rather than O(ncells).
/// Nearest-cell (rather than barycentric) keeps each cell's values intact: cloud cover and
/// condensate of one cell stay together (the ICON corrections compare them cell by cell) and no
/// new extrema or mixed cloud edges appear; the price is blocky edges at the cell scale.
class CellLocator {
 public:
  CellLocator(const std::vector<double>& lon_deg, const std::vector<double>& lat_deg, double cos_mid, double bucket_deg)
      : lon_(lon_deg), lat_(lat_deg), cos_(cos_mid), bucket_(bucket_deg) {
    min_x_ = std::numeric_limits<double>::max();
    min_y_ = std::numeric_limits<double>::max();
    double max_x = -min_x_, max_y = -min_y_;
    for (std::size_t c = 0; c < lon_.size(); ++c) {
      min_x_ = std::min(min_x_, lon_[c] * cos_);
      max_x = std::max(max_x, lon_[c] * cos_);
      min_y_ = std::min(min_y_, lat_[c]);
      max_y = std::max(max_y, lat_[c]);
    }
    nbx_ = static_cast<int>((max_x - min_x_) / bucket_) + 1;
    nby_ = static_cast<int>((max_y - min_y_) / bucket_) + 1;
    start_.assign(std::size_t(nbx_) * std::size_t(nby_) + 1, 0);
    std::vector<std::size_t> bucket_of(lon_.size());
    for (std::size_t c = 0; c < lon_.size(); ++c) {
      bucket_of[c] = bucketIndex(bx(lon_[c] * cos_), by(lat_[c]));
      ++start_[bucket_of[c] + 1];
    }
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    cells_.resize(lon_.size());
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t c = 0; c < lon_.size(); ++c) cells_[fill[bucket_of[c]]++] = c;
  }

  std::size_t nearest(double lon, double lat) const {
    const double x = lon * cos_;
    const int cx = bx(x), cy = by(lat);
    double best = std::numeric_limits<double>::max();
    std::size_t best_cell = 0;
    for (int ring = 0; ring < std::max(nbx_, nby_) + 1; ++ring) {
      // Only the buckets on the ring's perimeter, clipped to the grid (the inner ones were
      // searched by the smaller rings).
      for (int j = std::max(cy - ring, 0); j <= std::min(cy + ring, nby_ - 1); ++j) {
        const bool edge_row = std::abs(j - cy) == ring;
        const int step = edge_row ? 1 : std::max(2 * ring, 1);
        for (int i = cx - ring; i <= cx + ring; i += step) {
          if (i < 0 || i >= nbx_) continue;
          const std::size_t b = bucketIndex(i, j);
          for (std::size_t n = start_[b]; n < start_[b + 1]; ++n) {
            const std::size_t c = cells_[n];
            const double dx = lon_[c] * cos_ - x, dy = lat_[c] - lat;
            const double d2 = dx * dx + dy * dy;
            if (d2 < best) {
              best = d2;
              best_cell = c;
            }
          }
        }
      }
      // Any cell in a further ring is at least `ring * bucket` away.
      const double reach = ring * bucket_;
      if (best < std::numeric_limits<double>::max() && best <= reach * reach) break;
    }
    return best_cell;
  }

 private:
  int bx(double x) const { return std::clamp(static_cast<int>((x - min_x_) / bucket_), 0, nbx_ - 1); }
  int by(double y) const { return std::clamp(static_cast<int>((y - min_y_) / bucket_), 0, nby_ - 1); }
  std::size_t bucketIndex(int i, int j) const { return std::size_t(j) * std::size_t(nbx_) + std::size_t(i); }
  const std::vector<double>& lon_;
  const std::vector<double>& lat_;
  double cos_, bucket_;
  double min_x_ = 0, min_y_ = 0;
  int nbx_ = 1, nby_ = 1;
  std::vector<std::size_t> start_, cells_;
};

/// Horizontal mapping of a regular source grid: nephele's rows run south to north.
std::vector<std::size_t> mapRegular(const IconSourceFields& src, ModelTimestep& ts) {
  const std::vector<double>& lon = src.lon_deg;
  const std::vector<double>& lat = src.lat_deg;
  if (lon.empty() || lat.empty() || lon.size() * lat.size() != src.npoints) {
    throw InputError(fmt::format("{}: {}/{} have {}/{} values, expected {} points in all", src.path, src.lon_name,
                                 src.lat_name, lon.size(), lat.size(), src.npoints));
  }
  auto spacing = [&](const std::vector<double>& v, const std::string& name) {
    if (v.size() < 2) return 0.0;
    const double step = v[1] - v[0];
    for (std::size_t n = 1; n < v.size(); ++n) {
      if (!(std::abs((v[n] - v[n - 1]) - step) <= 1e-3 * std::abs(step)) || step == 0.0) {
        throw InputError(
            fmt::format("{}: {} is not evenly spaced at index {}, expected a regular lat-lon grid", src.path, name, n));
      }
    }
    return step;
  };
  const double dlon = spacing(lon, src.lon_name);
  const double dlat = spacing(lat, src.lat_name);
  if (dlon < 0.0) {
    throw InputError(fmt::format("{}: {} decreases, expected increasing longitudes", src.path, src.lon_name));
  }
  const bool south_first = dlat >= 0.0;
  const std::size_t nlon = lon.size(), nlat = lat.size();
  ts.nx = static_cast<int>(nlon);
  ts.ny = static_cast<int>(nlat);
  ts.georef.dx_m = nlon > 1 ? dlon : 1.0;
  ts.georef.dy_m = nlat > 1 ? std::abs(dlat) : 1.0;
  ts.georef.x0 = lon.front();
  ts.georef.y0 = south_first ? lat.front() : lat.back();
  std::vector<std::size_t> source_of(nlon * nlat);
  for (std::size_t j = 0; j < nlat; ++j) {
    const std::size_t sj = south_first ? j : nlat - 1 - j;  // rows south to north
    for (std::size_t i = 0; i < nlon; ++i) source_of[j * nlon + i] = sj * nlon + i;
  }
  return source_of;
}

/// Horizontal mapping of the native grid: nearest cell of every point of a regular lat-lon grid.
std::vector<std::size_t> mapNative(const IconSourceFields& src, const LoadOptions& options, ModelTimestep& ts) {
  const std::vector<double>& lon = src.lon_deg;
  const std::vector<double>& lat = src.lat_deg;
  if (lon.size() != src.npoints || lat.size() != src.npoints) {
    throw InputError(fmt::format("{}: {}/{} have {}/{} values, expected ncells = {}", src.path, src.lon_name,
                                 src.lat_name, lon.size(), lat.size(), src.npoints));
  }
  double lat_min = 90, lat_max = -90, lon_min = 1e9, lon_max = -1e9;
  for (std::size_t c = 0; c < src.npoints; ++c) {
    if (!std::isfinite(lon[c]) || !std::isfinite(lat[c]) || std::abs(lat[c]) > 90.0) {
      throw InputError(fmt::format("{}: {}/{} of cell {} is not a valid position ({}, {} degrees)", src.path,
                                   src.lon_name, src.lat_name, c, lon[c], lat[c]));
    }
    lat_min = std::min(lat_min, lat[c]);
    lat_max = std::max(lat_max, lat[c]);
    lon_min = std::min(lon_min, lon[c]);
    lon_max = std::max(lon_max, lon[c]);
  }
  const double cos_mid = std::max(std::cos(0.5 * (lat_min + lat_max) / kDegPerRad), 0.01);
  double dlat = options.native_resolution_deg;
  if (!(dlat > 0.0)) {
    // One target point per cell on average over the cells' bounding box.
    const double area = std::max((lon_max - lon_min) * cos_mid, 1e-9) * std::max(lat_max - lat_min, 1e-9);
    dlat = std::sqrt(area / double(src.npoints));
    // ... but never finer than the longer extent over ncells: for cells along a line (two
    // cells, or one row) the box has no area, and the clamped area above gave ~1e-5 deg
    // spacing, a 44 000-point row whose empty buckets CellLocator::nearest scanned for hours.
    // With this floor each axis has at most ncells + 1 points, the grid at most 3 ncells + 1.
    dlat = std::max(dlat, std::max((lon_max - lon_min) * cos_mid, lat_max - lat_min) / double(src.npoints));
  }
  const double dlon = dlat / cos_mid;
  const double nx_d = std::floor((lon_max - lon_min) / dlon) + 1.0;
  const double ny_d = std::floor((lat_max - lat_min) / dlat) + 1.0;
  requireWithinBudget(src.path, "the resampled native grid", nx_d * ny_d * double(src.nz), 12,
                      memoryBudgetBytes(options));
  const auto nx_checked = limits::toIntChecked<int>(nx_d), ny_checked = limits::toIntChecked<int>(ny_d);
  if (!nx_checked || !ny_checked) {
    throw InputError(fmt::format("{}: the resampled native grid would be {} x {} points, more than an int "
                                 "indexes (LoadOptions::native_resolution_deg too fine)",
                                 src.path, nx_d, ny_d));
  }
  ts.nx = *nx_checked;
  ts.ny = *ny_checked;
  ts.georef.dx_m = dlon;
  ts.georef.dy_m = dlat;
  ts.georef.x0 = lon_min;
  ts.georef.y0 = lat_min;
  const CellLocator locator(lon, lat, cos_mid, 2.0 * dlat);
  std::vector<std::size_t> source_of(std::size_t(ts.nx) * std::size_t(ts.ny));
  for (int j = 0; j < ts.ny; ++j) {
    for (int i = 0; i < ts.nx; ++i) {
      source_of[std::size_t(j) * std::size_t(ts.nx) + std::size_t(i)] =
          locator.nearest(lon_min + i * dlon, lat_min + j * dlat);
    }
  }
  return source_of;
}

}  // namespace

void checkIconField(const std::string& path, const std::string& var, IconQuantity quantity, std::vector<float>& data,
                    LoadRepairs& repairs, bool fraction_units) {
  requireFinite(path, var, data);
  switch (quantity) {
    case IconQuantity::Condensate:
    case IconQuantity::SpecificHumidity: {
      requireAtMost(path, var, data, kMaxMixingRatio_kg_per_kg,
                    quantity == IconQuantity::Condensate ? "a mixing ratio [kg/kg]" : "a specific humidity [kg/kg]");
      const std::int64_t negative = clampNegative(data);
      if (negative > 0 && quantity == IconQuantity::Condensate) {
        log::warn("{}: {} had {} negative values, set to 0", path, var, negative);
      }
      repairs.negative_clamped += negative;
      break;
    }
    case IconQuantity::Temperature: requireRange(path, var, data, 100.0, 400.0, "a temperature [K]"); break;
    case IconQuantity::Pressure: requireRange(path, var, data, 1.0, 2.0e5, "a pressure [Pa]"); break;
    case IconQuantity::Height: requireRange(path, var, data, kLowestHeight_m, kHighestHeight_m, "a height [m]"); break;
    case IconQuantity::CloudCoverPercent: {
      // clc is in percent (ICON, DWD GRIB2 "%"): to [0, 1]; negative values clamp to 0.
      const double scale = fraction_units ? 1.0 : 0.01;
      for (float& v : data) v = static_cast<float>(std::clamp(double(v) * scale, 0.0, 1.0));
      break;
    }
  }
}

ModelTimestep assembleIconTimestep(IconSourceFields src, const LoadOptions& options) {
  const std::size_t nz = src.nz, nsrc = src.npoints;
  const std::size_t height_levels = src.heights_are_half_levels ? nz + 1 : nz;
  auto require_size = [&](const std::vector<float>& f, std::size_t levels, const char* what) {
    if (f.size() != levels * nsrc) {
      throw InputError(
          fmt::format("{}: {} has {} values, expected {} levels x {} points", src.path, what, f.size(), levels, nsrc));
    }
  };
  for (auto& [kind, f] : src.q_kg_per_kg) require_size(f, nz, "a condensate field");
  require_size(src.temperature_k, nz, "temperature");
  require_size(src.pressure_pa, nz, "pressure");
  require_size(src.water_vapour_kg_per_kg, nz, "specific humidity");
  if (!src.cloud_cover_fraction.empty()) require_size(src.cloud_cover_fraction, nz, "cloud cover");
  require_size(src.heights_m, height_levels, src.heights_name.c_str());

  // Vertical order: ICON writes level 1 at the model top; nephele wants bottom to top.
  std::vector<float>& heights = src.heights_m;
  const bool top_down = nz > 1 ? heights[0] > heights[(height_levels - 1) * nsrc] : false;
  auto flip = [&](std::vector<float>& f, std::size_t levels) {
    if (!top_down || f.empty()) return;
    for (std::size_t k = 0; k < levels / 2; ++k) {
      std::swap_ranges(f.begin() + std::ptrdiff_t(k * nsrc), f.begin() + std::ptrdiff_t((k + 1) * nsrc),
                       f.begin() + std::ptrdiff_t((levels - 1 - k) * nsrc));
    }
  };
  for (auto& [kind, f] : src.q_kg_per_kg) flip(f, nz);
  flip(src.temperature_k, nz);
  flip(src.pressure_pa, nz);
  flip(src.water_vapour_kg_per_kg, nz);
  flip(src.cloud_cover_fraction, nz);
  flip(heights, height_levels);
  // Mass-level heights: midpoints of half levels (Muth §3.2: z_k = (h_k + h_k+1) / 2).
  std::vector<float> height(nz * nsrc);
  std::vector<float> terrain(nsrc);
  for (std::size_t p = 0; p < nsrc; ++p) {
    if (src.heights_are_half_levels) {
      terrain[p] = heights[p];
      for (std::size_t k = 0; k < nz; ++k) {
        const float lo = heights[k * nsrc + p], hi = heights[(k + 1) * nsrc + p];
        if (!(hi > lo)) {
          throw InputError(fmt::format("{}: {} does not increase with height at level {} (point {}): {} m then {} m",
                                       src.path, src.heights_name, k, p, lo, hi));
        }
        height[k * nsrc + p] = 0.5f * (lo + hi);
      }
    } else {
      for (std::size_t k = 0; k < nz; ++k) height[k * nsrc + p] = heights[k * nsrc + p];
      // Surface: half a layer below the lowest full level.
      const float dz = nz > 1 ? heights[nsrc + p] - heights[p] : 20.0f;
      terrain[p] = heights[p] - 0.5f * dz;
    }
  }
  heights = {};

  ModelTimestep ts;
  ts.source_file = src.path;
  ts.time_index = src.time_index;
  ts.time_utc = src.time_utc;
  ts.model = ModelKind::Icon;
  ts.nz = static_cast<int>(nz);
  ts.repairs = src.repairs;
  ts.georef.proj_definition = fmt::format("+proj=longlat +R={} +no_defs", kIconEarthRadius_m);
  ts.georef.geographic = true;
  const std::vector<std::size_t> source_of = src.native ? mapNative(src, options, ts) : mapRegular(src, ts);

  const std::size_t n2 = std::size_t(ts.nx) * std::size_t(ts.ny);
  auto remap = [&](const std::vector<float>& f, std::size_t levels) {
    std::vector<float> out(levels * n2);
    for (std::size_t k = 0; k < levels; ++k)
      for (std::size_t p = 0; p < n2; ++p) out[k * n2 + p] = f[k * nsrc + source_of[p]];
    return out;
  };
  for (auto& [kind, f] : src.q_kg_per_kg) ts.q_kg_per_kg[kind] = remap(f, nz);
  ts.temperature_k = remap(src.temperature_k, nz);
  ts.pressure_pa = remap(src.pressure_pa, nz);
  ts.water_vapour_kg_per_kg = remap(src.water_vapour_kg_per_kg, nz);
  if (!src.cloud_cover_fraction.empty()) ts.cloud_cover_fraction = remap(src.cloud_cover_fraction, nz);
  ts.height_m = remap(height, nz);
  ts.terrain_height_m = remap(terrain, 1);
  ts.georef.lon_deg.resize(n2);
  ts.georef.lat_deg.resize(n2);
  for (int j = 0; j < ts.ny; ++j) {
    for (int i = 0; i < ts.nx; ++i) {
      const std::size_t p = std::size_t(j) * std::size_t(ts.nx) + std::size_t(i);
      ts.georef.lon_deg[p] = static_cast<float>(ts.georef.x0 + i * ts.georef.dx_m);
      ts.georef.lat_deg[p] = static_cast<float>(ts.georef.y0 + j * ts.georef.dy_m);
    }
  }
  return ts;
}

}  // namespace nph::io

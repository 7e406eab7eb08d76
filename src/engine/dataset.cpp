#include "engine/dataset.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "cache/nph_cache.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/limits.h"
#include "core/log.h"
#include "io/model_file.h"
#include "physics/volume_builder.h"
#include "volume/volume_frame.h"

namespace nph::engine {
namespace {

/// Model files are opened with the detail fields deferred: a quick look converts a timestep with
/// them read after the optics' fields are freed (physics::buildExtinctionVolumes; issue 19, memory).
io::LoadOptions deferredDetailOptions() {
  io::LoadOptions o;
  o.defer_detail = true;
  return o;
}

class NphDataset final : public Dataset {
 public:
  NphDataset(const std::string& path, cache::NphReader reader, std::vector<geo::OptionalUtcTime> times)
      : Dataset(path, std::move(times)), reader_(std::move(reader)) {}
  ExtinctionVolumes load(std::size_t t) const override { return reader_.read(t); }
  std::unique_ptr<ExtinctionSlices> loadSlices(std::size_t t) const override { return reader_.readSlices(t); }
  std::optional<ExtinctionVolumes> loadHeader(std::size_t t) const override { return reader_.readHeader(t); }

 private:
  cache::NphReader reader_;  // read() is thread-safe (pread)
};

class ModelDataset final : public Dataset {
 public:
  ModelDataset(const std::string& path, io::ModelSeries series, std::vector<geo::OptionalUtcTime> times,
               std::vector<std::string> sources)
      : Dataset(path, std::move(times), std::move(sources)), series_(std::move(series)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    if (t >= timestepCount()) {
      throw UsageError(fmt::format("{}: timestep {} requested, the dataset has {}", path(), t, timestepCount()));
    }
    // NetCDF-C keeps global state without locks: one model file read at a time in the process.
    static std::mutex netcdf_mutex;
    std::lock_guard lock(netcdf_mutex);
    log::info("{}: not a .nph cache; converting timestep {} with the default optics", sourceFile(t), t);
    // WRF's detail fields are read once the optics' fields are freed (io::LoadOptions::defer_detail).
    return physics::buildExtinctionVolumes(
        series_.load(t), physics::defaultOptics(), physics::VerticalGridOptions{},
        [](io::ModelTimestep& fields) { io::loadDeferredDetail(fields, deferredDetailOptions()); });
  }

 private:
  io::ModelSeries series_;
};

/// Model fields held in memory, converted on every load as a model file's (the Python arrays).
class ModelFieldsDataset final : public Dataset {
 public:
  ModelFieldsDataset(std::string name, std::vector<io::ModelTimestep> fields, std::vector<geo::OptionalUtcTime> times)
      : Dataset(std::move(name), std::move(times)), fields_(std::move(fields)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    if (t >= fields_.size()) {
      throw UsageError(fmt::format("{}: timestep {} requested, the dataset has {}", path(), t, fields_.size()));
    }
    return convertModelTimestep(fields_[t]);
  }

 private:
  std::vector<io::ModelTimestep> fields_;
};

class MemoryDataset final : public Dataset {
 public:
  MemoryDataset(std::string name, std::vector<ExtinctionVolumes> volumes, std::vector<geo::OptionalUtcTime> times)
      : Dataset(std::move(name), std::move(times)), volumes_(std::move(volumes)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    if (t >= volumes_.size()) {
      throw UsageError(fmt::format("{}: timestep {} requested, the dataset has {}", path(), t, volumes_.size()));
    }
    return volumes_[t];
  }

 private:
  std::vector<ExtinctionVolumes> volumes_;
};

/// InputError unless `beta` holds `count` finite values >= 0 (an extinction coefficient).
void requireExtinction(const std::string& name, std::size_t t, const char* array, const std::vector<float>& beta,
                       std::size_t count) {
  if (beta.size() != count) {
    throw InputError(
        fmt::format("{}: timestep {}: {} has {} values, expected nx*ny*nz = {}", name, t, array, beta.size(), count));
  }
  const auto bad = std::find_if(beta.begin(), beta.end(), [](float b) { return !(b >= 0.0f) || std::isinf(b); });
  if (bad != beta.end()) {
    throw InputError(fmt::format("{}: timestep {}: {}[{}] = {}, expected a finite extinction coefficient >= 0 [1/m]",
                                 name, t, array, bad - beta.begin(), *bad));
  }
}

}  // namespace

Dataset::Dataset(std::string path, std::vector<geo::OptionalUtcTime> times, std::vector<std::string> sources)
    : path_(std::move(path)), times_(std::move(times)), sources_(std::move(sources)) {
  for (const auto& t : times_) iso_times_.push_back(geo::isoOrEmpty(t));
  if (times_.empty()) throw InputError(fmt::format("{}: has no timesteps", path_));
  if (!sources_.empty() && sources_.size() != times_.size()) throw UsageError("Dataset: one source file per timestep");
}

std::unique_ptr<ExtinctionSlices> Dataset::loadSlices(std::size_t t) const {
  return std::make_unique<VolumeSlices>(std::make_shared<const ExtinctionVolumes>(load(t)));
}

std::optional<ExtinctionVolumes> Dataset::loadHeader(std::size_t) const { return std::nullopt; }

std::string Dataset::identity(std::size_t t) const {
  if (sources_.empty()) return fmt::format("{}#{}", std::filesystem::absolute(path_).string(), t);
  return fmt::format("{}#{}", std::filesystem::absolute(sources_.at(t)).string(), t);
}

std::shared_ptr<const Dataset> Dataset::open(const std::string& path) {
  std::error_code ec;
  // DWD's GRIB2: a folder of files, or a pattern
  if (std::filesystem::is_directory(path, ec) ||
      (!std::filesystem::exists(path, ec) && path.find_first_of("*?[") != std::string::npos)) {
    return openSeries({path});
  }
  requireRegularFile(path, "a .nph cache, a WRF/ICON NetCDF or ICON GRIB2 file, or a folder of them");
  if (cache::NphReader::sniff(path)) {
    cache::NphReader reader(path);
    std::vector<geo::OptionalUtcTime> times;
    for (std::size_t t = 0; t < reader.timestepCount(); ++t) times.push_back(reader.timestep(t).time_utc);
    return std::make_shared<NphDataset>(path, std::move(reader), std::move(times));
  }
  return openSeries({path});
}

std::shared_ptr<const Dataset> Dataset::openSeries(const std::vector<std::string>& paths) {
  if (paths.empty()) throw UsageError("Dataset::openSeries: no files");
  if (paths.size() == 1 && std::filesystem::exists(paths[0]) && cache::NphReader::sniff(paths[0]))
    return open(paths[0]);
  const std::vector<std::string> files = io::expandModelInputs(paths);  // folders and patterns
  for (const auto& p : files) {
    requireRegularFile(p, "a WRF/ICON NetCDF or ICON GRIB2 file");
    if (cache::NphReader::sniff(p)) {
      throw InputError(
          fmt::format("{}: a .nph cache cannot be part of a series of model files; convert them together", p));
    }
  }
  io::ModelSeries series = io::ModelSeries::open(files, deferredDetailOptions());
  std::vector<geo::OptionalUtcTime> times;
  std::vector<std::string> sources;
  for (const auto& ref : series.timesteps()) {
    times.push_back(ref.time_utc);
    sources.push_back(ref.file);
  }
  if (files.size() == 1) sources.clear();
  const std::string name = paths.size() == 1 ? paths[0] : fmt::format("{} (and {} more)", paths[0], paths.size() - 1);
  return std::make_shared<ModelDataset>(name, std::move(series), std::move(times), std::move(sources));
}

std::shared_ptr<const Dataset> Dataset::fromVolumes(std::string name, std::vector<ExtinctionVolumes> timesteps) {
  std::vector<geo::OptionalUtcTime> times;
  for (std::size_t t = 0; t < timesteps.size(); ++t) {
    ExtinctionVolumes& v = timesteps[t];
    const auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
    if (v.nx <= 0 || v.ny <= 0 || v.nz <= 0) {
      throw InputError(
          fmt::format("{}: timestep {}: grid {}x{}x{}, expected at least one voxel", name, t, v.nx, v.ny, v.nz));
    }
    if (!positive(v.georef.dx_m) || !positive(v.georef.dy_m) || !positive(v.dz_m) || !std::isfinite(v.z_bottom_m)) {
      throw InputError(fmt::format("{}: timestep {}: spacing dx {} dy {} dz {} (z_bottom {}), expected finite values, "
                                   "the spacings > 0",
                                   name, t, v.georef.dx_m, v.georef.dy_m, v.dz_m, v.z_bottom_m));
    }
    requireExtinction(name, t, "ice_per_m", v.ice_per_m, v.voxelCount());
    requireExtinction(name, t, "water_per_m", v.water_per_m, v.voxelCount());
    const std::size_t columns = std::size_t(v.nx) * std::size_t(v.ny);
    if (!v.terrain_height_m.empty() && v.terrain_height_m.size() != columns) {
      throw InputError(fmt::format("{}: timestep {}: terrain_height_m has {} values, expected nx*ny = {}", name, t,
                                   v.terrain_height_m.size(), columns));
    }
    if (v.source_file.empty()) v.source_file = name;
    v.source_time_index = std::int64_t(t);
    v.updateMaxima();
    times.push_back(v.time_utc);
  }
  return std::make_shared<MemoryDataset>(std::move(name), std::move(timesteps), std::move(times));
}

std::shared_ptr<const Dataset> Dataset::fromModelFields(std::string name, std::vector<io::ModelTimestep> timesteps) {
  std::vector<geo::OptionalUtcTime> times;
  for (std::size_t t = 0; t < timesteps.size(); ++t) {
    if (timesteps[t].source_file.empty()) timesteps[t].source_file = name;
    timesteps[t].time_index = std::int64_t(t);
    times.push_back(timesteps[t].time_utc);
  }
  return std::make_shared<ModelFieldsDataset>(std::move(name), std::move(timesteps), std::move(times));
}

ExtinctionVolumes convertModelTimestep(const io::ModelTimestep& fields) {
  return physics::buildExtinctionVolumes(fields, physics::defaultOptics(), physics::VerticalGridOptions{});
}

ExtinctionVolumes convertModelTimestep(io::ModelTimestep&& fields) {
  return physics::buildExtinctionVolumes(std::move(fields), physics::defaultOptics(), physics::VerticalGridOptions{});
}

namespace {

/// Bilinear read of layer `layer` of a field laid out as ExtinctionVolumes (x fastest) at
/// fractional column indices (x, y), column centres at integers, clamped to the edge columns
/// (GL_CLAMP_TO_EDGE: what flows in across the domain's edge is the edge column's value, the inflow
/// boundary condition of a limited-area semi-Lagrangian scheme). At integer (x, y) the weights are
/// exactly 1 and 0, so the value is read back bit for bit.
float bilinear(const float* layer, int nx, int ny, double x, double y) {
  x = x > 0.0 ? std::min(x, double(nx - 1)) : 0.0;  // NaN (a NaN wind) reads the edge too
  y = y > 0.0 ? std::min(y, double(ny - 1)) : 0.0;
  const int i0 = std::min(int(x), nx - 1), j0 = std::min(int(y), ny - 1);
  const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
  const float fx = float(x - i0), fy = float(y - j0);
  const float* r0 = layer + std::size_t(j0) * std::size_t(nx);
  const float* r1 = layer + std::size_t(j1) * std::size_t(nx);
  return (r0[i0] * (1.0f - fx) + r0[i1] * fx) * (1.0f - fy) + (r1[i0] * (1.0f - fx) + r1[i1] * fx) * fy;
}

/// Where the air at each voxel centre of `v` is found after `seconds` of model time moving with
/// v's own horizontal wind (negative: where it was before), in fractional column indices (x, y per
/// voxel, v's layout). Semi-Lagrangian trajectory (Staniforth & Côté 1991, Mon. Wea. Rev. 119,
/// "Semi-Lagrangian integration schemes for atmospheric models — a review", §2–3): the
/// displacement d solves d = s·u(x + d/2), the wind at the trajectory's midpoint, by fixed-point
/// iteration from d = s·u(x) — two iterations, as operational two-time-level schemes use: with a
/// uniform wind the first is already exact, with a sheared one each iteration shrinks the error by
/// s·|∇u|/2 (< ½ while the wind moves air less than a column per column of shear). Per level:
/// only U and V move the air (W is left out, as the detail's noise leaves it out: volume/detail.h
/// DetailFlow). `dx`, `dy`: the column spacing in metres (volume::frameOf, also for lat-lon grids).
std::vector<float> trajectoryEnds(const ExtinctionVolumes& v, double seconds, double dx, double dy) {
  const int nx = v.nx, ny = v.ny;
  const std::size_t layer = std::size_t(nx) * std::size_t(ny);
  std::vector<float> ends(2 * v.voxelCount());
  const double sx = seconds / dx, sy = seconds / dy;  // metres per second -> columns
  // Levels are independent (each writes only its own ends): one task per level, the same floats
  // whatever the thread count.
  tbb::parallel_for(0, v.nz, [&](int k) {
    const float* u = v.wind_u_m_per_s.data() + std::size_t(k) * layer;
    const float* vv = v.wind_v_m_per_s.data() + std::size_t(k) * layer;
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
        double ex = sx * double(u[c]), ey = sy * double(vv[c]);
        for (int it = 0; it < 2; ++it) {
          const double mx = i + 0.5 * ex, my = j + 0.5 * ey;
          ex = sx * double(bilinear(u, nx, ny, mx, my));
          ey = sy * double(bilinear(vv, nx, ny, mx, my));
        }
        ends[2 * (std::size_t(k) * layer + c)] = float(i + ex);
        ends[2 * (std::size_t(k) * layer + c) + 1] = float(j + ey);
      }
    }
  });
  return ends;
}

/// Half-width (columns) of the window over which steeringWinds averages.
constexpr int kSteeringWindow = 2;

/// The wind a cloud column moves with (docs/animation.md "Clouds move as columns"): per column, the
/// horizontal wind averaged over its levels weighted by the cloud in them — β_a + β_b on the blend's
/// grid (layers: a's layer ka at oa + ka, b's kb at ob + kb) — and over the (2·kSteeringWindow + 1)²
/// columns around it; where that window holds no cloud, the plain mean over the levels. Returned
/// as a volume of v's grid holding only U, V: that wind at every level, so that trajectoryEnds
/// moves all levels of a column alike.
/// Why: a convective cell moves as a whole with a mean of the winds over its depth (the steering
/// wind; Bunkers et al. 2000, Wea. Forecasting 15, the 0–6 km mean), not each level with its own
/// wind. Moving each level with its own wind shears a tower in a wind that grows with height (6 m/s
/// at its base, 24 m/s at its top) into slanted streaks between the timesteps, where the model shows
/// an upright tower at both (the alpine life cycle, docs/animation.md). Weighted by the cloud, an
/// anvil column moves with the anvil's wind and a tower's with its depth's.
ExtinctionVolumes steeringWinds(const ExtinctionVolumes& v, int offset, const ExtinctionVolumes& a, int oa,
                                const ExtinctionVolumes& b, int ob) {
  const int nx = v.nx, ny = v.ny;
  const std::size_t layer = std::size_t(nx) * std::size_t(ny);
  const auto beta = [&](const ExtinctionVolumes& w, int k, std::size_t c) {
    if (k < 0 || k >= w.nz) return 0.0;
    double sum = 0.0;
    for (const std::vector<float>* f : {&w.ice_per_m, &w.water_per_m}) {
      if (!f->empty()) sum += double((*f)[std::size_t(k) * layer + c]);
    }
    return sum;
  };
  // Per column: Σβ·u, Σβ·v, Σβ, Σu, Σv over the levels.
  std::vector<std::array<double, 5>> column(layer, {0.0, 0.0, 0.0, 0.0, 0.0});
  tbb::parallel_for(std::size_t(0), layer, [&](std::size_t c) {
    std::array<double, 5>& s = column[c];
    for (int k = 0; k < v.nz; ++k) {
      const double u = double(v.wind_u_m_per_s[std::size_t(k) * layer + c]);
      const double w = double(v.wind_v_m_per_s[std::size_t(k) * layer + c]);
      const int level = offset + k;  // on the blend's grid
      const double m = beta(a, level - oa, c) + beta(b, level - ob, c);
      s[0] += m * u;
      s[1] += m * w;
      s[2] += m;
      s[3] += u;
      s[4] += w;
    }
  });
  ExtinctionVolumes out;  // the grid and the wind only: what trajectoryEnds reads
  out.nx = nx;
  out.ny = ny;
  out.nz = v.nz;
  out.wind_u_m_per_s.resize(v.wind_u_m_per_s.size());
  out.wind_v_m_per_s.resize(v.wind_v_m_per_s.size());
  tbb::parallel_for(0, ny, [&](int j) {
    for (int i = 0; i < nx; ++i) {
      std::array<double, 5> s{0.0, 0.0, 0.0, 0.0, 0.0};
      for (int q = std::max(j - kSteeringWindow, 0); q <= std::min(j + kSteeringWindow, ny - 1); ++q)
        for (int p = std::max(i - kSteeringWindow, 0); p <= std::min(i + kSteeringWindow, nx - 1); ++p) {
          const std::array<double, 5>& t = column[std::size_t(q) * std::size_t(nx) + std::size_t(p)];
          for (int n = 0; n < 5; ++n) s[std::size_t(n)] += t[std::size_t(n)];
        }
      const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      const std::array<double, 5>& own = column[c];
      const float u = float(s[2] > 0.0 ? s[0] / s[2] : own[3] / double(v.nz));
      const float w = float(s[2] > 0.0 ? s[1] / s[2] : own[4] / double(v.nz));
      for (int k = 0; k < v.nz; ++k) {
        out.wind_u_m_per_s[std::size_t(k) * layer + c] = u;
        out.wind_v_m_per_s[std::size_t(k) * layer + c] = w;
      }
    }
  });
  return out;
}

}  // namespace

bool blendHasMotion(const ExtinctionVolumes& a, const ExtinctionVolumes& b) {
  if (!a.time_utc || !b.time_utc || !(b.time_utc->secondsSince(*a.time_utc) > 0.0)) return false;
  const auto hasWind = [](const ExtinctionVolumes& v) {
    return v.wind_u_m_per_s.size() == v.voxelCount() && v.wind_v_m_per_s.size() == v.voxelCount();
  };
  return hasWind(a) && hasWind(b);
}

ExtinctionVolumes blendVolumes(const ExtinctionVolumes& a, const ExtinctionVolumes& b, double w, TimeBlend blend) {
  w = std::clamp(w, 0.0, 1.0);
  if (w == 0.0) return a;
  if (w == 1.0) return b;
  // Each timestep converted on the fly is cropped to its own column (bottom from its lowest
  // surface, top above its highest condensate), so two timesteps may start and end at different
  // layers of the same dz lattice: blend on the union of both (issue #18: a real 4-timestep
  // wrfout failed at frame 1), as the .nph route pads every timestep to one grid.
  const double shift_layers = (b.z_bottom_m - a.z_bottom_m) / a.dz_m;
  if (a.nx != b.nx || a.ny != b.ny || a.dz_m != b.dz_m || !(std::abs(shift_layers - std::round(shift_layers)) < 1e-6) ||
      !(std::abs(shift_layers) < double(limits::kMaxDerivedLevels))) {
    throw UsageError(fmt::format("cannot blend timesteps on different grids: {}x{}x{} (dz {} m from {} m) at {} and "
                                 "{}x{}x{} (dz {} m from {} m) at {}",
                                 a.nx, a.ny, a.nz, a.dz_m, a.z_bottom_m, geo::isoOrEmpty(a.time_utc), b.nx, b.ny, b.nz,
                                 b.dz_m, b.z_bottom_m, geo::isoOrEmpty(b.time_utc)));
  }
  const int shift = static_cast<int>(std::round(shift_layers));  // b's layer 0 is out's layer ob
  const int oa = std::max(-shift, 0), ob = std::max(shift, 0);
  ExtinctionVolumes out;
  out.nx = a.nx;
  out.ny = a.ny;
  out.nz = std::max(oa + a.nz, ob + b.nz);
  out.dz_m = a.dz_m;
  out.z_bottom_m = std::min(a.z_bottom_m, b.z_bottom_m);
  out.georef = a.georef;
  out.terrain_height_m = a.terrain_height_m;  // static in time
  out.time_utc = w < 0.5 ? a.time_utc : b.time_utc;
  out.source_file = a.source_file;
  out.source_time_index = a.source_time_index;
  const std::size_t layer = std::size_t(a.nx) * std::size_t(a.ny);
  // Motion compensation (TimeBlend::Motion; docs/animation.md "Between two timesteps"). The
  // cross-fade of Thomann 2021 §3.5 (listing 9: hourly meteoblue data, lerp by the time) keeps a
  // moving cloud at both its places mid-interval; frame interpolation in video does the same blend
  // after moving each key frame along its motion field to the in-between time, and the model gives
  // the motion field: its wind. Timestep a is read where the air at x was at a's time
  // (a trajectory back over w·Δt with a's wind), b where it will be at b's time (forward over
  // (1−w)·Δt with b's wind). A cloud carried by a uniform wind is then one cloud at the
  // in-between place (within the bilinear reads' smoothing), and the weights still sum to 1, so
  // what the model changed in place (growth, decay) still fades linearly. Not conservative: a
  // convergent or sheared wind compresses or stretches what it carries, and what leaves the
  // domain is replaced by the edge column (bilinear()).
  const bool motion = blend == TimeBlend::Motion && blendHasMotion(a, b);
  std::vector<float> from_a, to_b;  // per voxel of a (b): fractional (x, y) to read it at
  if (motion) {
    const volume::VolumeFrame frame = volume::frameOf(a);
    const double dt = b.time_utc->secondsSince(*a.time_utc);
    // Each column moves as one, with its cloud-weighted wind (steeringWinds).
    from_a = trajectoryEnds(steeringWinds(a, oa, a, oa, b, ob), -w * dt, frame.voxel_size_m.x, frame.voxel_size_m.y);
    to_b =
        trajectoryEnds(steeringWinds(b, ob, a, oa, b, ob), (1.0 - w) * dt, frame.voxel_size_m.x, frame.voxel_size_m.y);
  }
  // `src` weighted by `weight` into dst from dst's layer `offset` on, read at `ends` (or in place).
  const auto addMoved = [&](const std::vector<float>& src, int nz, const std::vector<float>& ends, float weight,
                            std::size_t offset, std::vector<float>& dst) {
    if (ends.empty()) {
      const std::size_t n = layer * std::size_t(nz);
      for (std::size_t i = 0; i < n; ++i) dst[offset + i] += weight * src[i];
      return;
    }
    tbb::parallel_for(0, nz, [&](int k) {  // per level, as trajectoryEnds
      const float* level = src.data() + std::size_t(k) * layer;
      for (std::size_t c = 0; c < layer; ++c) {
        const std::size_t i = std::size_t(k) * layer + c;
        dst[offset + i] += weight * bilinear(level, a.nx, a.ny, ends[2 * i], ends[2 * i + 1]);
      }
    });
  };
  const auto mix = [&](const std::vector<float>& va, int nza, const std::vector<float>& vb, int nzb,
                       std::vector<float>& dst) {
    dst.assign(layer * std::size_t(out.nz), 0.0f);
    if (!va.empty()) addMoved(va, nza, from_a, float(1.0 - w), layer * std::size_t(oa), dst);
    if (!vb.empty()) addMoved(vb, nzb, to_b, float(w), layer * std::size_t(ob), dst);
  };
  mix(a.ice_per_m, a.nz, b.ice_per_m, b.nz, out.ice_per_m);
  mix(a.water_per_m, a.nz, b.water_per_m, b.nz, out.water_per_m);
  // The detail fields (volume/detail.h) blend like β where both timesteps have them; a field only
  // one timestep has is dropped (the detail then uses its proxy, the same for every w in (0, 1)).
  const auto mixDetail = [&](const std::vector<float>& va, const std::vector<float>& vb, std::vector<float>& dst) {
    if (va.empty() || vb.empty()) return;
    mix(va, a.nz, vb, b.nz, dst);
  };
  mixDetail(a.tke_m2_per_s2, b.tke_m2_per_s2, out.tke_m2_per_s2);
  mixDetail(a.cloud_fraction, b.cloud_fraction, out.cloud_fraction);
  mixDetail(a.wind_w_m_per_s, b.wind_w_m_per_s, out.wind_w_m_per_s);
  mixDetail(a.wind_u_m_per_s, b.wind_u_m_per_s, out.wind_u_m_per_s);
  mixDetail(a.wind_v_m_per_s, b.wind_v_m_per_s, out.wind_v_m_per_s);
  // The noise's clock runs with model time through the blend (volume/detail.h DetailFlow), so the
  // advected noise moves smoothly across the interval and is continuous at each timestep.
  out.detail_clock_s = (1.0 - w) * a.detail_clock_s + w * b.detail_clock_s;
  out.updateMaxima();
  return out;
}

TimeBracket bracketTime(double t, std::size_t count) {
  TimeBracket b;
  if (count == 0) return b;
  if (!std::isfinite(t)) throw UsageError(fmt::format("time index {} is not finite", t));
  t = std::clamp(t, 0.0, double(count - 1));
  b.first = std::min(std::size_t(std::floor(t)), count - 1);
  b.second = std::min(b.first + 1, count - 1);
  b.weight = b.second == b.first ? 0.0 : t - double(b.first);
  return b;
}

}  // namespace nph::engine

#include "engine/dataset.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "cache/nph_cache.h"
#include "core/error.h"
#include "core/log.h"
#include "io/model_file.h"
#include "physics/volume_builder.h"

namespace nph::engine {
namespace {

class NphDataset final : public Dataset {
 public:
  NphDataset(const std::string& path, cache::NphReader reader, std::vector<std::string> times)
      : Dataset(path, std::move(times)), reader_(std::move(reader)) {}
  ExtinctionVolumes load(std::size_t t) const override { return reader_.read(t); }

 private:
  cache::NphReader reader_;  // read() is thread-safe (pread)
};

class ModelDataset final : public Dataset {
 public:
  ModelDataset(const std::string& path, io::ModelFile file, std::vector<std::string> times)
      : Dataset(path, std::move(times)), file_(std::move(file)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    if (t >= timestepCount()) {
      throw UsageError(fmt::format("{}: timestep {} requested, the file has {}", path(), t, timestepCount()));
    }
    log::info("{}: not a .nph cache; converting timestep {} with the default optics", path(), t);
    return physics::buildExtinctionVolumes(file_.load(t), physics::defaultOptics(), physics::VerticalGridOptions{});
  }

 private:
  io::ModelFile file_;
};

}  // namespace

Dataset::Dataset(std::string path, std::vector<std::string> times) : path_(std::move(path)), times_(std::move(times)) {
  if (times_.empty()) throw InputError(fmt::format("{}: has no timesteps", path_));
}

std::string Dataset::identity(std::size_t t) const {
  return fmt::format("{}#{}", std::filesystem::absolute(path_).string(), t);
}

std::shared_ptr<const Dataset> Dataset::open(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: no such file", path));
  if (cache::NphReader::sniff(path)) {
    cache::NphReader reader(path);
    std::vector<std::string> times;
    for (std::size_t t = 0; t < reader.timestepCount(); ++t) times.push_back(reader.timestep(t).time_utc);
    return std::make_shared<NphDataset>(path, std::move(reader), std::move(times));
  }
  io::ModelFile file = io::openModelFile(path);
  std::vector<std::string> times;
  for (const auto& ref : file.timesteps()) times.push_back(ref.time_utc);
  return std::make_shared<ModelDataset>(path, std::move(file), std::move(times));
}

ExtinctionVolumes blendVolumes(const ExtinctionVolumes& a, const ExtinctionVolumes& b, double w) {
  w = std::clamp(w, 0.0, 1.0);
  if (w == 0.0) return a;
  if (w == 1.0) return b;
  if (a.nx != b.nx || a.ny != b.ny || a.dz_m != b.dz_m || a.z_bottom_m != b.z_bottom_m) {
    throw UsageError(fmt::format("cannot blend timesteps on different grids: {}x{}x{} (dz {} m from {} m) at {} and "
                                 "{}x{}x{} (dz {} m from {} m) at {}",
                                 a.nx, a.ny, a.nz, a.dz_m, a.z_bottom_m, a.time_utc, b.nx, b.ny, b.nz, b.dz_m,
                                 b.z_bottom_m, b.time_utc));
  }
  ExtinctionVolumes out;
  out.nx = a.nx;
  out.ny = a.ny;
  out.nz = std::max(a.nz, b.nz);
  out.dz_m = a.dz_m;
  out.z_bottom_m = a.z_bottom_m;
  out.georef = a.georef;
  out.time_utc = w < 0.5 ? a.time_utc : b.time_utc;
  out.source_file = a.source_file;
  out.source_time_index = a.source_time_index;
  const std::size_t layer = std::size_t(a.nx) * std::size_t(a.ny);
  const auto mix = [&](const std::vector<float>& va, int nza, const std::vector<float>& vb, int nzb,
                       std::vector<float>& dst) {
    dst.assign(layer * std::size_t(out.nz), 0.0f);
    const float wa = float(1.0 - w), wb = float(w);
    const std::size_t na = va.empty() ? 0 : layer * std::size_t(nza), nb = vb.empty() ? 0 : layer * std::size_t(nzb);
    for (std::size_t i = 0; i < na; ++i) dst[i] = wa * va[i];
    for (std::size_t i = 0; i < nb; ++i) dst[i] += wb * vb[i];
  };
  mix(a.ice_per_m, a.nz, b.ice_per_m, b.nz, out.ice_per_m);
  mix(a.water_per_m, a.nz, b.water_per_m, b.nz, out.water_per_m);
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

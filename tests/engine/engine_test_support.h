#pragma once
// Helpers for the engine tests: a tiny generated WRF storm with a few hourly timesteps (real
// NetCDF through data_tools, converted on load by engine::Dataset) and a scripted in-memory
// dataset whose loads can be counted, held in flight (a gate, no sleeps) or made to fail.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cache/nph_cache.h"
#include "core/error.h"
#include "engine/dataset.h"
#include "support/scratch_dir.h"
#include "wrf_hurricane.h"

namespace nph::test {

/// A folder for this test process's files, removed at exit.
inline std::filesystem::path engineTestDir() {
  static const ScratchDir dir = ScratchDir::forProcess("engine");
  return dir.path();
}

/// `steps` (converted model timesteps on one grid) written to the .nph `file` with the cache's writer,
/// the first timestep's grid and terrain as the file's, as `nephele convert` writes them.
inline void writeNphOf(const std::filesystem::path& file, const std::vector<ExtinctionVolumes>& steps) {
  const ExtinctionVolumes& first = steps.at(0);
  cache::NphMetadata meta;
  meta.nx = first.nx;
  meta.ny = first.ny;
  meta.dz_m = first.dz_m;
  meta.z_bottom_m = first.z_bottom_m;
  meta.georef = first.georef;
  meta.terrain_height_m = first.terrain_height_m;
  cache::NphWriter writer(file, meta);
  for (const ExtinctionVolumes& v : steps) writer.append(v);
  writer.commit();
}

/// A tiny 3-timestep hurricane (hourly, drifting and intensifying), written once per process.
inline const std::string& tinyStormFile() {
  static const std::string path = [] {
    const auto dir = engineTestDir();
    const std::string p = (dir / "wrfout_tiny.nc").string();
    datagen::WrfHurricaneSpec spec;
    spec.ntimes = 3;
    datagen::writeWrfHurricane(spec, p);
    return p;
  }();
  return path;
}

/// Timesteps held in memory; load() counts calls, may be held at a gate, and fails for `fail_at`.
class ScriptedDataset final : public engine::Dataset {
 public:
  /// `times`: ISO 8601 per timestep, "" for none.
  ScriptedDataset(std::vector<ExtinctionVolumes> steps, const std::vector<std::string>& times)
      : Dataset("scripted.nph", parsed(times)), steps_(std::move(steps)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    ++loads;
    {
      std::unique_lock lock(gate_mutex_);
      if (held_ && *held_ == t) {
        holding_ = true;
        gate_cv_.notify_all();
        gate_cv_.wait(lock, [&] { return released_; });
      }
    }
    if (fail_at && *fail_at == t) throw InputError("scripted.nph: chunk " + std::to_string(t) + " is truncated");
    return steps_.at(t);
  }
  mutable std::atomic<int> loads{0};
  std::optional<std::size_t> fail_at;

  /// load(t) blocks once it has started until release(): a decode the test holds in flight.
  void hold(std::size_t t) {
    std::lock_guard lock(gate_mutex_);
    held_ = t;
  }
  /// Blocks until some thread is inside load() of the held timestep.
  void waitUntilHolding() const {
    std::unique_lock lock(gate_mutex_);
    gate_cv_.wait(lock, [&] { return holding_; });
  }
  void release() {
    {
      std::lock_guard lock(gate_mutex_);
      released_ = true;
    }
    gate_cv_.notify_all();
  }

 private:
  mutable std::mutex gate_mutex_;
  mutable std::condition_variable gate_cv_;
  std::optional<std::size_t> held_;
  mutable bool holding_ = false;
  bool released_ = false;

  static std::vector<nph::geo::OptionalUtcTime> parsed(const std::vector<std::string>& times) {
    std::vector<nph::geo::OptionalUtcTime> out;
    for (const std::string& t : times) out.push_back(nph::geo::parseOptional(t));
    return out;
  }
  std::vector<ExtinctionVolumes> steps_;
};

/// nx × ny × nz volumes whose every voxel holds `value` (ice) and 2·value (water).
inline ExtinctionVolumes constantVolumes(int nx, int ny, int nz, float value, const std::string& time = "") {
  ExtinctionVolumes v;
  v.nx = nx;
  v.ny = ny;
  v.nz = nz;
  v.dz_m = 250.0;
  v.georef.dx_m = v.georef.dy_m = 3000.0;
  v.time_utc = nph::geo::parseOptional(time);
  v.ice_per_m.assign(v.voxelCount(), value);
  v.water_per_m.assign(v.voxelCount(), 2.0f * value);
  v.updateMaxima();
  return v;
}

}  // namespace nph::test

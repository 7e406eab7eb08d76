#pragma once
// Helpers for the engine tests: a tiny generated WRF storm with a few hourly timesteps (real
// NetCDF through data_tools, converted on load by engine::Dataset) and a scripted in-memory
// dataset whose loads can be counted, slowed down or made to fail.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

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

/// Timesteps held in memory; load() counts calls, may sleep, and fails for `fail_at`.
class ScriptedDataset final : public engine::Dataset {
 public:
  ScriptedDataset(std::vector<ExtinctionVolumes> steps, std::vector<std::string> times)
      : Dataset("scripted.nph", std::move(times)), steps_(std::move(steps)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    ++loads;
    if (delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    if (fail_at && *fail_at == t) throw InputError("scripted.nph: chunk " + std::to_string(t) + " is truncated");
    return steps_.at(t);
  }
  mutable std::atomic<int> loads{0};
  int delay_ms = 0;
  std::optional<std::size_t> fail_at;

 private:
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
  v.time_utc = time;
  v.ice_per_m.assign(v.voxelCount(), value);
  v.water_per_m.assign(v.voxelCount(), 2.0f * value);
  v.updateMaxima();
  return v;
}

}  // namespace nph::test

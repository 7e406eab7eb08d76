// `nephele export-vdb INPUT... -o out/storm`: one OpenVDB file per timestep (out/storm_0000.vdb,
// ...) with the grids ice_extinction, water_extinction and density [1/m] (interop/vdb_export.h),
// for Blender, Houdini and Unreal Engine 5. The input is a .nph cache (values exactly as cached)
// or model files (converted with the default optics, as `nephele render` does). --nanovdb also
// writes out/storm_0000.nvdb (NanoVDB) per timestep.
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "core/error.h"
#include "core/log.h"
#include "engine/dataset.h"
#include "interop/vdb_export.h"

namespace nph::cli {

namespace {

struct ExportVdbOptions {
  std::vector<std::string> inputs;
  std::string output_prefix;
  std::vector<std::size_t> timesteps;  ///< empty: all
  bool stats = false;
  bool nanovdb = false;
};

int runExportVdb(const ExportVdbOptions& o) {
  const auto dataset =
      o.inputs.size() > 1 ? engine::Dataset::openSeries(o.inputs) : engine::Dataset::open(o.inputs.front());
  std::vector<std::size_t> timesteps = o.timesteps;
  if (timesteps.empty()) {
    for (std::size_t t = 0; t < dataset->timestepCount(); ++t) timesteps.push_back(t);
  }
  for (std::size_t t : timesteps) {
    if (t >= dataset->timestepCount()) {
      throw UsageError(fmt::format("--timestep {}: {} has {} timesteps (0..{})", t, dataset->path(),
                                   dataset->timestepCount(), dataset->timestepCount() - 1));
    }
  }
  const std::filesystem::path prefix(o.output_prefix);
  if (!prefix.parent_path().empty()) std::filesystem::create_directories(prefix.parent_path());

  interop::VdbWriteOptions options;
  options.creator = "nephele " NEPHELE_VERSION;
  options.nanovdb = o.nanovdb;
  for (std::size_t t : timesteps) {
    const ExtinctionVolumes volumes = dataset->load(t);
    const std::filesystem::path path = interop::vdbSequencePath(prefix, t);
    const interop::VdbWriteStats s = interop::writeVdb(volumes, path, options);
    log::info("{}: {} {}x{}x{}, {} of {} voxels active ({:.1f} %), {} leaves, {:.2f} MB", path.string(),
              geo::isoOrEmpty(volumes.time_utc), volumes.nx, volumes.ny, volumes.nz, s.active_voxels, s.dense_voxels,
              100.0 * double(s.active_voxels) / double(std::max<std::uint64_t>(s.dense_voxels, 1)), s.leaf_nodes,
              double(s.file_bytes) / 1e6);
    if (o.nanovdb) {
      log::info("{}: NanoVDB, {:.2f} MB", interop::nanovdbPathOf(path).string(), double(s.nanovdb_file_bytes) / 1e6);
    }
    if (o.stats) {
      std::printf("file=%s\ntime_utc=%s\nactive_voxels=%llu\ndense_voxels=%llu\nleaf_nodes=%llu\n"
                  "file_bytes=%llu\n",
                  path.string().c_str(), geo::isoOrEmpty(volumes.time_utc).c_str(),
                  static_cast<unsigned long long>(s.active_voxels), static_cast<unsigned long long>(s.dense_voxels),
                  static_cast<unsigned long long>(s.leaf_nodes), static_cast<unsigned long long>(s.file_bytes));
      if (o.nanovdb) {
        std::printf("nanovdb_file=%s\nnanovdb_file_bytes=%llu\n", interop::nanovdbPathOf(path).string().c_str(),
                    static_cast<unsigned long long>(s.nanovdb_file_bytes));
      }
    }
  }
  return kExitOk;
}

}  // namespace

void addExportVdbCommand(CLI::App& app, Action& run) {
  auto o = std::make_shared<ExportVdbOptions>();
  CLI::App* sub = app.add_subcommand(
      "export-vdb", "Write the extinction volumes as an OpenVDB sequence, one file per timestep\n"
                    "(PREFIX_0000.vdb, ...), with float grids ice_extinction, water_extinction and density\n"
                    "(their sum) in 1/m; transform in metres in the data's projected frame, georeference in\n"
                    "the grid metadata; sparse (clear air is not stored). Blender, Houdini and Unreal Engine 5\n"
                    "read it (docs/interop.md).\n"
                    "Example: nephele export-vdb storm.nph -o vdb/storm");
  sub->add_option("inputs", o->inputs, "a .nph cache, or model files (one time series)")
      ->required()
      ->check(existingPathOrPattern());
  sub->add_option("-o,--output", o->output_prefix,
                  "sequence prefix: PREFIX_0000.vdb, PREFIX_0001.vdb, ... (folders are created)")
      ->required();
  sub->add_option("-t,--timestep", o->timesteps, "export only these timesteps (repeatable)");
  sub->add_flag("--nanovdb", o->nanovdb,
                "also write each timestep as NanoVDB (PREFIX_0000.nvdb: the same grids and transform, for GPU "
                "engines)");
  sub->add_flag("--stats", o->stats, "print per file: active and dense voxel counts, leaves, bytes (key=value lines)");
  sub->callback([o, &run] { run = [o] { return runExportVdb(*o); }; });
}

}  // namespace nph::cli

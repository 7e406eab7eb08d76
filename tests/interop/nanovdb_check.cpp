// Reads a NanoVDB file written by `nephele export-vdb --nanovdb` back with NanoVDB's own reader
// (header-only, Debian libnanovdb-dev) and checks it against the .nph it came from, decoded by
// NphReader independently of the exporter (issue 16: "optionally a NanoVDB file for GPU engines").
//
// usage: nephele_nanovdb_check FILE.nph FILE.nvdb TIMESTEP
// Checked: the three float fog grids ice_extinction, water_extinction, density; every voxel of
// the model grid equals the cached value exactly (density = ice + water in float, as exported),
// clear air is inactive and reads 0; the active voxel count is the count of β > 0; voxel size and
// the index -> world map are the OpenVDB export's (interop::vdbFrameOf: metres in the data's
// projected frame, voxel (0,0,0) at (x0, y0, z_bottom + dz/2)). Prints one line per grid; exits 1
// with what differed.
#include <fmt/format.h>
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/IO.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cache/nph_cache.h"
#include "interop/vdb_export.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s FILE.nph FILE.nvdb TIMESTEP\n", argv[0]);
    return 2;
  }
  const nph::cache::NphReader reader(argv[1]);
  const nph::ExtinctionVolumes v = reader.read(std::stoul(argv[3]));
  const nph::interop::VdbFrame frame = nph::interop::vdbFrameOf(v);
  int failures = 0;
  const auto fail = [&](const std::string& what) {
    std::fprintf(stderr, "FAIL: %s\n", what.c_str());
    ++failures;
  };
  for (const char* name : {"ice_extinction", "water_extinction", "density"}) {
    const auto handle = nanovdb::io::readGrid(argv[2], name);
    const nanovdb::FloatGrid* grid = handle.grid<float>();
    if (grid == nullptr) {
      fail(fmt::format("{}: no float grid named {}", argv[2], name));
      continue;
    }
    if (grid->gridClass() != nanovdb::GridClass::FogVolume) fail(fmt::format("{}: not a fog volume", name));
    const nanovdb::Vec3R size = grid->voxelSize();
    if (std::abs(size[0] - frame.dx_m) > 1e-6 * frame.dx_m || std::abs(size[1] - frame.dy_m) > 1e-6 * frame.dy_m ||
        std::abs(size[2] - frame.dz_m) > 1e-6 * frame.dz_m) {
      fail(fmt::format("{}: voxel size {} {} {}, expected {} {} {}", name, size[0], size[1], size[2], frame.dx_m,
                       frame.dy_m, frame.dz_m));
    }
    for (const auto& [ijk, want] :
         {std::pair{nanovdb::Vec3R(0, 0, 0), nanovdb::Vec3R(frame.x0_m, frame.y0_m, frame.z0_m)},
          std::pair{nanovdb::Vec3R(v.nx - 1, v.ny - 1, v.nz - 1),
                    nanovdb::Vec3R(frame.x0_m + (v.nx - 1) * frame.dx_m, frame.y0_m + (v.ny - 1) * frame.dy_m,
                                   frame.z0_m + (v.nz - 1) * frame.dz_m)}}) {
      const nanovdb::Vec3R got = grid->indexToWorld(ijk);
      for (int c = 0; c < 3; ++c) {
        if (std::abs(got[c] - want[c]) > 1e-3) {
          fail(fmt::format("{}: index ({}, {}, {}) maps to {} on axis {}, expected {}", name, ijk[0], ijk[1], ijk[2],
                           got[c], c, want[c]));
        }
      }
    }
    const auto accessor = grid->getAccessor();
    std::uint64_t positive = 0, differing = 0;
    for (int k = 0; k < v.nz; ++k) {
      for (int j = 0; j < v.ny; ++j) {
        for (int i = 0; i < v.nx; ++i) {
          const std::size_t n = v.index(i, j, k);
          const std::string_view which(name);
          const float want = which == "ice_extinction"     ? v.ice_per_m[n]
                             : which == "water_extinction" ? v.water_per_m[n]
                                                           : v.ice_per_m[n] + v.water_per_m[n];
          const nanovdb::Coord c(i, j, k);
          positive += want > 0.0f ? 1 : 0;
          if (accessor.getValue(c) != want || accessor.isActive(c) != (want > 0.0f)) ++differing;
        }
      }
    }
    if (differing != 0) fail(fmt::format("{}: {} of {} voxels differ from the .nph", name, differing, v.voxelCount()));
    if (grid->activeVoxelCount() != positive) {
      fail(
          fmt::format("{}: {} active voxels, the .nph has {} with beta > 0", name, grid->activeVoxelCount(), positive));
    }
    std::printf("%s: %llu active voxels of %zu, voxel %.0f x %.0f x %.0f m, every voxel equal to the .nph\n", name,
                static_cast<unsigned long long>(grid->activeVoxelCount()), v.voxelCount(), size[0], size[1], size[2]);
  }
  return failures == 0 ? 0 : 1;
}

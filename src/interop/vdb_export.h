#pragma once
// OpenVDB export of extinction volumes (issue #16): one .vdb file per timestep, the way into
// Blender volume objects, Houdini and Unreal Engine 5 Sparse Volume Textures.
//
// Each file holds three float grids, all in [1/m]:
//   ice_extinction    β_ext of ice + snow + graupel + hail (ExtinctionVolumes::ice_per_m)
//   water_extinction  β_ext of cloud + rain (ExtinctionVolumes::water_per_m)
//   density           their sum, the total extinction coefficient. With the scene in metres
//                     (1 Blender unit = 1 m) a renderer's "density" times path length is the
//                     optical depth, so Cycles' Principled Volume with density = this grid
//                     reproduces the transmittance nephele renders (Nes 2008 eq. 5.3, §5.6).
//
// Sparse: only voxels with β > 0 are set (background 0, inactive elsewhere), so OpenVDB stores
// leaf nodes (8³ voxels) only where there is condensate; clear air costs nothing. Values are the
// decoded floats of the input, unchanged (a .nph input keeps its 16-bit quantisation bound,
// max/131070 per timestep, nph_cache.h).
//
// Transform (index -> world, metres): voxel (i, j, k) is centred at
//   x = x0_m + i·dx_m,  y = y0_m + j·dy_m,  z = z_bottom_m + (k + ½)·dz_m
// in the data's projected frame: the grid's own map projection for metric grids (Lambert,
// Mercator, polar stereographic: x0/y0 are the projected coordinates of mass point (0, 0) with the
// projection's false easting/northing), and for geographic (lat-lon, rotated-pole) grids the
// equirectangular projection at the grid's central latitude φc on nephele's sphere, the same
// local scaling nephele's own flat-map frame uses (volume/volume_frame.h): x = R·λ·cos φc, y = R·φ
// (λ, φ in radians, rotated-pole coordinates for rotated grids). z is height above mean sea level.
// Voxels are not cubes (dx ≠ dz): the transform is a scale-translate map.
//
// Georeference in every grid's metadata (strings unless noted):
//   nephele_frame_proj      PROJ definition of the frame x/y are in (see above); "" for Cartesian
//   nephele_grid_proj       the model grid's own PROJ definition (GridGeoreference)
//   nephele_lonlat_corners  "lon,lat;..." of the footprint's outer corners (SW, SE, NE, NW)
//   nephele_time_utc, nephele_source_file, nephele_units ("1/m"), nephele_quantity
//   nephele_x0_m, nephele_y0_m, nephele_z_bottom_m, nephele_dx_m, nephele_dy_m, nephele_dz_m (double)
//   nephele_nx, nephele_ny, nephele_nz (int): the model grid's size (index range [0, n))
#include <cstdint>
#include <filesystem>
#include <string>

#include "volume/extinction_volumes.h"

namespace nph::interop {

/// Index -> world placement of a volume in the data's projected frame (see above).
struct VdbFrame {
  double dx_m = 0.0, dy_m = 0.0, dz_m = 0.0;  ///< voxel size [m]
  double x0_m = 0.0, y0_m = 0.0;              ///< centre of voxel (0, 0, ·)
  double z0_m = 0.0;                          ///< centre of layer 0 above mean sea level
  std::string frame_proj_definition;          ///< PROJ definition of x/y; "" for Cartesian grids
};

/// The frame of `volumes`. UsageError for an empty volume or non-positive spacing.
VdbFrame vdbFrameOf(const ExtinctionVolumes& volumes);

struct VdbWriteOptions {
  std::string creator = "nephele";  ///< file metadata "creator"
  /// Also write the density grid (ice + water); the two extinction grids are always written.
  bool density = true;
  /// Also write the same grids as NanoVDB (nanovdbPathOf(path)): the flat, pointer-free layout
  /// GPU engines load straight into a buffer (NanoVDB's own renderers, Houdini's and UE5's NanoVDB
  /// paths). Values, transform and grid names are the OpenVDB file's; the nephele_* metadata is
  /// not carried (NanoVDB grids hold no string metadata).
  bool nanovdb = false;
};

struct VdbWriteStats {
  std::uint64_t active_voxels = 0;  ///< of the density grid (voxels with β > 0)
  std::uint64_t leaf_nodes = 0;     ///< 8³ leaves allocated in the density grid
  std::uint64_t dense_voxels = 0;   ///< nx·ny·nz
  std::uint64_t file_bytes = 0;
  std::uint64_t nanovdb_file_bytes = 0;  ///< 0 when no NanoVDB file was written
};

/// Writes `volumes` to `path` (through a temporary file renamed over `path`, so no partial .vdb is
/// left behind), and with options.nanovdb the NanoVDB copy the same way. IoError names the file
/// when it cannot be written.
VdbWriteStats writeVdb(const ExtinctionVolumes& volumes, const std::filesystem::path& path,
                       const VdbWriteOptions& options = {});

/// `storm_0007.vdb` -> `storm_0007.nvdb`: where writeVdb puts the NanoVDB copy.
std::filesystem::path nanovdbPathOf(const std::filesystem::path& vdb_path);

/// `prefix_0007.vdb` for timestep 7 of a sequence (Blender's and Houdini's sequence naming: the
/// frame number is the last digit group before the extension). A trailing ".vdb" on `prefix` is
/// dropped first.
std::filesystem::path vdbSequencePath(const std::filesystem::path& prefix, std::size_t index);

}  // namespace nph::interop

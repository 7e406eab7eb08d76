#include "interop/vdb_export.h"

#include <fmt/format.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <mutex>
#include <numbers>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "scene/georeference.h"
#include "volume/volume_frame.h"

namespace nph::interop {

namespace {

/// "+proj=longlat ..." -> "+proj=eqc +lat_ts=φc ..." (and "+o_proj=longlat" -> "+o_proj=eqc" for
/// rotated poles, where ob_tran hands lat_ts to the oblique projection): the projection whose
/// metres are frameOf()'s local equirectangular scaling of the grid's degrees.
std::string equirectangularOf(const std::string& geographic_definition, double lat_ts_deg) {
  std::string d = geographic_definition;
  const std::string eqc = fmt::format("eqc +lat_ts={:.10g} +lat_0=0", lat_ts_deg);
  for (const char* key : {"+o_proj=longlat", "+proj=longlat", "+o_proj=latlong", "+proj=latlong"}) {
    const std::size_t at = d.find(key);
    if (at == std::string::npos) continue;
    const std::size_t value = d.find('=', at) + 1;
    d.replace(value, d.find(' ', value) == std::string::npos ? d.size() - value : d.find(' ', value) - value, eqc);
    break;
  }
  // frameOf() scales on nephele's sphere (volume_frame.h); say so instead of the model's radius.
  const std::size_t r = d.find("+R=");
  if (r != std::string::npos) {
    const std::size_t end = d.find(' ', r);
    d.replace(r, end == std::string::npos ? d.size() - r : end - r, fmt::format("+R={:.0f}", volume::kEarthRadius_m));
  }
  return d;
}

void initialiseOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

openvdb::FloatGrid::Ptr sparseGrid(const ExtinctionVolumes& v, const std::vector<float>* a,
                                   const std::vector<float>* b) {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (int k = 0; k < v.nz; ++k) {
    for (int j = 0; j < v.ny; ++j) {
      for (int i = 0; i < v.nx; ++i) {
        const std::size_t n = v.index(i, j, k);
        const float value = (*a)[n] + (b ? (*b)[n] : 0.0f);
        if (value > 0.0f) acc.setValue(openvdb::Coord(i, j, k), value);  // clear air stays unset
      }
    }
  }
  return grid;
}

/// Writes through `path`.partial renamed into place (no partial file under the final name).
template <class Write>
void writeThenRename(const std::filesystem::path& path, const char* what, Write&& write) {
  const std::filesystem::path partial = path.string() + ".partial";
  try {
    write(partial.string());
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(partial, ec);
    throw IoError(fmt::format("{}: cannot write the {} file: {}", path.string(), what, e.what()));
  }
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) {
    std::filesystem::remove(partial, ec);
    throw IoError(
        fmt::format("{}: cannot rename the written {} file into place: {}", path.string(), what, ec.message()));
  }
}

}  // namespace

VdbFrame vdbFrameOf(const ExtinctionVolumes& v) {
  const volume::VolumeFrame world = volume::frameOf(v);  // metres per voxel, as nephele renders it
  const geo::GridGeoreference& g = v.georef;
  VdbFrame f;
  f.dx_m = world.voxel_size_m.x;
  f.dy_m = world.voxel_size_m.y;
  f.dz_m = world.voxel_size_m.z;
  f.z0_m = v.z_bottom_m + 0.5 * v.dz_m;
  if (g.geographic) {
    const double lat_centre_deg = g.y0 + 0.5 * double(v.ny - 1) * g.dy_m;  // as frameOf()
    f.x0_m = g.x0 * (f.dx_m / g.dx_m);
    f.y0_m = g.y0 * (f.dy_m / g.dy_m);
    f.frame_proj_definition = equirectangularOf(g.proj_definition, lat_centre_deg);
  } else {
    f.x0_m = g.x0;
    f.y0_m = g.y0;
    f.frame_proj_definition = g.proj_definition;
  }
  return f;
}

std::filesystem::path nanovdbPathOf(const std::filesystem::path& vdb_path) {
  std::filesystem::path p = vdb_path;
  return p.replace_extension(".nvdb");
}

std::filesystem::path vdbSequencePath(const std::filesystem::path& prefix, std::size_t index) {
  std::filesystem::path p = prefix;
  if (p.extension() == ".vdb") p.replace_extension();
  return p.parent_path() / fmt::format("{}_{:04d}.vdb", p.filename().string(), index);
}

VdbWriteStats writeVdb(const ExtinctionVolumes& v, const std::filesystem::path& path, const VdbWriteOptions& options) {
  if (v.ice_per_m.size() != v.voxelCount() || v.water_per_m.size() != v.voxelCount()) {
    throw UsageError(
        fmt::format("writeVdb {}: volume arrays do not match the {}x{}x{} grid", path.string(), v.nx, v.ny, v.nz));
  }
  initialiseOpenVdb();
  const VdbFrame frame = vdbFrameOf(v);

  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(1.0);
  transform->preScale(openvdb::Vec3d(frame.dx_m, frame.dy_m, frame.dz_m));
  transform->postTranslate(openvdb::Vec3d(frame.x0_m, frame.y0_m, frame.z0_m));

  std::string corners;
  if (!v.georef.proj_definition.empty()) {
    const scene::SceneGeoreference geo(v, volume::frameOf(v));
    for (const scene::LonLat& c : geo.footprintCorners()) {
      corners += fmt::format("{}{:.6f},{:.6f}", corners.empty() ? "" : ";", c.lon_deg, c.lat_deg);
    }
  }

  openvdb::GridPtrVec grids;
  auto add = [&](openvdb::FloatGrid::Ptr grid, const char* name, const char* quantity) {
    grid->setName(name);
    grid->setTransform(transform);
    // A fog volume: the values are a density-like quantity, background 0 (what Blender, Houdini
    // and UE5 expect of a smoke/cloud grid).
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->insertMeta("nephele_quantity", openvdb::StringMetadata(quantity));
    grid->insertMeta("nephele_units", openvdb::StringMetadata("1/m"));
    grid->insertMeta("nephele_time_utc", openvdb::StringMetadata(geo::isoOrEmpty(v.time_utc)));
    grid->insertMeta("nephele_source_file", openvdb::StringMetadata(v.source_file));
    grid->insertMeta("nephele_frame_proj", openvdb::StringMetadata(frame.frame_proj_definition));
    grid->insertMeta("nephele_grid_proj", openvdb::StringMetadata(v.georef.proj_definition));
    grid->insertMeta("nephele_lonlat_corners", openvdb::StringMetadata(corners));
    grid->insertMeta("nephele_x0_m", openvdb::DoubleMetadata(frame.x0_m));
    grid->insertMeta("nephele_y0_m", openvdb::DoubleMetadata(frame.y0_m));
    grid->insertMeta("nephele_z_bottom_m", openvdb::DoubleMetadata(v.z_bottom_m));
    grid->insertMeta("nephele_dx_m", openvdb::DoubleMetadata(frame.dx_m));
    grid->insertMeta("nephele_dy_m", openvdb::DoubleMetadata(frame.dy_m));
    grid->insertMeta("nephele_dz_m", openvdb::DoubleMetadata(frame.dz_m));
    grid->insertMeta("nephele_nx", openvdb::Int32Metadata(v.nx));  // the model grid, of which
    grid->insertMeta("nephele_ny", openvdb::Int32Metadata(v.ny));  // the active voxels are a part
    grid->insertMeta("nephele_nz", openvdb::Int32Metadata(v.nz));
    grids.push_back(grid);
    return grid;
  };
  add(sparseGrid(v, &v.ice_per_m, nullptr), "ice_extinction", "extinction coefficient of ice, snow, graupel and hail");
  add(sparseGrid(v, &v.water_per_m, nullptr), "water_extinction", "extinction coefficient of cloud droplets and rain");
  openvdb::FloatGrid::Ptr density;
  if (options.density) {
    density = add(sparseGrid(v, &v.ice_per_m, &v.water_per_m), "density", "total extinction coefficient (ice + water)");
  }

  openvdb::MetaMap file_meta;
  file_meta.insertMeta("creator", openvdb::StringMetadata(options.creator));
  file_meta.insertMeta("nephele_time_utc", openvdb::StringMetadata(geo::isoOrEmpty(v.time_utc)));

  writeThenRename(path, "OpenVDB", [&](const std::string& partial) {
    openvdb::io::File file(partial);
    file.write(grids, file_meta);
    file.close();
  });
  VdbWriteStats stats;
  if (options.nanovdb) {
    // NanoVDB (Museth 2021): each FloatGrid converted as is (32-bit floats, no quantisation),
    // the grids' names kept, all in one .nvdb, uncompressed so a GPU engine can map it directly.
    std::vector<nanovdb::GridHandle<nanovdb::HostBuffer>> handles;
    for (const openvdb::GridBase::Ptr& grid : grids) {
      handles.push_back(nanovdb::openToNanoVDB(*openvdb::gridPtrCast<openvdb::FloatGrid>(grid)));
    }
    const std::filesystem::path nvdb = nanovdbPathOf(path);
    writeThenRename(nvdb, "NanoVDB", [&](const std::string& partial) { nanovdb::io::writeGrids(partial, handles); });
    stats.nanovdb_file_bytes = std::filesystem::file_size(nvdb);
  }
  const openvdb::FloatGrid& counted = density ? *density : *openvdb::gridPtrCast<openvdb::FloatGrid>(grids[0]);
  stats.active_voxels = counted.activeVoxelCount();
  stats.leaf_nodes = counted.tree().leafCount();
  stats.dense_voxels = v.voxelCount();
  stats.file_bytes = std::filesystem::file_size(path);
  return stats;
}

}  // namespace nph::interop

#pragma once
// A user DEM under the clouds (issue 14 item 2: "ground elevation from the model's own field and,
// optionally, a user DEM (GeoTIFF through GDAL)"). Scene file: "terrain": {"dem": "srtm.tif"}.
//
// The DEM is any raster GDAL reads with a coordinate reference system and one band of heights in
// metres above sea level (SRTM, Copernicus GLO-30/90, GMTED2010, a VRT mosaic of tiles, ...); its
// nodata value is honoured. It is warped by GDAL's warper (bilinear, the basemap's transformer
// chain: scene/gdal_support.h) onto two grids of the flat view's world frame:
//   1. the model's mass points ((i + ½)·dx, (j + ½)·dy): there the DEM replaces the model's own
//      field (WRF HGT, ICON HSURF) wherever it has data; where it has none (nodata, outside the
//      raster) the model's field stays (volume/terrain_field.h terrainOf: "the DEM wins");
//   2. the far basemap's square around the footprint (scene::farBasemapRectangle, 1024 × 1024
//      pixels like the far basemap): the ground beyond the domain, sea level where the DEM has no
//      data, so mountains go on to the horizon (glsl/common/terrain.glsl's far field).
// Both are uploaded with the volume (render::VolumeTextures) and drawn by the same march, normals
// and shadows as the model's terrain.
#include <memory>
#include <string>
#include <vector>

#include "scene/basemap.h"
#include "scene/georeference.h"
#include "volume/terrain_field.h"
#include "volume/volume_frame.h"

namespace nph::scene {

/// A DEM opened through GDAL. Cheap to copy (the dataset is shared); not thread-safe.
class DemRaster {
 public:
  /// Opens `path`. Throws InputError naming `path` when it is missing, not a regular file, not a
  /// raster GDAL reads, has no CRS or no geotransform, has other than one band, a band of other
  /// than 16/32-bit integers or 32/64-bit floats (Byte is a picture, not heights), a colour
  /// palette, or a unit other than metres.
  static DemRaster open(const std::string& path);

  const std::string& name() const;
  int width() const;
  int height() const;
  /// The band's nodata value is set (those pixels are "no data").
  bool hasNoData() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<Impl> impl_;
};

/// `dem` warped onto `width` × `height` pixels covering `rect` of the world frame of `geo`
/// (pixel-is-area: pixel (i, j)'s centre at rect.min_m + ((i + ½)·w_px, (j + ½)·h_px)), x fastest,
/// row 0 at the SOUTH edge (the mass points' and textures' order); NaN where the DEM has no data.
/// Throws InputError naming the file when GDAL cannot read the heights (a truncated file) or a
/// height lies outside [io::kLowestHeight_m, io::kHighestTerrain_m] (not metres above sea level).
std::vector<float> warpDem(const DemRaster& dem, const SceneGeoreference& geo, const WorldRect& rect, int width,
                           int height);

/// Both grids of the header comment for the volume placed by `frame`: the mass points (refined
/// `refine` times per cell each way: DemHeights::refine) and, when `far_field` (the flat view; the
/// globe's terrain ends with its table), the far square (farBasemapRectangle, kFarBasemapPixels
/// per side).
volume::DemHeights demHeightsFor(const DemRaster& dem, const SceneGeoreference& geo, const volume::VolumeFrame& frame,
                                 bool far_field = true, int refine = 1);

/// How many times the model's cell (the smaller of dx, dy) holds the DEM's own pixel at the
/// footprint's centre, rounded, in [1, kMaxTerrainRefine] and at most 4096 / max(nx, ny) (the
/// texture's side): the lattice on which the DEM keeps the relief it has (docs/terrain.md "A DEM
/// finer than the model"). 1 where the DEM does not cover the centre, or is as coarse as the model.
int demRefinementFor(const DemRaster& dem, const SceneGeoreference& geo, const volume::VolumeFrame& frame);

}  // namespace nph::scene

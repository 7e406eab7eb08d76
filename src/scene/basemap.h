#pragma once
// Satellite basemap under the clouds (Nes 2008 §5.5: NASA Blue Marble drawn as the background, the
// volume composited over it; §5.5.3: higher-resolution imagery where it helps). Issue 14 item 3:
// the imagery is read through GDAL, so any raster GDAL opens serves (GeoTIFF/COG, VRT, MBTiles,
// PNG/JPEG with a world file, a WMTS service description, ...), and it is reprojected into the
// data's map frame by GDAL's warper (GDALChunkAndWarpImage with bilinear resampling) rather than by
// hand. BasemapRaster is an opened, georeferenced source.
//
// Georeference of a source: its own CRS and geotransform (GeoTIFF keys, .prj/.wld/.aux.xml, ...).
// A raster with neither is taken as a whole-Earth equirectangular (plate carrée) image when its
// width is twice its height: lon −180..180 left to right, lat 90..−90 top to bottom, pixel-is-area
// (pixel (0, 0) covers lon [−180, −180 + 360/w], lat [90 − 180/h, 90]) — Debian's `marble-qt-data`
// Blue Marble (/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg, 2700×1350), the
// zero-configuration default, is such an image. Any other raster without a CRS is refused.
// Whole-Earth lon/lat sources wrap across the antimeridian (a VRT places the image three times side
// by side, so bilinear filtering there sees both neighbours).
//
// Colour: 8- and 16-bit integer rasters are taken as sRGB-encoded and decoded to linear after the
// warp (IEC 61966-2-1 piecewise curve; GDAL interpolates the codes, so at sharp edges — coastlines —
// the result differs from decoding first: up to 17 of 255 codes on the demo, mean 0.05 codes);
// float rasters are taken as linear already. Float images Debian's GDAL has no driver for
// (OpenEXR, Radiance HDR) are read with OpenImageIO as whole-Earth 2:1 images. Alpha bands
// mask the source (transparent = no data); grey rasters are replicated to RGB.
//
// Flat view: reprojectBasemap() warps the raster into the data's map projection over a world
// rectangle (volume footprint plus margin) — what the ray caster draws on the ground and what the
// CPU references use. Globe view: the GPU samples an equirectangular image (reprojectEquirectangular())
// directly through equirectUv(); EquirectangularImage::sampleLonLat() is the CPU reference of
// that lookup.
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/georeference.h"

namespace nph::scene {

/// Linear-RGB float image, row 0 at the top (north for map images), RGB interleaved.
struct LinearRgbImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  ///< width·height·3
  /// Issue 19 (memory): every source pixel behind the image was an 8- or 16-bit integer code (the
  /// "Colour" rule above; Blue Marble's JPEG), so no more than half floats' 11 significant bits
  /// are needed to hold it and the GPU stores it as RGBA16F (render/raycast/cloud_renderer.cpp).
  /// False (the default) for float rasters and images made in memory: they keep float textures
  /// (a float raster may carry more than 11 bits, as the tests' lon/lat-coded basemaps do).
  bool integer_source = false;

  glm::vec3 at(int x, int y) const {
    const std::size_t i = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// sRGB transfer function (IEC 61966-2-1): encoded [0, 1] -> linear (the inverse, linearToSrgb,
/// is in scene/output_image.h).
float srgbToLinear(float encoded);

/// The zero-configuration basemap: NASA Blue Marble from Debian's marble-qt-data (2700×1350,
/// whole Earth, no georeference: the 2:1 rule). Also laid under regional rasters (scene_setup.h).
inline constexpr const char* kBlueMarblePath = "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg";

/// A raster opened through GDAL with its georeference (see the header comment). Cheap to copy (the
/// dataset is shared); not thread-safe.
class BasemapRaster {
 public:
  /// Opens `path` with GDAL. Throws InputError naming `path` when it is missing, not a regular
  /// file, not a raster GDAL reads, larger than limits::kMaxBasemapSourcePixels, has no CRS (and
  /// is not a 2:1 whole-Earth image), or has bands other than 1-4 of 8/16-bit integers or floats.
  static BasemapRaster open(const std::string& path);
  /// From memory: a linear-RGB whole-Earth equirectangular image (2:1), through the same warper.
  static BasemapRaster fromEquirectangular(const LinearRgbImage& image, const std::string& name = "<memory>");

  const std::string& name() const;
  int width() const;
  int height() const;
  /// Whether the source covers the whole Earth in lon/lat (it wraps across the antimeridian).
  bool wholeEarth() const;
  /// Whether its pixels are 8- or 16-bit integer codes (sRGB-encoded), not floats.
  bool integerCoded() const;
  /// Issue 14 item 3, imagery LOD: the widths of the file's reduced-resolution levels (GeoTIFF/COG
  /// internal overviews, external .ovr), finest first; empty when it has none. The warp
  /// (reprojectBasemap, reprojectEquirectangular) reads the coarsest level that still has at least
  /// one source pixel per output pixel, as gdalwarp's `-ovr AUTO`, instead of the full resolution.
  const std::vector<int>& overviewWidths() const;
  /// The same file opened at overview `level` (an index into overviewWidths(); GDAL's OVERVIEW_LEVEL
  /// open option, the geotransform scaled to it). Throws UsageError for a level it does not have.
  BasemapRaster atOverview(int level) const;
  /// The overview level this raster reads (-1: full resolution).
  int overviewLevel() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<Impl> impl_;
};

/// Lon/lat sampling of an equirectangular linear-RGB image: the CPU twin of the globe's lookup.
class EquirectangularImage {
 public:
  /// Opens `path` through GDAL (BasemapRaster::open; same errors) and warps it onto the whole Earth
  /// at its natural size (equirectangularSizeFor).
  static EquirectangularImage load(const std::string& path);
  /// From memory (tests, procedurally made images): linear RGB, must be 2:1.
  explicit EquirectangularImage(LinearRgbImage image, std::string name = "<memory>");

  /// Bilinear lookup at lon/lat [deg]: wraps across the antimeridian, clamps at the poles.
  glm::vec3 sampleLonLat(double lon_deg, double lat_deg) const;
  const LinearRgbImage& image() const { return image_; }
  const std::string& name() const { return name_; }

 private:
  LinearRgbImage image_;
  std::string name_;
};

/// Size of the whole-Earth equirectangular image the globe draws `raster` with: a whole-Earth
/// source keeps its own size; a regional one gets its own resolution in degrees; both are capped
/// at 8192 × 4096 (limits::kMaxBasemapPixels).
glm::ivec2 equirectangularSizeFor(const BasemapRaster& raster);

/// `layers` (bottom first, as reprojectBasemap) warped onto the whole Earth, `width` × `height`
/// plate carrée (row 0 = 90°N, equirectUv's pixels), linear RGB; black where no layer has data.
LinearRgbImage reprojectEquirectangular(const std::vector<BasemapRaster>& layers, int width, int height);

/// Texture coordinates of lon/lat in an equirectangular texture: u = (lon + 180)/360 (wrap in
/// u), v = (90 − lat)/180 with v = 0 at the top row (the GPU's globe lookup uses the same).
glm::dvec2 equirectUv(double lon_deg, double lat_deg);

/// A world-space rectangle (metres, volume_frame.h) and the image that covers it.
struct WorldRect {
  glm::dvec2 min_m{0.0};
  glm::dvec2 max_m{0.0};
};

/// The volume's footprint [0, size.x] × [0, size.y] grown by `margin_fraction` of its larger side
/// on every side (0.25 = a quarter of the larger side each way).
WorldRect basemapRectangle(const volume::VolumeFrame& frame, double margin_fraction);

/// Pixel (px, py) centre of a `width`×`height` image covering `rect` (row 0 = north edge).
glm::dvec2 worldFromBasemapPixel(const WorldRect& rect, int width, int height, double px, double py);

/// Warps `layers` (bottom first) into the data's projection with GDAL's warper: output pixel ->
/// world -> lon/lat (through `geo`, offset included) -> each source's pixel, bilinear. A layer
/// writes only where it has data, so a regional raster over a whole-Earth one keeps the latter
/// around it; pixels no layer covers (or PROJ cannot invert) are black, their count logged.
/// Throws UsageError for an empty rectangle or size, InputError naming the file when GDAL cannot
/// read the pixels (a truncated file).
LinearRgbImage reprojectBasemap(const std::vector<BasemapRaster>& layers, const SceneGeoreference& geo,
                                const WorldRect& rect, int width, int height);
inline LinearRgbImage reprojectBasemap(const BasemapRaster& source, const SceneGeoreference& geo, const WorldRect& rect,
                                       int width, int height) {
  return reprojectBasemap(std::vector<BasemapRaster>{source}, geo, rect, width, height);
}
/// An in-memory image through the same warper.
inline LinearRgbImage reprojectBasemap(const EquirectangularImage& source, const SceneGeoreference& geo,
                                       const WorldRect& rect, int width, int height) {
  return reprojectBasemap(BasemapRaster::fromEquirectangular(source.image(), source.name()), geo, rect, width, height);
}

}  // namespace nph::scene

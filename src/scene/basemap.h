#pragma once
// Satellite basemap under the clouds (Nes 2008 §5.5: NASA Blue Marble drawn as the background, the
// volume composited over it). The source is an equirectangular (plate carrée) image covering
// lon −180..180 left to right and lat 90..−90 top to bottom, pixel-is-area (pixel (0, 0) covers
// lon [−180, −180 + 360/w], lat [90 − 180/h, 90]). The demo uses Debian's `marble-qt-data`
// (/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg, 2700×1350).
//
// Colour: 8- and 16-bit integer images are taken as sRGB-encoded and decoded to linear
// (IEC 61966-2-1 piecewise curve); half/float images (EXR, HDR) are taken as linear already.
// Alpha or extra channels are dropped; grey images are replicated to RGB.
//
// Flat view: reprojectBasemap() resamples the image into the data's map projection over a world
// rectangle (volume footprint plus margin) with bilinear filtering — what the ray caster draws at
// z = 0 and what the CPU references use. Globe view: the GPU samples the equirectangular image
// directly through equirectUv(); sampleLonLat() is the CPU reference of that lookup.
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

  glm::vec3 at(int x, int y) const {
    const std::size_t i = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// sRGB transfer function (IEC 61966-2-1): encoded [0, 1] -> linear (the inverse, linearToSrgb,
/// is in scene/output_image.h).
float srgbToLinear(float encoded);

class EquirectangularImage {
 public:
  /// Loads with OpenImageIO. Throws InputError naming `path` when it is missing, unreadable or
  /// not an image with 1-4 channels, and when its aspect ratio is not 2:1 (±1 pixel), which an
  /// image covering 360° × 180° must have.
  static EquirectangularImage load(const std::string& path);
  /// From memory (tests, procedurally made images): linear RGB, must be 2:1 like load().
  explicit EquirectangularImage(LinearRgbImage image, std::string name = "<memory>");

  /// Bilinear lookup at lon/lat [deg]: wraps across the antimeridian, clamps at the poles.
  glm::vec3 sampleLonLat(double lon_deg, double lat_deg) const;
  const LinearRgbImage& image() const { return image_; }
  const std::string& name() const { return name_; }

 private:
  LinearRgbImage image_;
  std::string name_;
};

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
WorldRect basemapRectangle(const VolumeFrame& frame, double margin_fraction);

/// Pixel (px, py) centre of a `width`×`height` image covering `rect` (row 0 = north edge).
glm::dvec2 worldFromBasemapPixel(const WorldRect& rect, int width, int height, double px, double py);

/// Resamples `source` into the data's projection: pixel centres -> world -> lon/lat (through
/// `geo`, offset included) -> bilinear lookup. Points PROJ cannot invert become black; their count
/// is logged. Throws UsageError for an empty rectangle or size.
LinearRgbImage reprojectBasemap(const EquirectangularImage& source, const SceneGeoreference& geo, const WorldRect& rect,
                                int width, int height);

}  // namespace nph::scene

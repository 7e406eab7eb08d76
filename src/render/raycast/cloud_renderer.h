#pragma once
// The eye pass: ray casting of the ice and water volumes with deep-light-map look-ups, composited
// over the lit basemap (glsl/render/clouds.comp; Nes 2008 §5.4 eq. 5.18, §5.5; Muth 2026 §3.4).
// Flat-map view only for now (the globe view of issue 5 is not implemented).
#include <glm/glm.hpp>

#include "render/dlm/deep_light_map.h"
#include "render/dlm/volume_textures.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "scene/basemap.h"
#include "scene/camera.h"
#include "scene/output_image.h"
#include "scene/sun.h"

namespace nph::render {

struct RenderSettings {
  double step_voxels = 0.5;              ///< view-ray step Δ in units of the smallest voxel side
  double min_transmittance = 0.01;       ///< early ray termination
  bool jitter = true;                    ///< per-pixel start offset against banding
  bool empty_space_skipping = true;
  bool shadows = true;                   ///< cloud shadows on the ground (DLM at z = 0)
  double g_ice = 0.75;                   ///< HG asymmetry of ice crystals (physics/phase.h)
  double g_water = 0.85;                 ///< HG asymmetry of droplets (physics/phase.h)
  glm::dvec3 ambient{0.20, 0.24, 0.30};  ///< uniform sky radiance (sun radiance = 1)
  glm::dvec3 ocean_albedo{0.02, 0.04, 0.07};  ///< ground outside the basemap
};

struct RenderOutput {
  scene::RgbaImage cloud_layer;  ///< premultiplied linear RGBA: the clouds alone
  scene::RgbaImage frame;        ///< clouds composited over the lit ground, alpha 1
  double milliseconds = 0.0;
};

class CloudRenderer {
 public:
  CloudRenderer();
  /// Sets (uploads) the basemap: linear RGB covering `rect` of the world (row 0 = north).
  void setBasemap(const scene::LinearRgbImage& image, const scene::WorldRect& rect);
  RenderOutput render(const VolumeTextures& volume, const DeepLightMap& dlm, const scene::Camera& camera,
                      const scene::Sun& sun, const RenderSettings& settings);

 private:
  gl::Program program_;
  gl::Texture basemap_, blank_;
  scene::WorldRect basemap_rect_;
};

}  // namespace nph::render

#pragma once
// Small scenes rendered end to end through engine::Session (scene file text -> Dataset -> Session
// -> CloudRenderer), the path `nephele render` takes: golden images and placement tests.
#include <memory>
#include <string>

#include "engine/session.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/camera.h"
#include "scene/output_image.h"
#include "scene/sun.h"
#include "support/scratch_dir.h"
#include "volume/extinction_volumes.h"
#include "wrf_hurricane.h"

namespace nph::test {

/// Writes a 720 × 360 equirectangular linear EXR whose colour encodes lon/lat (R = (lon+180)/360,
/// G = (90−lat)/180) with a 10° checkerboard in B (0.2 / 0.6), so images show where the map is.
void writeCodedBasemap(const std::string& path);
/// lon/lat [deg] from a basemap colour of writeCodedBasemap.
void decodeBasemapColour(float r, float g, double& lon_deg, double& lat_deg);
/// writeCodedBasemap's blue at lon/lat: 0.2 or 0.6, constant over 10° squares.
double codedBasemapBlue(double lon_deg, double lat_deg);
/// Continuous image position (x right, y down, pixel centres at + 0.5) of a world point.
glm::dvec2 projectedPixel(const scene::Camera& cam, const glm::dvec3& world);
/// The sub-pixel image position of the ground point at `target` (lon, lat) in a frame over the coded
/// basemap, whose blue there is `blue`: blue/blue_true is the lighting (sun only, grey), so (red,
/// green)/that decodes the lon/lat a pixel shows, whatever the shading; the nearest pixel, then
/// one Newton step on the decoded field's local Jacobian (the terrain placement tests).
glm::dvec2 locateCodedLonLat(const scene::RgbaImage& frame, const scene::Camera& cam, glm::dvec2 target, double blue);

/// The small storm of the golden and placement tests: 80 × 72 × 20 mass points at 5 km (a
/// 400 × 360 km domain with eye and eyewall), one timestep, in `projection`.
datagen::WrfHurricaneSpec smallStormSpec(datagen::WrfProjection projection = datagen::WrfProjection::Lambert);
/// The storm centre's lon/lat from the generator's own XLAT/XLONG (bilinear between mass points).
scene::LonLat stormCentreLonLat(const datagen::WrfTruth& truth, const datagen::WrfHurricaneSpec& spec);

/// A session of `scene_json` (a scene file's text; its data.path is replaced by `data_path`) with a
/// current GL context.
std::unique_ptr<engine::Session> openSession(const std::string& scene_json, const std::string& data_path);

/// The demo's oblique view of a volume (issue 13's coarse storm): height exaggeration 8, 40°
/// field of view, the sun of the demo (azimuth 140°, elevation 35°).
struct DemoView {
  volume::VolumeFrame frame;
  scene::Camera camera;
  scene::Sun sun{140.0, 35.0};
};
DemoView demoView(const ExtinctionVolumes& v, int width, int height, double distance_scale = 1.0);

/// Uploads `v` with the filter and sub-grid detail given, builds the DLM (empty-space skipping as
/// `rs`, texels of `dlm_texel_voxels`) and ray casts the demo view with `rs`.
render::RenderOutput renderDemoView(const ExtinctionVolumes& v, const DemoView& d, const render::RenderSettings& rs,
                                    volume::Reconstruction reconstruction, volume::Detail detail = volume::Detail::None,
                                    double dlm_texel_voxels = 1.0);

}  // namespace nph::test

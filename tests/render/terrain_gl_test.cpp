// Terrain through the renderer (issue 14 "Done means": "a generated storm over a generated Gaussian
// mountain at a known lon/lat shows the summit at the projected pixel (≤ 1.5 px) and the cloud
// behind it occluded"). The data is a real wrfout written through NetCDF-C by nephele-gen's
// generator (issue 13's coarse storm, 72 × 64 columns at 10 km, Lambert) with a 3000 m Gaussian
// mountain (σ = 35 km) added to HGT at a lon/lat; the chain under test is wrfout → loader
// (HGT) → ExtinctionVolumes::terrain_height_m → Session → VolumeTextures (R32F) → the eye pass's
// march (glsl/common/terrain.glsl) → the frame.
//
// 1. Summit placement. The basemap codes lon/lat in red/green (render_scenes.h) and is constant in
//    blue inside the mountain's 10° square, so blue/blue_true is the lighting at a pixel (sun only,
//    grey: no sky light, no atmosphere) and (red, green)/that decodes the lon/lat of the ground
//    point the pixel shows, whatever the slope's shading. The point showing the mountain's lon/lat
//    (sub-pixel, from the decoded field's local Jacobian) must be within 1.5 px of the projection
//    of the summit's world point (x, y, e·h(x, y)) at height exaggeration e = 4. The same search on
//    the flat ground (knob terrain off) lands tens of pixels away: the check sees the displacement.
// 2. Occlusion. A low camera looks through the mountain at the storm behind it. At the pixels
//    whose rays meet the mountain (CPU twin of the march) and pass through thick cloud behind it
//    (exact optical depth of the untruncated ray ≥ 2), the GPU layer's α with terrain is the
//    truncated ray's 1 − e^{−τ(0, t_ground)} (≈ 0: the air in front of the mountain is clear), and
//    without terrain it is the cloud's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "reference/path_tracer_field.h"
#include "render/raycast/globe.h"
#include "render_scenes.h"
#include "support/gl_fixture.h"
#include "volume/terrain_field.h"

namespace nph::test {
namespace {

constexpr double kMountainLon_deg = -76.2, kMountainLat_deg = 24.3;
constexpr double kMountainHeight_m = 3000.0, kMountainSigma_m = 35000.0;
constexpr double kExaggeration = 4.0;

// The summit's lon/lat over the coded basemap: blue 0.2 in its 10° square (x/20 + y/20 even).
glm::dvec2 locateLonLat(const scene::RgbaImage& frame, const scene::Camera& cam) {
  return locateCodedLonLat(frame, cam, {kMountainLon_deg, kMountainLat_deg}, 0.2);
}

// Low (1200 m), 120 km from the summit on the side away from the storm's centre turned by 60°,
// looking at the mountain's upper half: behind it lies the stratiform shield, and along part of the
// mountain the air in front of it is clear. (The shield covers most of the mountain's surroundings:
// from the unturned direction, or from higher up, every ray that meets the mountain crosses opaque
// cloud before it, and α = 1 with or without terrain would prove nothing.)
scene::Camera lowCameraFacingTheMountain(const scene::PreparedScene& prep, const glm::dvec3& summit) {
  const glm::dvec2 summitXy(summit);
  const glm::dvec2 centre(0.5 * prep.frame.size_m().x, 0.55 * prep.frame.size_m().y);
  const glm::dvec2 out = glm::normalize(summitXy - centre);
  const double turn = glm::radians(60.0);
  const glm::dvec2 away(std::cos(turn) * out.x - std::sin(turn) * out.y,
                        std::sin(turn) * out.x + std::cos(turn) * out.y);
  scene::Camera cam = prep.flat_camera;
  cam.target_m = summit - glm::dvec3(0.0, 0.0, 0.3 * summit.z);
  cam.position_m = glm::dvec3(summitXy + 120000.0 * away, 0.1 * summit.z);
  cam.vertical_fov_deg = 30.0;
  return cam;
}

// What the occlusion tests count over the pixels whose ray meets the mountain with thick cloud
// behind it: α with terrain against the bound from the optical depth in front of the ground
// (`allowed`), α without terrain, and α with terrain where the air in front is clear (τ < 0.1).
struct OcclusionTally {
  int hidden = 0, clear = 0;
  double worst = 0.0, weakest = 1.0, clearWith = 0.0;
  void add(double with, double without, double inFront, double allowed) {
    ++hidden;
    worst = std::max(worst, with - allowed);
    weakest = std::min(weakest, without);
    if (inFront < 0.1) {  // clear air in front: here the mountain is what hides the cloud
      ++clear;
      clearWith = std::max(clearWith, with);
    }
  }
  void check(const char* view, double worstBound) const {
    std::printf("[ terrain] %s: %d pixels of cloud behind the mountain: alpha with terrain <= in-front alpha (to a "
                "quarter cell past the ground) + %.4f; without terrain >= %.3f; %d with clear air in front, alpha "
                "with terrain <= %.4f\n",
                view, hidden, worst, weakest, clear, clearWith);
    EXPECT_GT(hidden, 200) << "the camera must see thick cloud behind the mountain";
    EXPECT_GT(clear, 200) << "the test needs pixels where the cloud in front of the mountain is thin";
    EXPECT_LT(worst, worstBound);
    EXPECT_LT(clearWith, 0.12);
    EXPECT_GT(weakest, 0.5);
  }
};

class TerrainRender : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    dir_ = std::make_unique<ScratchDir>("terrain");
    datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
    spec.ntimes = 1;
    spec.mountain = {kMountainLon_deg, kMountainLat_deg, kMountainHeight_m, kMountainSigma_m};
    data_ = dir_->file("wrfout_mountain.nc");
    basemap_ = dir_->file("coded.exr");
    truth_ = datagen::writeWrfHurricane(spec, data_);
    writeCodedBasemap(basemap_);
  }
  std::unique_ptr<engine::Session> open(int width, int height, const std::string& view = "flat") const {
    const std::string json = R"({"data": {"path": "x"}, "camera": {"preset": "top", "fov_deg": 30},
      "sun": {"azimuth_deg": 200, "elevation_deg": 60},
      "basemap": {"path": ")" +
                             basemap_ + R"(", "margin": 0.1, "pixels_long_side": 2048},
      "quality": {"preset": "broadcast", "overrides": {"shadows": false}},
      "output": {"width": )" +
                             std::to_string(width) + R"(, "height": )" + std::to_string(height) + R"(},
      "height_exaggeration": 4, "view": ")" +
                             view + R"("})";
    return openSession(json, data_);
  }
  void summitLandsAtItsProjectedPixel(const std::string& view);
  std::unique_ptr<ScratchDir> dir_;
  std::string data_, basemap_;
  datagen::WrfTruth truth_;
};

// The summit test in `view` ("flat" or "globe"): on the globe the same camera is carried onto the
// sphere (scene::globeCameraFrom, as a scene file's camera is) and the summit's world point with it
// (SceneGeoreference::ecefFromWorld: radius R + e·h).
void TerrainRender::summitLandsAtItsProjectedPixel(const std::string& view) {
  auto session = open(320, 240, view);
  lighting::StyleSettings style = session->style();
  style.atmosphere = false;
  style.ambient = glm::dvec3(0.0);  // sunlight only: grey, so blue measures the shading
  session->setStyle(style);
  session->renderSettings().min_transmittance = 1.0;  // clouds off: no ray marches
  const auto& prep = session->prepared();
  const volume::TerrainField terrain = volume::terrainOf(session->dataset().load(0), prep.frame);
  ASSERT_TRUE(terrain.present());
  const glm::dvec2 summitXy = prep.geo->worldFromLonLat({kMountainLon_deg, kMountainLat_deg});
  const double summitZ = terrain.heightAt(summitXy);
  // The grid samples the Gaussian every 10 km: its bilinear surface at the summit's lon/lat keeps
  // ≥ 97 % of the height (the summit is at most 7 km from a mass point: e^{−49/2450} = 0.98).
  EXPECT_GT(summitZ, 0.97 * kExaggeration * kMountainHeight_m);
  EXPECT_LE(summitZ, 1.0001 * kExaggeration * kMountainHeight_m);
  glm::dvec3 summit(summitXy, summitZ);

  scene::Camera cam = prep.flat_camera;
  const double az = glm::radians(225.0), el = glm::radians(25.0), distance_m = 150000.0;
  // Aimed off the summit, so that its pixel is neither the image centre nor a pixel centre.
  cam.target_m = summit + glm::dvec3(3170.0, -4310.0, -2270.0);
  cam.position_m =
      summit + distance_m * glm::dvec3(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
  if (view == "globe") {
    cam = scene::globeCameraFrom(cam, *prep.geo);
    summit = prep.geo->ecefFromWorld(summit);
  }
  const glm::dvec2 expected = projectedPixel(cam, summit);

  const auto locate = [&](const scene::RgbaImage& frame) { return locateLonLat(frame, cam); };
  const glm::dvec2 found = locate(session->render(cam).frame);
  const double miss = glm::length(found - expected);
  std::printf("[ terrain] %s: summit (%.1f m world) at pixel (%.3f, %.3f), projected (%.3f, %.3f): %.3f px\n",
              view.c_str(), summitZ, found.x, found.y, expected.x, expected.y, miss);
  EXPECT_LE(miss, 1.5);

  session->renderSettings().terrain = false;  // the bare ground: the same lon/lat is far away in the image
  const glm::dvec2 flat = locate(session->render(cam).frame);
  std::printf("[ terrain] %s: without terrain the lon/lat shows at (%.2f, %.2f): %.1f px away\n", view.c_str(), flat.x,
              flat.y, glm::length(flat - expected));
  EXPECT_GT(glm::length(flat - expected), 20.0);
  // ... and there it is the bare ground's point (sea level: the plane z = 0, the sphere R). On the
  // globe this caught llvmpipe's inexact asin (every latitude 0.0093° low: 2.3 px here; globe.glsl).
  const glm::dvec3 bare(summitXy, 0.0);
  const glm::dvec2 expectedBare = projectedPixel(cam, view == "globe" ? prep.geo->ecefFromWorld(bare) : bare);
  std::printf("[ terrain] %s: bare ground projected at (%.2f, %.2f): %.3f px\n", view.c_str(), expectedBare.x,
              expectedBare.y, glm::length(flat - expectedBare));
  EXPECT_LE(glm::length(flat - expectedBare), 1.5);
}

TEST_F(TerrainRender, SummitLandsAtItsProjectedPixel) { summitLandsAtItsProjectedPixel("flat"); }

TEST_F(TerrainRender, OnTheGlobeSummitLandsAtItsProjectedPixel) { summitLandsAtItsProjectedPixel("globe"); }

TEST_F(TerrainRender, MountainHidesTheCloudBehindIt) {
  auto session = open(240, 160);
  const auto& prep = session->prepared();
  const ExtinctionVolumes volumes = session->dataset().load(0);
  const volume::TerrainField terrain = volume::terrainOf(volumes, prep.frame);
  const glm::dvec2 summitXy = prep.geo->worldFromLonLat({kMountainLon_deg, kMountainLat_deg});
  const glm::dvec3 summit(summitXy, terrain.heightAt(summitXy));
  const scene::Camera cam = lowCameraFacingTheMountain(prep, summit);

  const auto layerWith = [&](bool on) {
    session->renderSettings().terrain = on;
    return session->render(cam).cloud_layer;
  };
  const scene::RgbaImage with = layerWith(true), without = layerWith(false);
  const reference::ExtinctionField field(volumes, session->volumeTextures().frame(),
                                         session->volumeTextures().reconstruction());
  OcclusionTally tally;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
      const double ground = terrain.hitDistance(cam.position_m, d, 0.0, 1e30);
      if (ground < 0.0) continue;
      const glm::dvec3 hit = cam.position_m + ground * d;
      if (glm::length(glm::dvec2(hit) - summitXy) > 2.0 * kMountainSigma_m) continue;  // the mountain itself
      if (field.opticalDepth(cam.position_m, d, 0.0, 1e300) < 2.0) continue;           // thick cloud behind it
      const double inFront = -std::expm1(-field.opticalDepth(cam.position_m, d, 0.0, ground));
      const std::size_t o = (std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4 + 3;
      // The GPU's march floors its step near the surface at a quarter of a lattice cell
      // horizontally (glsl/common/terrain.glsl), so on rays that graze the mountain's limb it
      // may find the ground up to one such step late: the bound is the α up to that point.
      const double lateBy = 0.25 * std::min(terrain.cell_m.x, terrain.cell_m.y) / glm::length(glm::dvec2(d));
      const double inFrontLate = -std::expm1(-field.opticalDepth(cam.position_m, d, 0.0, ground + lateBy));
      tally.add(with.rgba[o], without.rgba[o], inFront, inFrontLate);
    }
  }
  tally.check("flat", 0.01);  // the CPU's ground hit is exact
}

// 3. Ground detail (style knob ground_tint; glsl/common/ground_tint.glsl). Off (the default) the
//    branch is skipped: the frame is the imagery's. On, with the snow line at 2000 m, the ground
//    above 2300 m (the transition's top) on the mountain's gentle slopes (≤ 3°, far below the rock's
//    30°) is 95 % snow: the coded basemap's constant blue 0.2 becomes 0.05·0.2 + 0.95·0.83 under the
//    same light, so each such pixel's blue is exactly 3.9925 times the untinted one (float rounding
//    only); below 1700 m the covers are zero and the pixel is the untinted one bit for bit; and with
//    the snow line above every summit the whole frame is the untinted one bit for bit.
TEST_F(TerrainRender, GroundTintPutsSnowAboveTheSnowLineAndNothingElsewhere) {
  auto session = open(240, 180);
  lighting::StyleSettings style = session->style();
  ASSERT_FALSE(style.ground_tint) << "synthesis is off by default";
  style.atmosphere = false;
  style.ambient = glm::dvec3(0.0);  // sunlight only, as the placement test
  session->setStyle(style);
  session->renderSettings().min_transmittance = 1.0;  // clouds off
  session->renderSettings().jitter = false;
  const auto& prep = session->prepared();
  const volume::TerrainField terrain = volume::terrainOf(session->dataset().load(0), prep.frame);
  const glm::dvec2 summitXy = prep.geo->worldFromLonLat({kMountainLon_deg, kMountainLat_deg});
  const glm::dvec3 summit(summitXy, terrain.heightAt(summitXy));
  scene::Camera cam = prep.flat_camera;
  const double az = glm::radians(225.0), el = glm::radians(25.0), distance_m = 120000.0;
  cam.target_m = summit;
  cam.position_m =
      summit + distance_m * glm::dvec3(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
  const auto frameWith = [&](bool tint, double snowLine_m) {
    session->renderSettings().ground_tint = tint;
    session->renderSettings().snow_line_m = snowLine_m;
    return session->render(cam).frame;
  };
  const scene::RgbaImage off = frameWith(false, 2000.0), on = frameWith(true, 2000.0),
                         nothing = frameWith(true, 6000.0);
  EXPECT_EQ(nothing.rgba, off.rgba) << "a snow line above every summit tints nothing";
  const double ratio = (0.05 * 0.2 + 0.95 * 0.83) / 0.2;
  int snow = 0, bare = 0;
  double worst = 0.0;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
      const double t = terrain.hitDistance(cam.position_m, d, 0.0, 1e30);
      if (t < 0.0) continue;
      const glm::dvec3 hit = cam.position_m + t * d;
      const double height_m = hit.z / kExaggeration;
      const std::size_t o = (std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4;
      if (height_m > 2400.0) {
        ++snow;
        worst = std::max(worst, std::abs(double(on.rgba[o + 2]) / double(off.rgba[o + 2]) / ratio - 1.0));
      } else if (height_m < 1600.0) {
        ++bare;
        for (int k = 0; k < 4; ++k)
          ASSERT_EQ(on.rgba[o + std::size_t(k)], off.rgba[o + std::size_t(k)]) << x << ", " << y;
      }
    }
  }
  std::printf("[ terrain] ground tint: %d snow pixels, blue x %.4f within %.2e; %d pixels below the snow line "
              "unchanged\n",
              snow, ratio, worst, bare);
  EXPECT_GT(snow, 200);
  EXPECT_GT(bare, 2000);
  EXPECT_LT(worst, 1e-4);
}

// 2b. Occlusion on the globe: the flat test's low camera carried onto the sphere. The reference
// marches each pixel's straight ECEF ray on the CPU in 250 m steps, mapping every point to the world
// through the globe's table (render::worldXyFromTable, the shader's twin): the ray is under the
// ground where |p| − R ≤ e·h(W(p)); the optical depth in front of the ground and behind it sums the
// extinction at (W(p), |p| − R) times the exaggeration's scale f(d) of the ray's direction in the
// footprint's local frame, as the eye pass does.
TEST_F(TerrainRender, OnTheGlobeTheMountainHidesTheCloudBehindIt) {
  auto session = open(240, 160, "globe");
  const auto& prep = session->prepared();
  const ExtinctionVolumes volumes = session->dataset().load(0);
  const volume::TerrainField terrain = volume::terrainOf(volumes, prep.frame);
  const glm::dvec2 summitXy = prep.geo->worldFromLonLat({kMountainLon_deg, kMountainLat_deg});
  const glm::dvec3 summit(summitXy, terrain.heightAt(summitXy));
  const scene::Camera cam = scene::globeCameraFrom(lowCameraFacingTheMountain(prep, summit), *prep.geo);

  const auto layerWith = [&](bool on) {
    session->renderSettings().terrain = on;
    return session->render(cam).cloud_layer;
  };
  const scene::RgbaImage with = layerWith(true), without = layerWith(false);
  const reference::ExtinctionField field(volumes, session->volumeTextures().frame(),
                                         session->volumeTextures().reconstruction());
  const render::GlobeMapping m = render::buildGlobeMapping(*prep.geo);
  const double R = volume::kEarthRadius_m, e = prep.frame.height_exaggeration;
  constexpr double kStep_m = 250.0, kReach_m = 400000.0;
  OcclusionTally tally;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
      const glm::dvec3 local = m.local_from_ecef * d;
      const double scale = glm::length(glm::dvec3(local.x, local.y, local.z / e));
      // As flat: the GPU may find the ground up to a quarter lattice cell (horizontally) late.
      const double lateBy = 0.25 * std::min(terrain.cell_m.x, terrain.cell_m.y) / glm::length(glm::dvec2(local));
      double tauFront = 0.0, tauLate = 0.0, tauBehind = 0.0, tHit = 0.0;
      bool hit = false;
      glm::dvec2 hitXy(0.0);
      for (double t = 0.0; t < kReach_m; t += kStep_m) {
        const glm::dvec3 p = cam.position_m + t * d;
        const glm::dvec2 w = render::worldXyFromTable(m, p);
        const double z = glm::length(p) - R;
        if (z < 0.0 || std::isnan(w.x)) break;  // the sphere, or outside the table: no cloud, no mountain
        if (!hit && z <= terrain.heightAt(w)) {
          hit = true;
          hitXy = w;
          tHit = t;
        }
        const double dtau = field.at({w, z}).total() * kStep_m * scale;
        (hit ? tauBehind : tauFront) += dtau;
        if (!hit || t <= tHit + lateBy) tauLate += dtau;
      }
      if (!hit || glm::length(hitXy - summitXy) > 2.0 * kMountainSigma_m) continue;  // the mountain itself
      if (tauFront + tauBehind < 2.0) continue;                                      // thick cloud behind it
      const double inFront = -std::expm1(-tauFront);
      const std::size_t o = (std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4 + 3;
      tally.add(with.rgba[o], without.rgba[o], inFront, -std::expm1(-tauLate));
    }
  }
  tally.check("globe", 0.02);  // the CPU's 250 m steps place the ground within a step of the GPU's bisection
}

}  // namespace
}  // namespace nph::test

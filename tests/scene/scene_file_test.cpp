// Scene files: the example parses to the documented values, defaults, strict errors naming the file
// and JSON path, camera presets that frame the volume, sun from the data's time.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "scene/scene_file.h"
#include "scene/solar_position.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

namespace fs = std::filesystem;

TEST(SceneFile, ExampleHurricaneParses) {
  const std::string dir = std::string(NEPHELE_SOURCE_DIR) + "/examples/scenes";
  const SceneDescription s = loadSceneFile(dir + "/hurricane.json");
  ASSERT_TRUE(s.data);
  EXPECT_EQ(fs::path(s.data->path), (fs::path(NEPHELE_SOURCE_DIR) / "out/hurricane-realistic.nph").lexically_normal());
  EXPECT_EQ(s.data->timestep, 0);
  EXPECT_EQ(s.camera.preset, CameraPreset::Oblique);
  EXPECT_EQ(s.camera.fov_deg, 40.0);
  EXPECT_TRUE(s.sun.from_time);
  EXPECT_EQ(s.sun.colour, glm::dvec3(1.0, 0.97, 0.92));
  ASSERT_TRUE(s.basemap);
  EXPECT_EQ(s.basemap->path, "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg");
  EXPECT_EQ(s.basemap->margin, 0.5);
  EXPECT_EQ(s.basemap->pixels_long_side, 4096);
  EXPECT_EQ(s.quality.preset, "broadcast");
  ASSERT_EQ(s.output.paths.size(), 2u);
  EXPECT_EQ(fs::path(s.output.paths[1]), (fs::path(NEPHELE_SOURCE_DIR) / "out/hurricane.exr").lexically_normal());
  EXPECT_EQ(s.output.width, 1920);
  EXPECT_EQ(s.output.height, 1080);
  EXPECT_EQ(s.output.image.tone_curve, ToneCurve::AcesFitted);
  EXPECT_TRUE(s.output.image.write_depth);
  EXPECT_EQ(s.height_exaggeration, 10.0);
  EXPECT_EQ(s.view, ViewMode::Flat);
}

TEST(SceneFile, Defaults) {
  const SceneDescription s = parseSceneText("{}", "empty.json");
  EXPECT_FALSE(s.data);
  EXPECT_FALSE(s.basemap);
  EXPECT_EQ(s.camera.preset, CameraPreset::Overview);
  EXPECT_FALSE(s.sun.from_time);
  EXPECT_EQ(s.sun.azimuth_deg, 135.0);
  EXPECT_EQ(s.quality.preset, "broadcast");
  EXPECT_EQ(s.quality.step_voxels, 0.5);
  EXPECT_TRUE(s.output.paths.empty());
  EXPECT_EQ(s.output.width, 1920);
  EXPECT_EQ(s.output.height, 1080);
  EXPECT_EQ(s.output.image.exposure_ev, kDefaultExposureEv);  // +2.5 EV since issue 12
  EXPECT_EQ(s.output.exposure, ExposureMode::Fixed);
  EXPECT_FALSE(s.output.image.write_depth);
  EXPECT_EQ(s.height_exaggeration, 1.0);
  EXPECT_EQ(s.view, ViewMode::Flat);
  EXPECT_EQ(s.lonlat_offset.lon_deg, 0.0);
  EXPECT_FALSE(s.centre_if_cartesian);
}

TEST(SceneFile, ValuesAndOverrides) {
  const SceneDescription s = parseSceneText(R"({
    // comments are allowed
    "data": {"path": "/data/storm.nph", "time_utc": "2026-09-01_18:00:00"},
    "camera": {"position_m": [1, 2, 3000], "target_m": [100, 200, 0], "up": [0, 0, 2], "fov_deg": 30},
    "sun": {"azimuth_deg": 250, "elevation_deg": 12.5, "intensity": 2},
    "basemap": null,
    "quality": {"preset": "draft", "overrides": {"step_voxels": 0.75, "shadows": false, "dlm_max_nodes": 12}},
    "output": {"paths": ["a.PNG"], "width": 640, "height": 360, "exposure_ev": -1.5, "tone_curve": "reinhard"},
    "view": "globe", "lonlat_offset_deg": [0.3, -0.1], "centre_lonlat_deg": [10, 50]
  })",
                                            "inline.json", "/scenes");
  EXPECT_EQ(*s.data->time_utc, "2026-09-01_18:00:00");
  EXPECT_FALSE(s.camera.preset);
  EXPECT_EQ(*s.camera.position_m, glm::dvec3(1, 2, 3000));
  EXPECT_EQ(s.camera.up, glm::dvec3(0, 0, 1));
  EXPECT_EQ(s.sun.azimuth_deg, 250.0);
  EXPECT_EQ(s.sun.elevation_deg, 12.5);
  EXPECT_FALSE(s.basemap);
  EXPECT_EQ(s.quality.preset, "draft");
  EXPECT_EQ(s.quality.step_voxels, 0.75);
  EXPECT_EQ(s.quality.dlm_step_voxels, 1.0);  // from the draft preset
  EXPECT_EQ(s.quality.dlm_epsilon, 0.04);     // from the draft preset
  EXPECT_EQ(s.quality.dlm_max_nodes, 12);
  EXPECT_FALSE(s.quality.shadows);
  EXPECT_EQ(s.output.paths[0], "/scenes/a.PNG");
  EXPECT_EQ(s.output.image.exposure_ev, -1.5);
  EXPECT_EQ(s.output.image.tone_curve, ToneCurve::Reinhard);
  EXPECT_EQ(s.output.exposure, ExposureMode::Fixed);
  // "exposure": "sun": exposure_ev holds at the 35° reference sun and the frame's sun adds to it.
  const SceneDescription sun = parseSceneText(R"({"output": {"exposure": "sun", "exposure_ev": 1}})", "s.json");
  EXPECT_EQ(sun.output.exposure, ExposureMode::Sun);
  EXPECT_EQ(imageOptionsFor(sun.output, kExposureReferenceSunElevationDeg).exposure_ev, 1.0);
  EXPECT_EQ(imageOptionsFor(sun.output, 5.0).exposure_ev, 1.0 + sunExposureOffsetEv(5.0));
  EXPECT_EQ(imageOptionsFor(s.output, 5.0).exposure_ev, -1.5);  // fixed: the sun changes nothing
  EXPECT_EQ(s.view, ViewMode::Globe);
  EXPECT_EQ(s.lonlat_offset.lon_deg, 0.3);
  EXPECT_EQ(s.lonlat_offset.lat_deg, -0.1);
  EXPECT_EQ(s.centre_if_cartesian->lat_deg, 50.0);
  EXPECT_EQ(parseSceneText(R"({"quality": "reference"})", "q.json").quality.dlm_step_voxels, 0.25);
  EXPECT_EQ(parseSceneText(R"({"quality": {"overrides": {"dlm_texel_voxels": 2}}})", "q.json").quality.dlm_texel_voxels,
            2.0);
}

TEST(SceneFile, StrictErrorsNameFileAndJsonPath) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"camera": {"fov_deg": "wide"}})", "scene.json: camera.fov_deg: expected a number, got a string"},
      {R"({"camra": {}})", "scene.json: camra: unknown key"},
      {R"({"camera": {"fvo_deg": 30}})", "scene.json: camera.fvo_deg: unknown key (expected one of: preset,"},
      {R"({"camera": {"preset": "closeup"}})", "scene.json: camera.preset: expected \"overview\""},
      {R"({"camera": {"position_m": [0, 0, 1]}})", "scene.json: camera.target_m: required"},
      {R"({"camera": {"preset": "top", "position_m": [0, 0, 1], "target_m": [0, 0, 0]}})",
       "camera.preset: give either"},
      {R"({"camera": {"preset": "oblique", "up": [0, 1, 0]}})", "camera.up: only used with position_m/target_m"},
      {R"({"camera": {"fov_deg": 200}})", "camera.fov_deg: expected a number in [1, 170], got 200"},
      {R"({"output": {"width": 1920.5}})", "scene.json: output.width: expected an integer, got 1920.5"},
      {R"({"output": {"height": 0}})", "output.height: expected an integer in [1, 16384], got 0"},
      {R"({"output": {"paths": ["frame.jpg"]}})", "scene.json: output.paths[0]: expected a .png or .exr file"},
      {R"({"output": {"paths": "a.png"}})", "output.paths: expected an array of file paths, got a string"},
      {R"({"output": {"depth": "yes"}})", "output.depth: expected true or false, got a string"},
      {R"({"output": {"tone_curve": "filmic"}})", "output.tone_curve: tone curve 'filmic'"},
      {R"({"output": {"exposure": "auto"}})",
       "scene.json: output.exposure: unknown exposure 'auto': expected \"fixed\""},
      {R"({"quality": "ultra"})", "scene.json: quality: quality preset 'ultra'"},
      {R"({"quality": {"preset": "draft", "overrides": {"step_voxel": 1}}})",
       "quality.overrides.step_voxel: unknown key"},
      {R"({"quality": 3})", "quality: expected an object, got a number"},
      {R"({"style": {"atmosfere": false}})", "scene.json: style.atmosfere: unknown key"},
      {R"({"style": {"g_ice": 2}})", "style.g_ice: expected a number in"},
      {R"({"style": {"step_voxels": 1}})", "style.step_voxels: unknown key"},
      {R"({"output": {"display": "Rec.2020"}})", "output.display: "},
      {R"({"output": {"view": "nephele"}})", "output.view: needs output.display"},
      {R"({"output": {"pass_files": {"albedo": "a.png"}}})", "output.pass_files.albedo: unknown pass 'albedo'"},
      {R"({"output": {"pass_files": {"depth": "z.png"}}})", "output.pass_files.depth: the depth pass holds distances"},
      {R"({"sun": {"from_time": true, "azimuth_deg": 10}})", "sun.azimuth_deg: not allowed with \"from_time\": true"},
      {R"({"sun": {"from_time": true, "time_utc": "noon"}})", "sun.time_utc: time 'noon'"},
      {R"({"sun": {"time_utc": "2026-09-01T12:00:00Z"}})", "sun.time_utc: only used with"},
      {R"({"sun": {"colour": [1, 1, "x"]}})", "sun.colour[2]: expected a number, got a string"},
      {R"({"view": "sphere"})", "scene.json: view: expected one of \"flat\", \"globe\", got \"sphere\""},
      {R"({"lonlat_offset_deg": [1]})", "lonlat_offset_deg: expected an array of 2 numbers, got 1 elements"},
      {R"({"data": {"timestep": 2}})", "scene.json: data.path: required"},
      {R"({"data": {"path": ""}})", "data.path: expected a file path, got an empty string"},
      {R"({"data": {"path": "a.nph", "timestep": 1, "time_utc": "2026-09-01T00:00:00Z"}})",
       "data.time_utc: give either"},
      {R"({"data": {"path": "a.nph", "timestep": -1}})", "data.timestep: expected an integer in [0,"},
      {R"({"basemap": {"margin": 0.1}})", "basemap.path: required"},
      {R"({"height_exaggeration": 0})", "height_exaggeration: expected a number in [0.01, 1000], got 0"},
      {R"([1, 2])", "scene.json: (top level): expected an object, got an array"},
      {R"({"camera": {)", "scene.json: not valid JSON"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      (void)parseSceneText(text, "scene.json");
      ADD_FAILURE() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
          << "input: " << text << "\nmessage: " << e.what() << "\nexpected: " << expected;
    }
  }
}

// The "style" object sets style knobs (lighting/knobs.h); absent, the style is StyleSettings{}.
// Output colour and passes keys land in OutputSpec.
TEST(SceneFile, StyleAndOutputPassesAndColour) {
  const SceneDescription s = parseSceneText(R"({"style": {"atmosphere": false, "g_ice": 0.7, "ambient_b": 1.2},
      "output": {"display": "Rec.2100-PQ", "passes": true, "pass_files": {"shadow": "m.png"}}})",
                                            "style.json");
  EXPECT_FALSE(s.style.atmosphere);
  EXPECT_EQ(s.style.g_ice, 0.7);
  EXPECT_EQ(s.style.ambient.z, 1.2);
  EXPECT_EQ(s.style.g_water, lighting::StyleSettings{}.g_water);
  EXPECT_EQ(s.output.image.display, "Rec.2100-PQ");
  EXPECT_TRUE(s.output.passes);
  ASSERT_EQ(s.output.pass_files.size(), 1u);
  EXPECT_EQ(s.output.pass_files[0].first, Pass::Shadow);
  EXPECT_TRUE(s.output.wantsPasses());
  const SceneDescription d = parseSceneText("{}", "empty.json");
  EXPECT_TRUE(d.style.atmosphere);
  EXPECT_FALSE(d.output.wantsPasses());
}

TEST(SceneFile, MissingFileIsAnInputErrorNamingIt) {
  nph::test::ScratchDir dir("scene");
  try {
    (void)loadSceneFile(dir.file("nope.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("nope.json")), std::string::npos) << e.what();
  }
  std::ofstream(dir.file("bad.json")) << R"({"output": {"width": "big"}})";
  try {
    (void)loadSceneFile(dir.file("bad.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("bad.json") + ": output.width: expected an integer"),
              std::string::npos)
        << e.what();
  }
}

/// Pixel position of a world point, or nullopt when it is behind the camera.
glm::dvec3 ndcOf(const Camera& cam, const glm::dvec3& p) {
  const glm::dvec4 clip = cam.clipFromView() * cam.viewFromWorld() * glm::dvec4(p, 1.0);
  return glm::dvec3(clip) / clip.w;
}

TEST(SceneFile, CameraPresetsFrameTheVolume) {
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v, 10.0);
  const glm::dvec3 lo = frame.min_m(), hi = frame.max_m();
  for (CameraPreset preset : {CameraPreset::Overview, CameraPreset::Oblique, CameraPreset::Top}) {
    CameraSpec spec;
    spec.preset = preset;
    const Camera cam = cameraFor(spec, frame, 1920, 1080);
    EXPECT_EQ(cam.width, 1920);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    EXPECT_NEAR(glm::length(cam.target_m - centre), 0.0, 1e-6);
    const glm::dvec3 d = cam.position_m - cam.target_m;
    const double elevation = glm::degrees(std::asin(d.z / glm::length(d)));
    int inside = 0;
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
      const glm::dvec3 ndc = ndcOf(cam, corner);
      ASSERT_GT(ndc.z, -1.0) << "corner behind the near plane";
      ASSERT_LT(ndc.z, 1.0) << "corner beyond the far plane";
      if (std::abs(ndc.x) <= 1.0 && std::abs(ndc.y) <= 1.0) ++inside;
    }
    switch (preset) {
      case CameraPreset::Overview:
        EXPECT_NEAR(elevation, 55.0, 1e-9);
        EXPECT_LT(cam.position_m.y, centre.y);  // from the south
        EXPECT_NEAR(cam.position_m.x, centre.x, 1e-6);
        EXPECT_EQ(inside, 8);
        break;
      case CameraPreset::Oblique:
        EXPECT_NEAR(elevation, 20.0, 1e-9);
        EXPECT_LT(cam.position_m.x, centre.x);  // south-south-west
        EXPECT_LT(cam.position_m.y, centre.y);
        EXPECT_GE(inside, 4);
        break;
      case CameraPreset::Top: {
        EXPECT_NEAR(elevation, 90.0, 1e-9);
        EXPECT_EQ(inside, 8);
        // North is up in the image: a point north of the centre lands in the upper half.
        const glm::dvec3 n = ndcOf(cam, centre + glm::dvec3(0.0, 1000.0, 0.0));
        EXPECT_GT(n.y, 0.0);
        EXPECT_NEAR(n.x, 0.0, 1e-9);
        // The ray through the image centre points straight down.
        const glm::dvec3 r = cam.rayDirection(960.0, 540.0);
        EXPECT_NEAR(r.z, -1.0, 1e-9);
        break;
      }
    }
  }
  // distance_scale moves the camera along the same line; explicit cameras pass through.
  CameraSpec closer;
  closer.distance_scale = 0.5;
  const Camera a = cameraFor(CameraSpec{}, frame, 1920, 1080), b = cameraFor(closer, frame, 1920, 1080);
  EXPECT_NEAR(glm::length(b.position_m - b.target_m), 0.5 * glm::length(a.position_m - a.target_m), 1e-6);
  CameraSpec expl;
  expl.preset.reset();
  expl.position_m = glm::dvec3(1, 2, 3);
  expl.target_m = glm::dvec3(4, 5, 6);
  expl.fov_deg = 25.0;
  const Camera e = cameraFor(expl, frame, 640, 480);
  EXPECT_EQ(e.position_m, glm::dvec3(1, 2, 3));
  EXPECT_EQ(e.vertical_fov_deg, 25.0);
  EXPECT_EQ(e.height, 480);
}

TEST(SceneFile, SunFromTheDataTime) {
  const auto v = test::lambertVolumes(400, 100, 4, 3000.0);
  const volume::VolumeFrame frame = volume::frameOf(v);
  SunSpec spec;
  spec.from_time = true;
  spec.colour = {1.0, 0.9, 0.8};
  // Centre of the domain: lon −80 (the central meridian, so grid north = true north), lat 25.
  const SceneGeoreference geo(v, frame);
  const Sun s = sunFor(spec, &geo, UtcTime::parse("2026-09-01_17:00:00"));
  const SolarPosition p = solarPosition(UtcTime::parse("2026-09-01T17:00:00Z"), -80.0, 25.0);
  EXPECT_NEAR(s.azimuth_deg, p.azimuth_deg, 1e-6);
  EXPECT_NEAR(s.elevation_deg, p.elevation_deg, 1e-9);
  EXPECT_EQ(s.colour, glm::dvec3(1.0, 0.9, 0.8));
  EXPECT_GT(s.elevation_deg, 60.0);  // early afternoon sun high over Florida in September
  // The manual offset moves the domain 20° east: the same instant is later in the local day.
  const SceneGeoreference east(v, frame, LonLatOffset{20.0, 0.0});
  const Sun later = sunFor(spec, &east, UtcTime::parse("2026-09-01_17:00:00"));
  EXPECT_NEAR(later.elevation_deg, solarPosition(UtcTime::parse("2026-09-01T17:00:00Z"), -60.0, 25.0).elevation_deg,
              1e-9);
  // time_utc overrides the data's time.
  spec.time_utc = "2026-09-01T12:00:00Z";
  const double morning = sunFor(spec, &geo, UtcTime::parse("2026-09-01_17:00:00")).elevation_deg;  // 07:00 local
  EXPECT_GT(morning, 5.0);
  EXPECT_LT(morning, 20.0);
  // Explicit suns pass through; from_time without a time or place is an error.
  SunSpec fixed;
  fixed.azimuth_deg = 200.0;
  EXPECT_EQ(sunFor(fixed, nullptr, std::nullopt).azimuth_deg, 200.0);
  spec.time_utc.reset();
  EXPECT_THROW(sunFor(spec, &geo, std::nullopt), InputError);
  EXPECT_THROW(sunFor(spec, nullptr, UtcTime::parse("2026-09-01T12:00:00Z")), InputError);
}

}  // namespace
}  // namespace nph::scene

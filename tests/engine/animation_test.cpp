// Animation without GL: exact frame rates, the camera spline, the scene file's animation section,
// the per-frame clock and sun of AnimationPlan, and the timestep blend at fractional time.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "core/error.h"
#include "engine/animation.h"
#include "engine/dataset.h"
#include "engine_test_support.h"
#include "scene/animation_spec.h"
#include "scene/scene_setup.h"

namespace nph::test {
namespace {

using scene::FrameRate;

TEST(FrameRate, BroadcastRatesAreExactRationals) {
  EXPECT_EQ(FrameRate::parse("25").text(), "25");
  EXPECT_EQ(FrameRate::parse("50").text(), "50");
  EXPECT_EQ(FrameRate::parse("59.94").text(), "60000/1001");
  EXPECT_EQ(FrameRate::parse("29.97").text(), "30000/1001");
  EXPECT_EQ(FrameRate::parse("23.976").text(), "24000/1001");
  EXPECT_EQ(FrameRate::parse("60000/1001").text(), "60000/1001");
  EXPECT_EQ(FrameRate::parse("12.5").text(), "25/2");
  // Frame 60000 of 59.94 lies at 1001 s exactly: no drift over a long sequence.
  EXPECT_EQ(FrameRate::parse("59.94").secondsAt(60000), 1001.0);
  for (const char* bad : {"", "abc", "0", "-25", "1/0", "25fps", "60000/", "1e9"}) {
    EXPECT_THROW(FrameRate::parse(bad), InputError) << bad;
  }
}

TEST(CatmullRom, PassesThroughTheKeysAndIsSmoothBetweenThem) {
  const std::vector<double> t{0.0, 1.0, 3.0, 4.0};
  const std::vector<double> v{0.0, 2.0, 1.0, 5.0};
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_DOUBLE_EQ(engine::catmullRom(t, v, t[i]), v[i]);
  EXPECT_DOUBLE_EQ(engine::catmullRom(t, v, -1.0), 0.0);  // held before the first key
  EXPECT_DOUBLE_EQ(engine::catmullRom(t, v, 9.0), 5.0);   // and after the last
  // C¹ at the inner keys: one-sided slopes agree.
  for (double k : {1.0, 3.0}) {
    const double h = 1e-6;
    const double left = (engine::catmullRom(t, v, k) - engine::catmullRom(t, v, k - h)) / h;
    const double right = (engine::catmullRom(t, v, k + h) - engine::catmullRom(t, v, k)) / h;
    EXPECT_NEAR(left, right, 1e-4) << "at " << k;
  }
  // Two keys: a straight line at constant speed.
  EXPECT_DOUBLE_EQ(engine::catmullRom<double>({0.0, 2.0}, {1.0, 5.0}, 0.5), 2.0);
}

scene::SceneDescription sceneWith(const std::string& animation) {
  return scene::parseSceneText(R"({ "data": { "path": ")" + tinyStormFile() +
                                   R"(" }, "sun": { "from_time": true }, "output": { "width": 64, "height": 36 },
                                   "animation": )" +
                                   animation + "}",
                               "anim.json");
}

TEST(AnimationSection, IsParsedStrictly) {
  const auto a = scene::parseAnimation(sceneWith(
      R"({ "from": 0, "to": "2026-09-01T14:00:00Z", "fps": "59.94", "duration_s": 2, "interpolation": "step",
           "sun_step_s": 60, "camera_keyframes": [ { "at_s": 0, "preset": "top" }, { "at_s": 1.5, "position_m": [0, 0, 9000], "target_m": [1, 1, 0] } ] })"));
  EXPECT_EQ(*a.from.index, 0.0);
  EXPECT_EQ(*a.to.utc, "2026-09-01T14:00:00Z");
  EXPECT_EQ(a.fps.text(), "60000/1001");
  EXPECT_EQ(a.interpolation, scene::TimeInterpolation::Step);
  EXPECT_EQ(scene::parseAnimation(sceneWith(R"({ "fps": 25 })")).interpolation, scene::TimeInterpolation::Motion);
  EXPECT_EQ(scene::parseAnimation(sceneWith(R"({ "interpolation": "linear" })")).interpolation,
            scene::TimeInterpolation::Linear);
  EXPECT_EQ(scene::parseAnimation(sceneWith(R"({ "interpolation": "motion" })")).interpolation,
            scene::TimeInterpolation::Motion);
  // One name table for scene files and `nephele animate --interpolation`, one mapping to the
  // Session's blend.
  for (const auto& [name, value] : scene::kTimeInterpolationNames) {
    EXPECT_EQ(scene::timeInterpolationNamed(name), value);
    EXPECT_EQ(scene::parseAnimation(sceneWith(fmt::format(R"({{ "interpolation": "{}" }})", name))).interpolation,
              value);
    EXPECT_EQ(engine::timeBlendFor(value),
              value == scene::TimeInterpolation::Motion ? engine::TimeBlend::Motion : engine::TimeBlend::Linear);
  }
  EXPECT_THROW((void)scene::timeInterpolationNamed("cubic"), UsageError);
  ASSERT_EQ(a.keyframes.size(), 2u);
  EXPECT_EQ(a.keyframes[1].at_s, 1.5);
  const auto fails = [](const std::string& section, const std::string& expected) {
    try {
      (void)scene::parseAnimation(sceneWith(section));
      ADD_FAILURE() << "no error for " << section;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  fails(R"({ "fpss": 25 })", "anim.json: animation.fpss: unknown key");
  fails(R"({ "fps": "fast" })", "animation.fps");
  fails(R"({ "interpolation": "smooth" })", "animation.interpolation");
  fails(R"({ "duration_s": 2, "speed": 60 })", "animation.speed: give either");
  fails(R"({ "to": "yesterday" })", "animation.to");
  fails(R"({ "camera_keyframes": [ { "at_s": 1 }, { "at_s": 0.5 } ] })", "animation.camera_keyframes[1].at_s");
  fails(R"({ "camera_keyframes": [ { "at_s": 0, "fov": 30 } ] })", "animation.camera_keyframes[0].fov: unknown key");
  EXPECT_THROW((void)scene::parseSceneText(R"({ "animation": 3 })", "x.json"), InputError);
}

TEST(AnimationSection, KeyframesFromAFileRelativeToTheScene) {
  const auto dir = engineTestDir() / "keys";
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "orbit.json") << R"({ "keyframes": [ { "at_s": 0, "preset": "oblique" },
                                                           { "at_s": 2, "preset": "top", "fov_deg": 30 } ] })";
    std::ofstream(dir / "bad.json") << R"({ "keyframes": [ { "at_s": 0, "preset": "sideways" } ] })";
  }
  const auto s =
      scene::parseSceneText(R"({ "animation": { "keyframes_file": "orbit.json" } })", "anim.json", dir.string());
  const auto a = scene::parseAnimation(s);
  ASSERT_EQ(a.keyframes.size(), 2u);
  EXPECT_EQ(a.keyframes[1].camera.fov_deg, 30.0);
  EXPECT_EQ(a.keyframes_file, (dir / "orbit.json").string());
  try {
    (void)scene::loadCameraKeyframes((dir / "bad.json").string());
    ADD_FAILURE() << "no error for a bad preset";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: keyframes[0].preset"), std::string::npos) << e.what();
  }
}

struct PlanFixture : ::testing::Test {
  std::shared_ptr<const engine::Dataset> ds = engine::Dataset::open(tinyStormFile());
  ExtinctionVolumes v0 = ds->load(0);
  scene::SceneDescription scene = sceneWith("{}");
  scene::PreparedScene prepared = scene::prepareScene(scene, v0);

  engine::AnimationPlan plan(const std::string& animation) {
    scene = sceneWith(animation);
    return engine::AnimationPlan(scene::parseAnimation(scene), *ds, scene, prepared);
  }
};

TEST_F(PlanFixture, FramesRunOverTheTimeRangeInclusiveAndDependOnlyOnTheirNumber) {
  const auto p = plan(R"({ "from": 0, "to": 2, "fps": 25, "duration_s": 2 })");
  ASSERT_EQ(p.frameCount(), 51);
  EXPECT_EQ(p.frame(0).time_index, 0.0);
  EXPECT_NEAR(p.frame(25).time_index, 1.0, 1e-9);
  EXPECT_EQ(p.frame(25).utc->iso8601(), "2026-09-01T13:00:00Z");
  EXPECT_NEAR(p.frame(50).time_index, 2.0, 1e-9);
  EXPECT_NEAR(p.frame(10).time_index, 0.4, 1e-9);
  // Frame k is a function of k: asking out of order changes nothing.
  const auto late = p.frame(37);
  (void)p.frame(3);
  EXPECT_EQ(p.frame(37).time_index, late.time_index);
  EXPECT_EQ(p.frame(37).sun.azimuth_deg, late.sun.azimuth_deg);
  EXPECT_THROW((void)p.frame(51), UsageError);
}

TEST_F(PlanFixture, UtcRangeAndSpeed) {
  // 12:30 to 13:30 at 1800 model seconds per video second: 2 s of video.
  const auto p = plan(R"({ "from": "2026-09-01T12:30:00Z", "to": "2026-09-01T13:30:00Z", "fps": 50, "speed": 1800 })");
  EXPECT_NEAR(p.durationSeconds(), 2.0, 1e-6);
  EXPECT_EQ(p.frameCount(), 101);
  EXPECT_NEAR(p.frame(0).time_index, 0.5, 1e-9);
  EXPECT_NEAR(p.frame(100).time_index, 1.5, 1e-6);
  EXPECT_THROW(plan(R"({ "from": "2026-09-01T10:00:00Z" })"), InputError);  // before the data
  EXPECT_THROW(plan(R"({ "from": 0, "to": 7 })"), InputError);              // past the last timestep
}

TEST_F(PlanFixture, StepInterpolationHoldsEachTimestep) {
  const auto p = plan(R"({ "fps": 10, "duration_s": 2, "interpolation": "step" })");
  EXPECT_EQ(p.frame(0).time_index, 0.0);
  EXPECT_EQ(p.frame(9).time_index, 0.0);
  EXPECT_EQ(p.frame(10).time_index, 1.0);
  EXPECT_EQ(p.frame(20).time_index, 2.0);
}

TEST_F(PlanFixture, TheSunFollowsTheClockOnItsOwnSteps) {
  const auto p = plan(R"({ "fps": 25, "duration_s": 2, "sun_step_s": 3600 })");
  ASSERT_TRUE(p.sunFollowsClock());
  EXPECT_EQ(p.frame(1).sun.azimuth_deg, p.frame(0).sun.azimuth_deg);  // same hour: same sun
  EXPECT_EQ(p.frame(24).sun.elevation_deg, p.frame(0).sun.elevation_deg);
  EXPECT_NE(p.frame(25).sun.elevation_deg, p.frame(0).sun.elevation_deg);
  // Hourly steps of the sun: the sun at 13:00 is the scene's sun for the 13:00 timestep.
  scene::SunSpec at13 = scene.sun;
  at13.time_utc = "2026-09-01T13:00:00Z";
  EXPECT_NEAR(p.frame(25).sun.elevation_deg, scene::sunFor(at13, &*prepared.geo, std::nullopt).elevation_deg, 1e-9);
  const auto fixed = plan(R"({ "fps": 25, "duration_s": 2, "sun_follows_clock": false })");
  EXPECT_EQ(fixed.frame(50).sun.elevation_deg, prepared.sun.elevation_deg);
}

TEST_F(PlanFixture, CameraKeyframesAreHitExactly) {
  const auto p = plan(R"({ "fps": 25, "duration_s": 2, "camera_keyframes": [
      { "at_s": 0, "preset": "oblique" }, { "at_s": 1, "position_m": [1000, 2000, 30000], "target_m": [300000, 250000, 0], "fov_deg": 30 },
      { "at_s": 2, "preset": "top" } ] })");
  const auto mid = p.frame(25).camera;
  EXPECT_NEAR(mid.position_m.z, 30000.0, 1e-6);
  EXPECT_NEAR(mid.target_m.x, 300000.0, 1e-6);
  EXPECT_NEAR(mid.vertical_fov_deg, 30.0, 1e-9);
  const auto first = p.frame(0).camera;
  scene::CameraSpec spec;
  spec.preset = scene::CameraPreset::Oblique;
  const scene::Camera oblique = scene::cameraFor(spec, prepared.frame, 64, 36);
  EXPECT_NEAR(glm::length(first.position_m - oblique.position_m), 0.0, 1e-6);
  EXPECT_EQ(first.width, 64);
}

TEST(Blend, HalfwayIsTheMeanOfTwoRealTimesteps) {
  const auto ds = engine::Dataset::open(tinyStormFile());
  const ExtinctionVolumes a = ds->load(0), b = ds->load(1);
  const ExtinctionVolumes m = engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Linear);
  ASSERT_EQ(m.nz, std::max(a.nz, b.nz));
  const std::size_t layer = std::size_t(a.nx) * std::size_t(a.ny);
  std::size_t differing = 0;
  for (std::size_t i = 0; i < m.ice_per_m.size(); ++i) {
    const float ai = i < layer * std::size_t(a.nz) ? a.ice_per_m[i] : 0.0f;
    const float bi = i < layer * std::size_t(b.nz) ? b.ice_per_m[i] : 0.0f;
    const float aw = i < layer * std::size_t(a.nz) ? a.water_per_m[i] : 0.0f;
    const float bw = i < layer * std::size_t(b.nz) ? b.water_per_m[i] : 0.0f;
    ASSERT_EQ(m.ice_per_m[i], 0.5f * ai + 0.5f * bi) << i;
    ASSERT_EQ(m.water_per_m[i], 0.5f * aw + 0.5f * bw) << i;
    differing += ai != bi ? 1 : 0;
  }
  EXPECT_GT(differing, m.ice_per_m.size() / 10) << "the storm must change between timesteps";
  EXPECT_EQ(engine::blendVolumes(a, b, 0.0, engine::TimeBlend::Linear).ice_per_m, a.ice_per_m);
  EXPECT_EQ(engine::blendVolumes(a, b, 1.0, engine::TimeBlend::Linear).water_per_m, b.water_per_m);
}

TEST(Blend, ARisingCloudTopIsBlendedOnTheUnionOfTheColumns) {
  // Issue 18: each timestep converted on the fly is cropped to its own column, so a series whose
  // ice tops rise gives timesteps of different heights; blending must not refuse them.
  const std::string path = (engineTestDir() / "wrfout_rising.nc").string();
  datagen::WrfHurricaneSpec spec;
  spec.ntimes = 3;
  spec.anvil_rise_km_per_h = 2.0;
  datagen::writeWrfHurricane(spec, path);
  const auto ds = engine::Dataset::open(path);
  const ExtinctionVolumes a = ds->load(0), c = ds->load(2);
  ASSERT_EQ(a.dz_m, c.dz_m);
  EXPECT_GT(c.z_bottom_m + c.dz_m * c.nz, a.z_bottom_m + a.dz_m * a.nz + 1000.0)
      << "the column of timestep 2 must reach at least 1 km higher than timestep 0's";
  const ExtinctionVolumes m = engine::blendVolumes(a, c, 0.25, engine::TimeBlend::Linear);
  EXPECT_EQ(m.z_bottom_m, std::min(a.z_bottom_m, c.z_bottom_m));
  EXPECT_DOUBLE_EQ(m.z_bottom_m + m.dz_m * m.nz, std::max(a.z_bottom_m + a.dz_m * a.nz, c.z_bottom_m + c.dz_m * c.nz));
  // The optical depth of every column is the blend of the two timesteps' (zeros above a's top).
  const auto column = [](const ExtinctionVolumes& v, int i, int j) {
    double tau = 0.0;
    for (int k = 0; k < v.nz; ++k) {
      const std::size_t n = (std::size_t(k) * std::size_t(v.ny) + std::size_t(j)) * std::size_t(v.nx) + std::size_t(i);
      tau += (double(v.ice_per_m[n]) + double(v.water_per_m[n])) * v.dz_m;
    }
    return tau;
  };
  double worst = 0.0;
  for (int j = 0; j < a.ny; ++j) {
    for (int i = 0; i < a.nx; ++i) {
      const double want = 0.75 * column(a, i, j) + 0.25 * column(c, i, j);
      worst = std::max(worst, std::abs(column(m, i, j) - want) / (1.0 + want));
    }
  }
  EXPECT_LT(worst, 1e-5);
}

}  // namespace
}  // namespace nph::test

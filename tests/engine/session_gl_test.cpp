// Session on GL (label gl): a frame at fractional time is the frame of the CPU-blended volume,
// and neither prefetch nor reused volumes and deep light maps change a single byte of a frame.
#include <gtest/gtest.h>

#include <memory>

#include "engine/session.h"
#include "engine_test_support.h"
#include "scene/scene_file.h"
#include "support/gl_fixture.h"
#include "volume/detail.h"

namespace nph::test {
namespace {

using SessionTest = GlTest;

/// An explicit camera and sun (they must not depend on which volume the scene was prepared with).
scene::SceneDescription tinyScene() {
  return scene::parseSceneText(R"({ "data": { "path": ")" + tinyStormFile() + R"(" },
      "camera": { "position_m": [-150000, -250000, 250000], "target_m": [300000, 270000, 5000], "fov_deg": 45 },
      "sun": { "azimuth_deg": 140, "elevation_deg": 35 }, "quality": "draft",
      "output": { "width": 96, "height": 54 }, "height_exaggeration": 8 })",
                               "tiny.json");
}

void expectSameImage(const scene::RgbaImage& a, const scene::RgbaImage& b, const char* what) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) differ += a.rgba[i] != b.rgba[i] ? 1 : 0;
  EXPECT_EQ(differ, 0u) << what << ": " << differ << " of " << a.rgba.size() << " values differ";
}

double meanAlpha(const scene::RgbaImage& img) {
  double sum = 0.0;
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) sum += double(img.rgba[i]);
  return sum / double(img.rgba.size() / 4);
}

// Without U, V the motion blend is the linear one bit for bit (blendHasMotion), so the key does not
// tell them apart: switching the setting re-blends and re-lights nothing.
TEST_F(SessionTest, SwitchingTheBlendOnDataWithoutWindKeepsTheVolume) {
  const auto ds = engine::Dataset::open(tinyStormFile());
  std::vector<ExtinctionVolumes> still{ds->load(0), ds->load(1)};
  std::vector<std::string> times;
  for (ExtinctionVolumes& v : still) {
    v.wind_u_m_per_s.clear();
    v.wind_v_m_per_s.clear();
    times.push_back(nph::geo::isoOrEmpty(v.time_utc));
  }
  ASSERT_FALSE(engine::blendHasMotion(still[0], still[1]));
  engine::Session session(std::make_shared<ScriptedDataset>(still, times), tinyScene());
  session.setTimeBlend(engine::TimeBlend::Motion);
  session.setTime(0.5);
  const auto motion = session.render(session.prepared().camera);
  EXPECT_TRUE(session.stats().volume_changed);
  session.setTimeBlend(engine::TimeBlend::Linear);
  const auto linear = session.render(session.prepared().camera);
  EXPECT_FALSE(session.stats().volume_changed) << "one volume: nothing to re-blend";
  EXPECT_FALSE(session.stats().dlm_rebuilt) << "one volume: nothing to re-light";
  EXPECT_EQ(motion.cloud_layer.rgba, linear.cloud_layer.rgba);
  session.setTime(0.25);  // a new weight of the same pair: the blend is learnt, the key still plain
  (void)session.render(session.prepared().camera);
  EXPECT_TRUE(session.stats().volume_changed);
  session.setTimeBlend(engine::TimeBlend::Motion);
  (void)session.render(session.prepared().camera);
  EXPECT_FALSE(session.stats().volume_changed);
}

TEST_F(SessionTest, HalfwayFrameIsTheFrameOfTheCpuBlendedVolume) {
  const auto ds = engine::Dataset::open(tinyStormFile());
  ASSERT_TRUE(engine::blendHasMotion(ds->load(0), ds->load(1))) << "the storm carries U, V and times";
  const scene::SceneDescription s = tinyScene();
  engine::Session session(ds, s);
  EXPECT_EQ(session.timeBlend(), engine::kDefaultTimeBlend);
  std::vector<float> previous;
  for (const engine::TimeBlend blend : {engine::TimeBlend::Motion, engine::TimeBlend::Linear}) {
    SCOPED_TRACE(engine::kTimeBlendNames[std::size_t(blend)]);
    session.setTimeBlend(blend);
    session.setTime(0.5);
    const auto halfway = session.render(session.prepared().camera);
    EXPECT_TRUE(session.stats().volume_changed) << "the blend is part of the volume's key";

    const ExtinctionVolumes blended = engine::blendVolumes(ds->load(0), ds->load(1), 0.5, blend);
    auto one = std::make_shared<ScriptedDataset>(std::vector<ExtinctionVolumes>{blended},
                                                 std::vector<std::string>{nph::geo::isoOrEmpty(blended.time_utc)});
    engine::Session reference(one, s);
    const auto expected = reference.render(reference.prepared().camera);
    EXPECT_GT(meanAlpha(expected.cloud_layer), 0.01) << "the storm must be in view";
    expectSameImage(halfway.cloud_layer, expected.cloud_layer, "cloud layer");
    expectSameImage(halfway.frame, expected.frame, "frame");
    EXPECT_NE(halfway.cloud_layer.rgba, previous) << "motion and linear blends differ on a moving storm";
    previous = halfway.cloud_layer.rgba;
  }
  const auto halfway = session.render(session.prepared().camera);

  // And it lies between the two timesteps: not the frame of either.
  session.setTime(0.0);
  const auto at0 = session.render(session.prepared().camera);
  session.setTime(1.0);
  const auto at1 = session.render(session.prepared().camera);
  EXPECT_NE(at0.cloud_layer.rgba, halfway.cloud_layer.rgba);
  EXPECT_NE(at1.cloud_layer.rgba, halfway.cloud_layer.rgba);
}

TEST_F(SessionTest, ReusedVolumeAndLightMapGiveTheSameFrame) {
  const auto ds = engine::Dataset::open(tinyStormFile());
  engine::Session session(ds, tinyScene());
  session.setTime(1.25);
  const auto first = session.render(session.prepared().camera);
  session.setTime(1.25);
  const auto again = session.render(session.prepared().camera);
  EXPECT_FALSE(session.stats().volume_changed);
  EXPECT_FALSE(session.stats().dlm_rebuilt);
  EXPECT_EQ(session.stats().dlm_reuses, 1u);
  expectSameImage(first.frame, again.frame, "reused");

  engine::Session fresh(ds, tinyScene());  // straight to 1.25, nothing to reuse
  fresh.setTime(1.25);
  expectSameImage(first.frame, fresh.render(fresh.prepared().camera).frame, "fresh session");
}

TEST_F(SessionTest, PrefetchOnAndOffGiveIdenticalFrames) {
  const auto ds = engine::Dataset::open(tinyStormFile());
  engine::Session on(ds, tinyScene()), off(ds, tinyScene());
  engine::PrefetchSettings no;
  no.enabled = false;
  off.setPrefetch(no);
  on.setPlaybackDirection(+1);
  for (const double t : {0.0, 0.4, 0.8, 1.2, 1.6, 2.0}) {
    on.setTime(t);
    off.setTime(t);
    expectSameImage(on.render(on.prepared().camera).frame, off.render(off.prepared().camera).frame, "prefetch");
  }
  EXPECT_GT(on.prefetchStats().prefetched, 0u);
  EXPECT_EQ(off.prefetchStats().prefetched, 0u);
  EXPECT_EQ(on.prefetchStats().misses, 1u) << "after the first timestep, the worker decoded every one ahead of time";
}

// The default filter "auto" (issue 13; lighting/knobs.h kCubicFromSpacing_m) is resolved from the
// data's grid when the session uploads a volume: the 15 km tiny storm renders exactly as with an
// explicit "cubic", the same domain written at 3 km exactly as with "trilinear", and the CPU
// references' filter (renderSettings) follows the upload.
TEST_F(SessionTest, AutoReconstructionIsTheFilterOfTheGrid) {
  auto withFilter = [](const std::string& file, const char* filter) {
    return scene::parseSceneText(R"({ "data": { "path": ")" + file + R"(" },
      "camera": { "position_m": [-150000, -250000, 250000], "target_m": [300000, 270000, 5000], "fov_deg": 45 },
      "sun": { "azimuth_deg": 140, "elevation_deg": 35 },
      "quality": { "preset": "draft", "overrides": { "reconstruction": ")" +
                                     std::string(filter) + R"(" } },
      "output": { "width": 96, "height": 54 }, "height_exaggeration": 8 })",
                                 "auto.json");
  };
  const std::string fine = (engineTestDir() / "wrfout_tiny_3km.nc").string();
  datagen::WrfHurricaneSpec spec;  // the tiny storm's 600 × 540 km domain at 3 km
  spec.nx = 200;
  spec.ny = 180;
  spec.ntimes = 1;
  spec.dx_m = 3000.0;
  datagen::writeWrfHurricane(spec, fine);
  for (const auto& [file, expected] : {std::pair{tinyStormFile(), volume::Reconstruction::Cubic},
                                       std::pair{fine, volume::Reconstruction::Trilinear}}) {
    SCOPED_TRACE(file);
    const auto ds = engine::Dataset::open(file);
    engine::Session automatic(ds, withFilter(file, "auto")), cubic(ds, withFilter(file, "cubic")),
        trilinear(ds, withFilter(file, "trilinear"));
    const auto a = automatic.render(automatic.prepared().camera);
    EXPECT_EQ(automatic.renderSettings().reconstruction, expected);
    EXPECT_GT(meanAlpha(a.cloud_layer), 0.01) << "the storm must be in view";
    const auto c = cubic.render(cubic.prepared().camera), t = trilinear.render(trilinear.prepared().camera);
    EXPECT_NE(c.frame.rgba, t.frame.rgba) << "the two filters must differ for the test to mean anything";
    expectSameImage(a.frame, expected == volume::Reconstruction::Cubic ? c.frame : t.frame, "auto");
  }
}

// Memory (issue 19, docs/benchmarks.md "Memory"): a one-shot session (`nephele render`,
// setReleaseAfterUpload) of a .nph cache prepares the scene from the file's index and uploads the
// timestep from its 16-bit codes a layer at a time, never decoding the float volume; a blended
// time still goes through the decoded cache. Every frame is the frame of the session that keeps
// the decoded volumes, bit for bit.
TEST_F(SessionTest, ReleaseAfterUploadReadsTheCacheByLayerForTheSameFrame) {
  // The tiny storm's first two timesteps as a .nph cache.
  const auto model = engine::Dataset::open(tinyStormFile());
  const std::string file = (engineTestDir() / "session-release.nph").string();
  writeNphOf(file, {model->load(0), model->load(1)});
  const auto ds = engine::Dataset::open(file);
  ASSERT_TRUE(ds->loadHeader(0).has_value()) << "a .nph cache gives its header from the index";
  // With the sub-grid detail on, the noise is advected by the file's wind (volume/detail.h
  // DetailFlow): the one-shot route must read the wind too (it decodes the whole timestep then).
  ASSERT_TRUE(engine::blendHasMotion(ds->load(0), ds->load(1))) << "the cache keeps U, V";
  for (const int detail : {int(volume::Detail::None), int(volume::Detail::Full)}) {
    SCOPED_TRACE(volume::kDetailNames[std::size_t(detail)]);
    scene::SceneDescription s = tinyScene();
    s.data->path = file;
    s.quality.detail = detail;
    engine::Session keeping(ds, s), releasing(ds, s);
    releasing.setReleaseAfterUpload(true);
    for (const double t : {1.0, 0.5, 0.0}) {
      keeping.setTime(t);
      releasing.setTime(t);
      const auto a = keeping.render(keeping.prepared().camera);
      const auto b = releasing.render(releasing.prepared().camera);
      EXPECT_TRUE(releasing.stats().volume_changed);
      EXPECT_EQ(releasing.volumeTextures().identity(), keeping.volumeTextures().identity());
      EXPECT_GT(meanAlpha(a.cloud_layer), 0.01) << "the storm must be in view";
      expectSameImage(b.cloud_layer, a.cloud_layer, "cloud layer");
      expectSameImage(b.frame, a.frame, "frame");
      EXPECT_EQ(releasing.prefetchStats().bytes, 0u) << "nothing decoded is kept after the upload";
    }
  }
}

}  // namespace
}  // namespace nph::test

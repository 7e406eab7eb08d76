// The quick look's framing (engine/quick_look.h): the oblique preset closed in on the cloud's reach
// from the domain's centre, and the height exaggeration following the framed width.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/quick_look.h"

namespace nph::test {
namespace {

// A 100 × 100 × 20 domain at 3 km (300 km), 500 m layers, with one cloudy column block.
ExtinctionVolumes domainWithCloud(int i0, int i1, int j0, int j1) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(100, 100, 20, 3000.0, 500.0, 0.0);
  for (int k = 2; k < 10; ++k)  // cloud top 5 km
    for (int j = j0; j < j1; ++j)
      for (int i = i0; i < i1; ++i) v.water_per_m[v.index(i, j, k)] = 0.01f;
  v.updateMaxima();
  return v;
}

nlohmann::json sceneOf(const ExtinctionVolumes& v) {
  return nlohmann::json::parse(engine::quickLookSceneText({"", {"x.png"}, 160, 90, "test"}, v));
}

TEST(QuickLook, ClosesInOnACloudInTheMiddleOfItsDomain) {
  // Columns 40–59: the farthest cloudy corner is 10·√2 columns from the centre, the half diagonal
  // 50·√2, so the reach is 0.2 — below the floor, 0.35.
  const nlohmann::json s = sceneOf(domainWithCloud(40, 60, 40, 60));
  EXPECT_EQ(s["camera"]["preset"], "oblique");
  EXPECT_DOUBLE_EQ(s["camera"]["distance_scale"].get<double>(), 0.35);
  // Exaggeration for the framed width: round(0.35·300 km / (12·5 km)) = 2 (the whole domain: 5).
  EXPECT_DOUBLE_EQ(s["height_exaggeration"].get<double>(), 2.0);
  // Reach (30² + 30²)^½ / (50·√2) = 0.6: rounded up to 0.6.
  EXPECT_DOUBLE_EQ(sceneOf(domainWithCloud(20, 80, 20, 80))["camera"]["distance_scale"].get<double>(), 0.6);
}

TEST(QuickLook, FramesTheWholeDomainWhenTheCloudReachesItsCorners) {
  for (const auto& v : {domainWithCloud(0, 3, 0, 3), ExtinctionVolumes::zeros(100, 100, 20, 3000.0, 500.0, 0.0)}) {
    const nlohmann::json s = sceneOf(v);  // a corner column, or clear air: the domain as before
    EXPECT_FALSE(s["camera"].contains("distance_scale")) << s.dump();
  }
  EXPECT_DOUBLE_EQ(sceneOf(domainWithCloud(0, 3, 0, 3))["height_exaggeration"].get<double>(), 5.0);
}

}  // namespace
}  // namespace nph::test

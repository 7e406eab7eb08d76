// The eye pass's speed-ups of issue 19 ("Frame time") change no bit: the programs specialised per
// view at compile time (SPEC_* defines, render/raycast/cloud_renderer.h EyePassFeatures) and the
// DLM look-up by linear scan (glsl/dlm/lookup.glsl) against the baseline they replaced — one
// program whose switches are uniforms, the binary search — on views that turn every switch both
// ways: flat with terrain, atmosphere, passes, sub-grid detail and cubic reconstruction all on,
// then all off; the globe with terrain, atmosphere and passes, then without. Every channel of the cloud
// layer, the frame and the passes must be equal bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "render_scenes.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

using EyePassVariants = GlTest;

struct Variant {
  const char* name;
  const char* view;
  bool on;  // every optional feature on, or every one off
};

// Index of the first float whose bits differ, or -1. On a GPU (softwareRasteriser false) each
// program is compiled on its own and may contract a·b + c into an FMA differently: the H200 moved
// single values by 6·10⁻⁸ relative, so there two floats count as equal within 10⁻⁶ relative.
long firstDifference(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return 0;
  const bool exact = softwareRasteriser();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::bit_cast<std::uint32_t>(a[i]) == std::bit_cast<std::uint32_t>(b[i])) continue;
    if (exact || !(std::abs(a[i] - b[i]) <= 1e-6f * std::max(std::abs(a[i]), std::abs(b[i])))) return long(i);
  }
  return -1;
}

void expectSameBits(const render::RenderOutput& fast, const render::RenderOutput& base, const std::string& what) {
  struct Channel {
    const char* name;
    const std::vector<float>* a;
    const std::vector<float>* b;
  };
  std::vector<Channel> channels = {{"cloud layer", &fast.cloud_layer.rgba, &base.cloud_layer.rgba},
                                   {"frame", &fast.frame.rgba, &base.frame.rgba}};
  ASSERT_EQ(fast.passes.has_value(), base.passes.has_value()) << what;
  if (fast.passes) {
    channels.push_back({"ground pass", &fast.passes->ground_rgb, &base.passes->ground_rgb});
    channels.push_back({"sky pass", &fast.passes->sky_rgb, &base.passes->sky_rgb});
    channels.push_back({"shadow matte", &fast.passes->shadow, &base.passes->shadow});
    channels.push_back({"depth", &fast.passes->depth_m, &base.passes->depth_m});
  }
  for (const Channel& c : channels) {
    const long i = firstDifference(*c.a, *c.b);
    EXPECT_EQ(i, -1) << what << ": " << c.name << " differs first at float " << i << " (pixel " << i / 4
                     << " if RGBA): " << (i >= 0 && std::size_t(i) < c.a->size() ? (*c.a)[std::size_t(i)] : 0.0f)
                     << " vs " << (i >= 0 && std::size_t(i) < c.b->size() ? (*c.b)[std::size_t(i)] : 0.0f);
  }
}

TEST_F(EyePassVariants, SpecialisedProgramsAndLinearScanMatchTheBaselineBitForBit) {
  ScratchDir dir("eye-pass-variants");
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 1;
  spec.mountain = {-76.2, 24.3, 3000.0, 35000.0};  // as tests/render/terrain_gl_test.cpp
  const std::string data = dir.file("wrfout_mountain.nc"), basemap = dir.file("coded.exr");
  datagen::writeWrfHurricane(spec, data);
  writeCodedBasemap(basemap);
  const Variant variants[] = {{"flat, all on", "flat", true},
                              {"flat, all off", "flat", false},
                              {"globe, all on", "globe", true},
                              {"globe, all off", "globe", false}};
  for (const Variant& v : variants) {
    const std::string b = v.on ? "true" : "false";
    const std::string json = R"({"data": {"path": "x"}, "camera": {"preset": "oblique", "fov_deg": 40},
      "sun": {"azimuth_deg": 140, "elevation_deg": 35},
      "basemap": {"path": ")" +
                             basemap +
                             R"(", "margin": 0.4, "pixels_long_side": 256},
      "style": {"terrain": )" +
                             b + R"(, "atmosphere": )" + b + R"(},
      "quality": {"preset": "broadcast", "overrides": {"light_cache_voxels": 0, "detail": ")" +
                             (v.on ? "full" : "none") + R"(", "reconstruction": ")" + (v.on ? "cubic" : "trilinear") +
                             R"("}},
      "output": {"width": 96, "height": 54}, "height_exaggeration": 8, "view": ")" +
                             v.view + R"("})";
    auto session = openSession(json, data);
    session->setPasses(v.on);
    const scene::Camera cam = session->prepared().camera;
    render::CloudRenderer& renderer = session->renderer();
    // The packed texture (one fetch of β and the column depths in half precision; its own test:
    // LightCacheTest.PackedTextureDiffersOnlyAtTheTerminationThreshold) is a specialisation the
    // uniform-branch program does not have: compared here with the separate textures on both sides.
    // So is the light cache (on in the broadcast preset; LightCacheTest): off in the scene above.
    renderer.setBaseline({.separate_textures = true});
    const render::RenderOutput fast = session->render(cam);  // uploads the volume, builds the DLM
    const render::EyePassFeatures f =
        renderer.features(session->volumeTextures(), session->deepLightMap(), session->renderSettings());
    EXPECT_EQ(f.globe, std::string(v.view) == "globe") << v.name;
    EXPECT_EQ(f.atmosphere, v.on) << v.name;
    EXPECT_EQ(f.passes, v.on) << v.name;
    EXPECT_EQ(f.detail, v.on) << v.name;
    EXPECT_EQ(f.cubic, v.on) << v.name;
    EXPECT_EQ(f.terrain, v.on) << v.name << " (terrain is drawn in both views)";
    EXPECT_FALSE(f.packed) << v.name << " (separate textures asked for)";
    EXPECT_EQ(session->volumeTextures().hasPacked(), !v.on) << v.name << " (packed for trilinear without detail)";
    renderer.setBaseline({.uniform_branches = true, .binary_search = false});
    const render::RenderOutput uniforms = session->render(cam);
    renderer.setBaseline({.uniform_branches = false, .binary_search = true, .separate_textures = true});
    const render::RenderOutput binary = session->render(cam);
    renderer.setBaseline({});
    EXPECT_EQ(renderer.programCount(), 3u) << v.name << ": specialised, uniform branches, binary search";
    double alpha = 0.0;
    for (std::size_t i = 3; i < fast.cloud_layer.rgba.size(); i += 4) alpha += double(fast.cloud_layer.rgba[i]);
    alpha /= double(fast.cloud_layer.rgba.size() / 4);
    EXPECT_GT(alpha, 0.05) << v.name << ": the view must show cloud";
    expectSameBits(fast, uniforms, std::string(v.name) + ", specialised vs uniform branches");
    expectSameBits(fast, binary, std::string(v.name) + ", linear scan vs binary search");
    std::printf("[ variants ] %s: mean alpha %.3f, specialised = uniform branches = binary search, bit for bit\n",
                v.name, alpha);
  }
}

}  // namespace
}  // namespace nph::test

// `nephele view` without interaction (issue 5): under xvfb-run, --frames 3 --screenshot renders
// three full-resolution frames in a GLFW window and writes what the window shows; the picture
// must be non-trivial (clouds and ground) and match `nephele render` of the same scene and camera
// (the flat view with a white balance of 8000 K, the globe neutral).
// Tolerance: the same ray caster on the same llvmpipe produces the same linear frame; the viewer
// applies exposure, tone curve and sRGB in GLSL (glsl/render/present.frag), `render` in C++
// (scene/output_image.cpp), so an 8-bit code may differ by one where a value sits on a rounding
// boundary (measured: 3 of 57 600 pixels at 320 × 180, by 1/255). Max 2/255, mean 1e-3.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <fmt/format.h>

#include "support/image_compare.h"
#include "support/scratch_dir.h"
#include "wrf_hurricane.h"

namespace nph::test {
namespace {

constexpr Tolerance kViewVsRender{2.0 / 255.0 + 1e-6, 1e-3};

class ViewTest : public ::testing::TestWithParam<std::string> {
 protected:
  std::string file(const std::string& name) const { return dir_.file(name); }
  ScratchDir dir_{"view"};
};

double luminanceSpread(const Image& img, double& mean) {
  double sum = 0.0, sum2 = 0.0;
  const double n = double(img.width) * double(img.height);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double l = double(img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
      sum += l;
      sum2 += l * l;
    }
  }
  mean = sum / n;
  return std::sqrt(std::max(sum2 / n - mean * mean, 0.0));
}

TEST_P(ViewTest, ScreenshotMatchesRender) {
  datagen::WrfHurricaneSpec spec;  // the tiny preset, two timesteps
  spec.ntimes = 2;
  const std::string data = file("wrfout_tiny.nc"), scene = file("scene.json");
  datagen::writeWrfHurricane(spec, data);
  std::ofstream(scene) << fmt::format(R"({{"data": {{"path": "{}", "timestep": 1}},
    "camera": {{"preset": "{}", "fov_deg": 40{}}}, "sun": {{"azimuth_deg": 140, "elevation_deg": 35}},
    "basemap": {{"path": "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg", "margin": 0.4, "pixels_long_side": 512}},
    "quality": {{"preset": "draft"}}, "output": {{"width": 200, "height": 120{}}},
    "height_exaggeration": 8, "view": "{}"}})",
                                      data, GetParam() == "globe" ? "overview" : "oblique",
                                      GetParam() == "globe" ? ", \"distance_scale\": 3" : "",
                                      // The flat view with a warm white balance (scene/white_balance.h): the
                                      // viewer's GLSL gain and the writer's C++ one must agree too.
                                      GetParam() == "globe" ? "" : ", \"white_balance_k\": 8000", GetParam());
  const std::string view = file("view.png"), render = file("render.png");
  const std::string nephele = NEPHELE_EXECUTABLE;
  // The sanitizer build's LD_PRELOAD for the viewer alone, not xvfb-run and Xvfb
  // (tests/support/keep_libraries_mapped.c); unset elsewhere.
  const char* preload = std::getenv("NEPHELE_TEST_GLFW_PRELOAD");
  const std::string env = preload != nullptr ? fmt::format("env 'LD_PRELOAD={}' ", preload) : "";
  ASSERT_EQ(
      // Server numbers from 1000 + pid % 1000 up (the other Xvfb tests start at 120 and 200), no
      // reset when a client leaves (tests/gl/CMakeLists.txt).
      std::system(fmt::format("xvfb-run -a -n {} -s '-screen 0 1280x1024x24 -noreset' {}'{}' view '{}' --width 200 "
                              "--height 120 --frames 3 --screenshot '{}'",
                              1000 + ::getpid() % 1000, env, nephele, scene, view)
                      .c_str()),
      0);
  ASSERT_EQ(std::system(fmt::format("'{}' render '{}' --gl auto -o '{}'", nephele, scene, render).c_str()), 0);
  const Image shot = readImage(view);
  ASSERT_EQ(shot.width, 200);
  ASSERT_EQ(shot.height, 120);
  double mean = 0.0;
  const double spread = luminanceSpread(shot, mean);
  std::printf("[ view     ] %s screenshot: mean %.3f, spread %.3f\n", GetParam().c_str(), mean, spread);
  EXPECT_GT(spread, 0.05) << "a flat picture: no clouds over ground";
  const CompareResult r = compareToFile(shot, render, kViewVsRender, "view-vs-render-" + GetParam());
  std::printf("[ view     ] %s vs nephele render: max %.4f, mean %.2e\n", GetParam().c_str(), r.max_abs, r.mean_abs);
  EXPECT_TRUE(r.pass) << r.message;
}

INSTANTIATE_TEST_SUITE_P(Views, ViewTest, ::testing::Values(std::string("flat"), std::string("globe")),
                         [](const auto& param) { return param.param; });

}  // namespace
}  // namespace nph::test

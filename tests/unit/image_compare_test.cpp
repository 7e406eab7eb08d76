#include <gtest/gtest.h>

#include <filesystem>

#include "support/image_compare.h"

namespace nph::test {
namespace {

Image ramp(int w, int h) {
  Image img{w, h, 3, std::vector<float>(std::size_t(w * h * 3))};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = float(x + y + c) / float(w + h + 3);
  return img;
}

TEST(ImageCompare, IdenticalImagesPassAtZeroTolerance) {
  const Image a = ramp(8, 5);
  const auto r = compareImages(a, a, {0.0, 0.0}, "identical");
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_EQ(r.max_abs, 0.0);
  EXPECT_TRUE(r.diff_path.empty());
}

TEST(ImageCompare, OnePixelOffFailsOnMaxAndWritesActualExpectedDiff) {
  const Image e = ramp(8, 5);
  Image a = e;
  a.at(3, 2, 1) += 0.5f;
  const auto r = compareImages(a, e, {0.1, 1.0}, "one_pixel_off");
  EXPECT_FALSE(r.pass);
  EXPECT_NEAR(r.max_abs, 0.5, 1e-6);
  EXPECT_NEAR(r.mean_abs, 0.5 / (8 * 5 * 3), 1e-7);
  ASSERT_FALSE(r.diff_path.empty());
  for (const char* kind : {"actual", "expected", "diff"}) {
    EXPECT_TRUE(std::filesystem::exists(testOutputDir() + "/one_pixel_off." + kind + ".exr")) << kind;
  }
  const Image diff = readImage(r.diff_path);
  EXPECT_FLOAT_EQ(diff.at(3, 2, 1), 1.0f);  // scaled so the largest difference is white
  EXPECT_FLOAT_EQ(diff.at(0, 0, 0), 0.0f);
}

TEST(ImageCompare, MeanToleranceCatchesSmallWidespreadError) {
  const Image e = ramp(8, 5);
  Image a = e;
  for (float& v : a.pixels) v += 0.01f;
  EXPECT_TRUE(compareImages(a, e, {0.02, 0.02}, "widespread_ok").pass);
  EXPECT_FALSE(compareImages(a, e, {0.02, 0.005}, "widespread_bad").pass);
}

TEST(ImageCompare, SizeMismatchAndNanFail) {
  EXPECT_FALSE(compareImages(ramp(8, 5), ramp(5, 8), {1, 1}, "size").pass);
  Image a = ramp(4, 4);
  a.at(1, 1, 0) = std::numeric_limits<float>::quiet_NaN();
  const auto r = compareImages(a, ramp(4, 4), {1e9, 1e9}, "nan");
  EXPECT_FALSE(r.pass) << "NaN must never pass, whatever the tolerance";
}

TEST(ImageCompare, FileRoundTripThroughOpenImageIO) {
  const Image a = ramp(6, 4);
  const std::string path = testOutputDir() + "/roundtrip.exr";
  writeImage(a, path);
  const auto r = compareToFile(a, path, {0.0, 0.0}, "roundtrip");
  EXPECT_TRUE(r.pass) << r.message;
}

}  // namespace
}  // namespace nph::test

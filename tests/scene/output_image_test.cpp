// Output images: EXR (half, premultiplied, linear, Z) and PNG (sRGB, straight alpha, 8-bit) round
// trips through OpenImageIO; known values -> known codes; zero alpha; no partial files.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "atmosphere/atmosphere.h"
#include "core/error.h"
#include "scene/output_image.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

namespace fs = std::filesystem;

/// IEC 61966-2-1 decode, written out here so the test does not lean on the code under test.
double srgbDecode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

RgbaImage image(int w, int h, std::vector<float> rgba, std::vector<float> depth = {}) {
  RgbaImage img;
  img.width = w;
  img.height = h;
  img.rgba = std::move(rgba);
  img.depth_m = std::move(depth);
  return img;
}

std::vector<float> readFloat(const std::string& path, OIIO::ImageSpec& spec) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  spec = in->spec();
  std::vector<float> px(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  return px;
}

TEST(OutputImage, ExrIsHalfPremultipliedLinearWithDepth) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("clouds.exr");
  const RgbaImage img = image(2, 1, {0.25f, 0.5f, 0.125f, 0.5f, 3.0f, 2.0f, 1.0f, 1.0f}, {1234.5f, 98765.25f});
  ImageOutputOptions o;
  o.exposure_ev = 1.0;
  writeExr(img, path, o);
  OIIO::ImageSpec spec;
  const std::vector<float> px = readFloat(path, spec);
  ASSERT_EQ(spec.nchannels, 5);
  EXPECT_EQ(spec.channelnames, (std::vector<std::string>{"R", "G", "B", "A", "Z"}));
  EXPECT_EQ(spec.channelformat(0), OIIO::TypeDesc::HALF);
  EXPECT_EQ(spec.channelformat(3), OIIO::TypeDesc::HALF);
  EXPECT_EQ(spec.channelformat(4), OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.alpha_channel, 3);
  // Premultiplied colour times 2^1, alpha untouched; these values are exact in half.
  EXPECT_EQ(px[0], 0.5f);
  EXPECT_EQ(px[1], 1.0f);
  EXPECT_EQ(px[2], 0.25f);
  EXPECT_EQ(px[3], 0.5f);
  EXPECT_EQ(px[4], 1234.5f);  // depth stays float: 98765 m would overflow half (max 65504)
  EXPECT_EQ(px[5], 6.0f);
  EXPECT_EQ(px[8], 1.0f);
  EXPECT_EQ(px[9], 98765.25f);
  // Without depth: four channels.
  o.write_depth = false;
  writeExr(img, path, o);
  EXPECT_EQ(readFloat(path, spec).size(), 8u);
  EXPECT_EQ(spec.nchannels, 4);
  // Half precision: 0.1 stores as 0.0999755859375.
  writeExr(image(1, 1, {0.1f, 0.0f, 0.0f, 1.0f}), path);
  EXPECT_NEAR(readFloat(path, spec)[0], 0.1f, 5e-5f);
}

TEST(OutputImage, KnownValuesGiveKnownSrgbCodes) {
  const double l100 = srgbDecode(100.0 / 255.0);  // linear value whose sRGB code is exactly 100
  const auto L = static_cast<float>(l100);
  ImageOutputOptions clamp;
  clamp.tone_curve = ToneCurve::Clamp;
  const RgbaImage img = image(4, 1,
                              {
                                  0.25f * L, 0.25f, 0.0f, 0.25f,  // α = ¼: straight colour (L, 1, 0)
                                  0.3f, 0.3f, 0.3f, 0.0f,         // α = 0 with "colour" (additive glow): dropped
                                  2.0f, 0.5f, 0.0f, 1.0f,         // opaque, over-range red
                                  1e-4f, 1e-4f, 1e-4f, 1e-3f,     // α below half a code: fully transparent, black
                              });
  const std::vector<std::uint8_t> c = encodeSrgb8(img, clamp);
  EXPECT_EQ((std::vector<int>(c.begin(), c.begin() + 4)), (std::vector<int>{100, 255, 0, 64}));
  EXPECT_EQ((std::vector<int>(c.begin() + 4, c.begin() + 8)), (std::vector<int>{0, 0, 0, 0}));
  // 0.5 linear -> sRGB 0.735357 -> 187.5 -> 188.
  EXPECT_EQ((std::vector<int>(c.begin() + 8, c.begin() + 12)), (std::vector<int>{255, 188, 0, 255}));
  EXPECT_EQ((std::vector<int>(c.begin() + 12, c.end())), (std::vector<int>{0, 0, 0, 0}));

  // Exposure +1 EV doubles the radiance before the curve: straight 0.5 -> 1.0 -> 255.
  ImageOutputOptions brighter = clamp;
  brighter.exposure_ev = 1.0;
  EXPECT_EQ(encodeSrgb8(image(1, 1, {0.5f, 0.25f, 0.0f, 1.0f}), brighter)[0], 255);
  EXPECT_EQ(encodeSrgb8(image(1, 1, {0.5f, 0.25f, 0.0f, 1.0f}), brighter)[1], 188);

  // Reinhard: 1 -> ½ -> 188. ACES fit (Narkowicz): x = 0.6 -> 0.673290 -> sRGB -> code.
  ImageOutputOptions reinhard;
  reinhard.tone_curve = ToneCurve::Reinhard;
  EXPECT_EQ(encodeSrgb8(image(1, 1, {1.0f, 0.0f, 0.0f, 1.0f}), reinhard)[0], 188);
  const double x = 0.6, aces = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
  EXPECT_NEAR(aces, 0.673290, 1e-6);
  const double acesSrgb = 1.055 * std::pow(aces, 1.0 / 2.4) - 0.055;
  EXPECT_EQ(encodeSrgb8(image(1, 1, {1.0f, 0.0f, 0.0f, 1.0f}), ImageOutputOptions{})[0],
            int(std::lround(acesSrgb * 255.0)));
  // The curves are monotone, map 0 to 0 and stay within [0, 1].
  for (ToneCurve t : {ToneCurve::Clamp, ToneCurve::Reinhard, ToneCurve::AcesFitted}) {
    EXPECT_EQ(applyToneCurve(0.0f, t), 0.0f);
    float prev = 0.0f;
    for (float v = 0.01f; v < 100.0f; v *= 1.5f) {
      const float y = applyToneCurve(v, t);
      EXPECT_GE(y, prev);
      EXPECT_LE(y, 1.0f);
      prev = y;
    }
    EXPECT_EQ(toneCurveFromName(toneCurveName(t)), t);
  }
  EXPECT_THROW(toneCurveFromName("filmic"), InputError);
}

TEST(OutputImage, PngRoundTripKeepsStraightAlphaCodes) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("clouds.png");
  const auto L = static_cast<float>(srgbDecode(100.0 / 255.0));
  const RgbaImage img = image(2, 2,
                              {0.25f * L, 0.25f * L, 0.25f * L, 0.25f,  //
                               0.0f, 0.0f, 0.0f, 0.0f,                  //
                               1.0f, 1.0f, 1.0f, 1.0f,                  //
                               0.5f * L, 0.0f, 0.5f, 0.5f});
  ImageOutputOptions o;
  o.tone_curve = ToneCurve::Clamp;
  writePng(img, path, o);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 4);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
  in.reset();
  // Read the stored codes as they are (no premultiplication on read).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  in = OIIO::ImageInput::open(path, &config);
  ASSERT_TRUE(in);
  std::vector<std::uint8_t> codes(16);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, codes.data()));
  EXPECT_EQ(codes, encodeSrgb8(img, o));
  // Straight alpha: the quarter-covered grey keeps its full colour code 100, not 25.
  EXPECT_EQ((std::vector<int>(codes.begin(), codes.begin() + 4)), (std::vector<int>{100, 100, 100, 64}));
  EXPECT_EQ((std::vector<int>(codes.begin() + 12, codes.end())), (std::vector<int>{100, 0, 255, 128}));
}

TEST(OutputImage, FailedWritesLeaveNoPartialFile) {
  nph::test::ScratchDir dir("scene");
  const RgbaImage img = image(1, 1, {0.5f, 0.5f, 0.5f, 1.0f});
  // A folder sits where the file should go: the rename fails, the temporary file is removed.
  fs::create_directories(dir.path() / "taken.png" / "inside");
  try {
    writePng(img, dir.file("taken.png"));
    FAIL() << "wrote over a folder";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("taken.png"), std::string::npos) << e.what();
  }
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename(), "taken.png") << "left behind: " << entry.path();
  }
  // A missing folder: IoError naming the file.
  EXPECT_THROW(writeExr(img, dir.file("no/such/folder/x.exr")), IoError);
  // An inconsistent image never touches an existing file.
  { std::ofstream(dir.file("keep.exr")) << "previous frame"; }
  EXPECT_THROW(writeExr(image(2, 2, {1.0f}), dir.file("keep.exr")), UsageError);
  std::ifstream kept(dir.file("keep.exr"));
  std::string content;
  std::getline(kept, content);
  EXPECT_EQ(content, "previous frame");
  // A successful write replaces the old file in one step.
  writeImage(img, dir.file("keep.exr"));
  OIIO::ImageSpec spec;
  EXPECT_EQ(readFloat(dir.file("keep.exr"), spec)[0], 0.5f);
  EXPECT_THROW(writeImage(img, dir.file("frame.tiff")), InputError);
  writeImage(img, dir.file("UPPER.PNG"));
  EXPECT_TRUE(fs::exists(dir.file("UPPER.PNG")));
}

}  // namespace
}  // namespace nph::scene

namespace nph::scene {
namespace {

// The exposure that follows the sun (output.exposure "sun", issue 14): half the log₂ drop of the
// horizontal illuminance (direct sun + sky, atmosphere::horizontalIlluminance) 2 km up against
// a 35° sun. Invariants, and the value at 5° against the meter evaluated here by its definition.
TEST(OutputImage, SunExposureFollowsHalfTheDaylightDrop) {
  EXPECT_EQ(sunExposureOffsetEv(kExposureReferenceSunElevationDeg), 0.0);
  double previous = 4.0;
  for (double el = -10.0; el <= 90.0; el += 0.5) {
    const double ev = sunExposureOffsetEv(el);
    EXPECT_LE(ev, previous + 1e-12) << "a higher sun never needs more exposure, at " << el << " deg";
    EXPECT_GE(ev, -1.0);
    EXPECT_LE(ev, 4.0);
    previous = ev;
  }
  EXPECT_EQ(sunExposureOffsetEv(-10.0), 4.0);  // night: clamped
  EXPECT_LT(sunExposureOffsetEv(60.0), 0.0);   // a higher sun than the reference: a little less
  const atmosphere::Parameters earth;
  const double rad = 3.14159265358979323846 / 180.0;
  const double expected = 0.5 * std::log2(atmosphere::horizontalIlluminance(earth, 2000.0, 35.0 * rad) /
                                          atmosphere::horizontalIlluminance(earth, 2000.0, 5.0 * rad));
  EXPECT_NEAR(sunExposureOffsetEv(5.0), expected, 1e-12);
  // The meter itself: at 5° the sky's share is large and the sun's small (a golden-hour scene is
  // ≈ 10× darker than at 35°: 3.3 EV, of which the exposure makes up half).
  EXPECT_GT(expected, 1.4);
  EXPECT_LT(expected, 1.9);
  EXPECT_EQ(sunExposureOffsetEv(std::nan("")), 0.0);
}

}  // namespace
}  // namespace nph::scene

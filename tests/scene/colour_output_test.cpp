// Output colour through OpenColorIO (issue 15 item 2; docs/colour.md): nephele's shipped config
// (src/scene/ocio/config.ocio, its LUT written at build time) against closed forms that do not
// lean on OCIO — the legacy tone curve + sRGB path, BT.1886's pure 2.4 power, PQ's inverse EOTF
// (SMPTE ST 2084) at the ACES HDR transform's design point — and the error messages.
#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "scene/colour_output.h"
#include "scene/output_image.h"

namespace nph::scene {
namespace {

// A grey ramp 0 … 20 (past the curve's white at ≈ 13) and saturated colours, α = 1, linear.
RgbaImage rampImage() {
  RgbaImage img;
  img.width = 1024;
  img.height = 2;
  for (int row = 0; row < 2; ++row) {
    for (int i = 0; i < 1024; ++i) {
      const float v = 20.0f * float(i) / 1023.0f * float(i) / 1023.0f;  // dense near black
      if (row == 0) img.rgba.insert(img.rgba.end(), {v, v, v, 1.0f});
      else img.rgba.insert(img.rgba.end(), {v, 0.3f * v, 0.05f * v, 1.0f});
    }
  }
  return img;
}

// The `nephele` view on the sRGB display is, by construction, the tone curve + sRGB encoding
// `nephele render` writes without OCIO: the two 8-bit encodings agree within 1 code everywhere
// (the LUT's interpolation and the two 3×3 matrices round trip in float), and exactly on almost
// every pixel.
TEST(ColourOutput, NepheleViewOnSrgbIsTheLegacyPngEncoding) {
  const RgbaImage img = rampImage();
  ImageOutputOptions legacy;
  legacy.exposure_ev = 0.5;
  ImageOutputOptions ocio = legacy;
  ocio.display = "sRGB";
  ocio.view = "nephele";
  const std::vector<std::uint8_t> a = encodeSrgb8(img, legacy);
  const std::vector<float> b = encodeDisplay(img, ocio);
  ASSERT_EQ(a.size(), b.size());
  int maxDiff = 0, exact = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const int code = int(std::lround(b[i] * 255.0f));
    maxDiff = std::max(maxDiff, std::abs(code - int(a[i])));
    exact += code == int(a[i]) ? 1 : 0;
  }
  EXPECT_LE(maxDiff, 1);
  EXPECT_GE(double(exact), 0.99 * double(a.size()));
}

// BT.1886 with a zero black level is a pure 2.4 power: the Rec.1886 display with the nephele view
// gives curve(c)^(1/2.4) (ITU-R BT.1886 annex 1, L_B = 0), to float precision.
TEST(ColourOutput, Rec1886IsThePureGammaOfTheToneCurve) {
  const RgbaImage img = rampImage();
  ImageOutputOptions o;
  o.display = "Rec.1886 Rec.709";
  o.view = "nephele";
  const std::vector<float> v = encodeDisplay(img, o);
  double maxErr = 0.0;
  for (int i = 0; i < 1024; ++i) {
    const double c = img.rgba[std::size_t(4 * i)];
    const double expected = std::pow(double(applyToneCurve(float(c), ToneCurve::AcesFitted)), 1.0 / 2.4);
    maxErr = std::max(maxErr, std::abs(double(v[std::size_t(4 * i)]) - expected));
  }
  EXPECT_LE(maxErr, 2e-4);  // the LUT's interpolation, amplified by the power near black
}

/// SMPTE ST 2084 inverse EOTF: absolute luminance [cd/m²] → PQ code value in [0, 1].
double pqEncode(double nits) {
  const double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0;
  const double c1 = 3424.0 / 4096.0, c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
  const double y = std::pow(nits / 10000.0, m1);
  return std::pow((c1 + c2 * y) / (1.0 + c3 * y), m2);
}

// The ACES 1.1 HDR video transform "1000nit-15nit" is designed to put scene mid grey (0.18) at
// 15 cd/m² and to peak at 1000: on the PQ display, grey 0.18 encodes to PQ(15 nits) and a very
// bright grey to at most PQ(1000 nits); the ramp is monotonic; the PNG is 16-bit (hdr-video).
TEST(ColourOutput, AcesHdrOnPqPutsMidGreyAtFifteenNits) {
  RgbaImage img;
  img.width = 3;
  img.height = 1;
  img.rgba = {0.18f, 0.18f, 0.18f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1000.0f, 1000.0f, 1000.0f, 1.0f};
  ImageOutputOptions o;
  o.display = "Rec.2100-PQ";
  o.view = "ACES HDR video";
  const std::vector<float> v = encodeDisplay(img, o);
  EXPECT_NEAR(v[0], pqEncode(15.0), 0.5 / 1023.0) << "PQ(15 nits) = " << pqEncode(15.0);
  EXPECT_NEAR(v[1], v[2], 1e-5);   // grey stays grey
  EXPECT_LT(v[4], pqEncode(0.1));  // black: below 0.1 nit
  EXPECT_LE(v[8], pqEncode(1000.0) + 0.5 / 1023.0);
  EXPECT_GT(v[8], pqEncode(900.0));
  EXPECT_TRUE(DisplayOutput::open("", "Rec.2100-PQ", "ACES HDR video")->hdr());
  EXPECT_FALSE(DisplayOutput::open("", "sRGB", "")->hdr());
  const RgbaImage ramp = rampImage();
  const std::vector<float> r = encodeDisplay(ramp, o);
  for (int i = 1; i < 1024; ++i) EXPECT_GE(r[std::size_t(4 * i)], r[std::size_t(4 * (i - 1))]) << i;
}

// Every display/view pair against OpenImageIO's own OpenColorIO path (ImageBufAlgo::ociodisplay,
// what `oiiotool --ociodisplay` runs) on the same float pixels: the codes agree to float rounding,
// far inside one code value (8-bit SDR, 10-bit HDR video).
TEST(ColourOutput, EveryDisplayViewMatchesOpenImageIOsConversion) {
  const RgbaImage img = rampImage();
  OIIO::ColorConfig config(defaultOcioConfig());
  ASSERT_FALSE(config.has_error()) << config.geterror();
  for (const auto& [display, view] :
       std::vector<std::pair<std::string, std::string>>{{"sRGB", "nephele"},
                                                        {"sRGB", "ACES SDR video"},
                                                        {"Rec.1886 Rec.709", "nephele"},
                                                        {"Rec.1886 Rec.709", "ACES SDR video"},
                                                        {"Rec.2100-PQ", "ACES HDR video"},
                                                        {"Rec.2100-HLG", "ACES HDR video"}}) {
    SCOPED_TRACE(display + " / " + view);
    ImageOutputOptions o;
    o.display = display;
    o.view = view;
    const std::vector<float> ours = encodeDisplay(img, o);
    OIIO::ImageBuf src(OIIO::ImageSpec(img.width, img.height, 4, OIIO::TypeDesc::FLOAT),
                       const_cast<float*>(img.rgba.data()));
    OIIO::ImageBuf dst;
    ASSERT_TRUE(
        OIIO::ImageBufAlgo::ociodisplay(dst, src, display, view, "Linear Rec.709 (sRGB)", "", true, "", "", &config))
        << dst.geterror();
    std::vector<float> theirs(ours.size());
    ASSERT_TRUE(dst.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, theirs.data()));
    double maxDiff = 0.0;
    for (std::size_t i = 0; i < ours.size(); ++i) {
      maxDiff = std::max(maxDiff, std::abs(double(ours[i]) - std::clamp(double(theirs[i]), 0.0, 1.0)));
    }
    EXPECT_LE(maxDiff, 1e-4);
  }
}

// Every display and view of the shipped config opens, the default view is the first listed, the
// video tags name the display's primaries and transfer, and mistakes name what exists.
TEST(ColourOutput, EveryDisplayOpensAndMistakesListWhatExists) {
  for (const char* display : {"sRGB", "Rec.1886 Rec.709", "Rec.2100-PQ", "Rec.2100-HLG"}) {
    for (const char* view : {"nephele", "Raw"}) EXPECT_NO_THROW(DisplayOutput::open("", display, view)) << display;
    EXPECT_FALSE(DisplayOutput::open("", display, "")->videoTags().empty());
  }
  EXPECT_EQ(DisplayOutput::open("", "sRGB", "")->view(), "nephele");
  EXPECT_EQ(DisplayOutput::open("", "Rec.2100-HLG", "")->view(), "ACES HDR video");
  EXPECT_EQ(DisplayOutput::open("", "Rec.2100-HLG", "")->videoTags().transfer, "arib-std-b67");
  EXPECT_EQ(DisplayOutput::open("", "Rec.2100-PQ", "")->videoTags().transfer, "smpte2084");
  try {
    (void)DisplayOutput::open("", "Rec.2020", "");
    FAIL() << "an unknown display opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"Rec.2100-PQ\""), std::string::npos) << e.what();
  }
  try {
    (void)DisplayOutput::open("", "sRGB", "Filmic");
    FAIL() << "an unknown view opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"ACES SDR video\""), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)DisplayOutput::open("/nonexistent/config.ocio", "sRGB", ""), InputError);
}

}  // namespace
}  // namespace nph::scene

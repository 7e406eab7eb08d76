// A camera's white balance (scene/white_balance.h; issue 14, nineteenth session): the Planckian
// locus against CIE illuminant A; the neutral setting is the identity, bit for bit, in every
// writer; a light of the set temperature comes out white; a grey card under a 5° sun is balanced at
// the temperature McCamy's closed form reads from its colour (up to the ozone's tint); the writers;
// the scene key and its range.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "atmosphere/atmosphere.h"
#include "core/error.h"
#include "scene/output_image.h"
#include "scene/scene_file.h"
#include "scene/white_balance.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Y of linear Rec.709 (IEC 61966-2-1's matrix row, as the code under test uses).
double luminance(glm::dvec3 c) { return 0.2126390059 * c.r + 0.7151686788 * c.g + 0.0721923154 * c.b; }

/// How far a colour is from grey: the largest channel over the smallest, minus 1.
double spread(glm::dvec3 c) { return std::max({c.r, c.g, c.b}) / std::min({c.r, c.g, c.b}) - 1.0; }

/// Correlated colour temperature of a linear Rec.709 colour by McCamy 1992 ("Correlated color
/// temperature as an explicit function of chromaticity coordinates", Color Res. Appl. 17(2)): the
/// colour's CIE 1931 xy (IEC 61966-2-1's Rec.709 → XYZ matrix, written out here), then
/// n = (x − 0.3320)/(0.1858 − y), CCT = 449 n³ + 3525 n² + 6823.3 n + 5520.33 — within 2 K of the
/// Planckian locus's isotemperature lines from 2856 to 6504 K. Independent of Kang et al.'s locus.
double mcCamyCct(glm::dvec3 c) {
  const double X = 0.4123907993 * c.r + 0.3575843394 * c.g + 0.1804807884 * c.b;
  const double Y = 0.2126390059 * c.r + 0.7151686788 * c.g + 0.0721923154 * c.b;
  const double Z = 0.0193308187 * c.r + 0.1191947798 * c.g + 0.9505321522 * c.b;
  const double x = X / (X + Y + Z), y = Y / (X + Y + Z);
  const double n = (x - 0.3320) / (0.1858 - y);
  return ((449.0 * n + 3525.0) * n + 6823.3) * n + 5520.33;
}

TEST(WhiteBalance, PlanckianLocusMeetsIlluminantAAndD65IsTheNeutralWhite) {
  // CIE 15:2004: illuminant A, the Planckian radiator at 2856 K, is (0.44757, 0.40745). Kang et
  // al.'s spline gives (0.44707, 0.40751).
  const glm::dvec2 a = planckianXy(2856.0);
  EXPECT_NEAR(a.x, 0.44757, 6e-4);
  EXPECT_NEAR(a.y, 0.40745, 1e-4);
  // The locus runs from red to blue: x falls with the temperature.
  for (double t = 2500.0; t < 25000.0; t *= 1.1) EXPECT_GT(planckianXy(t).x, planckianXy(t * 1.1).x) << t;
  // The neutral light is the renderer's white, D65 = (1, 1, 1) in Rec.709.
  const glm::dvec3 w = whiteBalanceLight(kNeutralWhiteBalanceK);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(w[c], 1.0, 1e-9) << c;
}

TEST(WhiteBalance, NeutralIsTheIdentityBitForBit) {
  EXPECT_EQ(whiteBalanceGain(kNeutralWhiteBalanceK), glm::dvec3(1.0));
  ImageOutputOptions defaults;
  EXPECT_EQ(defaults.white_balance_k, kNeutralWhiteBalanceK);
  EXPECT_EQ(parseSceneText("{}", "empty.json").output.image.white_balance_k, kNeutralWhiteBalanceK);
  defaults.exposure_ev = 2.5;
  EXPECT_EQ(radianceScale(defaults), glm::vec3(static_cast<float>(std::exp2(2.5))));  // the scale before the knob
  // Every value of a float image through the PNG path: the same codes as without the knob's
  // multiplication (2^2.5 · v, the writer before the white balance).
  RgbaImage img;
  img.width = 64;
  img.height = 1;
  for (int i = 0; i < 64; ++i) {
    const float v = 0.003f * float(i * i);
    img.rgba.insert(img.rgba.end(), {v, 0.5f * v, 0.25f * v, 1.0f});
  }
  const std::vector<std::uint8_t> codes = encodeSrgb8(img, defaults);
  const float s = static_cast<float>(std::exp2(2.5));
  for (std::size_t i = 0; i < codes.size(); ++i) {
    if (i % 4 == 3) continue;
    const auto expect = static_cast<std::uint8_t>(std::lround(
        std::clamp(linearToSrgb(applyToneCurve(s * img.rgba[i], ToneCurve::AcesFitted)), 0.0f, 1.0f) * 255.0f));
    ASSERT_EQ(codes[i], expect) << i;
  }
}

TEST(WhiteBalance, ALightOfTheSetTemperatureComesOutWhiteAtItsLuminance) {
  for (double t : {2500.0, 3200.0, 4000.0, 5600.0, 8000.0, 12000.0, 25000.0}) {
    for (double duv : {0.0, -0.015, 0.01}) {
      const glm::dvec3 light = whiteBalanceLight(t, duv);
      EXPECT_NEAR(luminance(light), 1.0, 1e-9) << t;
      const glm::dvec3 seen = whiteBalanceGain(t, duv) * light;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(seen[c], 1.0, 1e-9) << t << " K, Duv " << duv << ", channel " << c;
    }
  }
  // A negative tint expects magenta light: it adds green; a positive one takes it.
  EXPECT_GT(whiteBalanceGain(kNeutralWhiteBalanceK, -0.01).g, 1.02);
  EXPECT_LT(whiteBalanceGain(kNeutralWhiteBalanceK, 0.01).g, 0.98);
  EXPECT_THROW((void)whiteBalanceGain(kNeutralWhiteBalanceK, 0.03), UsageError);
  // Above the neutral the camera expects bluer light: the picture warms; below it cools. The
  // gains grow monotonically away from the neutral.
  const glm::dvec3 shade = whiteBalanceGain(7500.0), tungsten = whiteBalanceGain(3200.0);
  EXPECT_GT(shade.r, 1.0);
  EXPECT_LT(shade.b, 1.0);
  EXPECT_LT(tungsten.r, 1.0);
  EXPECT_GT(tungsten.b, 1.0);
  EXPECT_GT(whiteBalanceGain(9000.0).r, shade.r);
  EXPECT_GT(whiteBalanceGain(2800.0).b, tungsten.b);
  EXPECT_THROW((void)whiteBalanceGain(2000.0), UsageError);
}

/// CIE 1960 uv of a linear Rec.709 colour (written out: IEC 61966-2-1's matrix, then u = 4X/(X + 15Y
/// + 3Z), v = 6Y/(X + 15Y + 3Z)).
glm::dvec2 uv(glm::dvec3 c) {
  const double X = 0.4123907993 * c.r + 0.3575843394 * c.g + 0.1804807884 * c.b;
  const double Y = 0.2126390059 * c.r + 0.7151686788 * c.g + 0.0721923154 * c.b;
  const double Z = 0.0193308187 * c.r + 0.1191947798 * c.g + 0.9505321522 * c.b;
  return glm::dvec2(4.0 * X, 6.0 * Y) / (X + 15.0 * Y + 3.0 * Z);
}

/// A light's signed distance in uv from the moved locus (whiteBalanceLight(T, 0)), searched within
/// 20 % of `t` — negative below the locus (magenta).
double lightDuv(glm::dvec3 light, double t) {
  const glm::dvec2 p = uv(light);
  double best = 1e300;
  glm::dvec2 nearest{};
  for (double tt = 0.8 * t; tt <= 1.2 * t; tt *= 1.0002) {
    const glm::dvec2 q = uv(whiteBalanceLight(tt));
    if (glm::length(p - q) < best) {
      best = glm::length(p - q);
      nearest = q;
    }
  }
  return p.y < nearest.y ? -best : best;
}

/// The temperature that makes `light` most nearly grey (the least spread), searched in steps of 0.2 %.
double matchingTemperature(glm::dvec3 light) {
  double best = 1e300, best_t = 0.0;
  for (double t = kMinWhiteBalanceK; t <= kMaxWhiteBalanceK; t *= 1.002) {
    const double s = spread(whiteBalanceGain(t) * light);
    if (s < best) {
      best = s;
      best_t = t;
    }
  }
  return best_t;
}

// A grey card lying flat under a 5° sun at sea level, lit by the model's direct beam through the air
// and its once-scattered sky (atmosphere::horizontalIrradiance): orange in the neutral picture. The
// temperature that makes it most nearly grey agrees with the one McCamy's closed form reads from its
// colour, and balances its amber–blue axis (R = B). What a temperature cannot take out is the
// light's tint off the locus: the ozone's Chappuis band takes green (docs/atmosphere.md "The
// golden-hour light, measured"), and the balanced card keeps 12.5 % less green than red and blue — a
// magenta tint, which the tint (white_balance_duv) takes out. Without the ozone the same sun's
// light is within 5 % of grey at its temperature alone (measured 4.6 %, a slight green).
TEST(WhiteBalance, GreyCardUnderA5DegreeSunIsBalancedAtItsOwnTemperature) {
  atmosphere::Parameters p = atmosphere::Parameters::earth();
  const double sun = 5.0 * kPi / 180.0;
  const glm::dvec3 card = 0.18 / kPi * atmosphere::horizontalIrradiance(p, 0.0, sun);
  const double t = matchingTemperature(card), cct = mcCamyCct(card);
  const glm::dvec3 balanced = whiteBalanceGain(t) * card;
  std::printf("grey card under a 5 deg sun: linear (%.5f, %.5f, %.5f), spread %.3f; McCamy %.0f K; matching %.0f K: "
              "(%.5f, %.5f, %.5f), G/R %.3f, B/R %.4f\n",
              card.r, card.g, card.b, spread(card), cct, t, balanced.r, balanced.g, balanced.b, balanced.g / balanced.r,
              balanced.b / balanced.r);
  RecordProperty("matching_K", std::to_string(t));
  EXPECT_GT(card.r, card.g);
  EXPECT_GT(card.g, card.b);
  EXPECT_GT(spread(card), 0.5);     // far from grey in the neutral picture (0.99)
  EXPECT_NEAR(t, cct, 0.05 * cct);  // two readings of the light's temperature (4516 and 4398 K)
  EXPECT_GT(t, 3500.0);
  EXPECT_LT(t, 5500.0);
  EXPECT_NEAR(balanced.b / balanced.r, 1.0, 0.01);  // the amber–blue axis balanced
  EXPECT_GT(1.0 - balanced.g / balanced.r, 0.10);   // the ozone's magenta, left as it is (0.125)
  EXPECT_LT(1.0 - balanced.g / balanced.r, 0.18);
  EXPECT_NEAR(luminance(balanced), luminance(card), 0.03 * luminance(card));
  // It is the matching temperature: 10 % either way puts the amber–blue axis 4+ % off.
  for (double f : {0.9, 1.1}) {
    const glm::dvec3 off = whiteBalanceGain(f * t) * card;
    EXPECT_GT(std::abs(off.b / off.r - 1.0), 0.04) << f;
  }
  // With the tint the card is grey: the (T, Duv) that balance it, found by search, are the light's
  // temperature and its distance below the locus (magenta) read from its CIE 1960 uv directly.
  double best = 1e300, best_t = 0.0, best_duv = 0.0;
  for (double duv = -0.02; duv <= 0.0; duv += 0.0002) {
    for (double tt = 0.9 * t; tt <= 1.1 * t; tt *= 1.002) {
      const double sp = spread(whiteBalanceGain(tt, duv) * card);
      if (sp < best) {
        best = sp;
        best_t = tt;
        best_duv = duv;
      }
    }
  }
  std::printf("with the tint: %.0f K, Duv %.4f: spread %.4f (light's own Duv %.4f)\n", best_t, best_duv, best,
              lightDuv(card, t));
  EXPECT_LT(best, 0.01);
  EXPECT_NEAR(best_duv, lightDuv(card, t), 0.001);
  EXPECT_LT(best_duv, -0.004);  // magenta
  // Without the ozone the reddened sun and sky are close to a blackbody: within 5 % of grey.
  p.ozone_absorption_per_m = glm::dvec3(0.0);
  const glm::dvec3 no_ozone = 0.18 / kPi * atmosphere::horizontalIrradiance(p, 0.0, sun);
  const double t0 = matchingTemperature(no_ozone);
  EXPECT_NEAR(t0, mcCamyCct(no_ozone), 0.05 * t0);
  EXPECT_LT(spread(whiteBalanceGain(t0) * no_ozone), 0.05);
}

TEST(WhiteBalance, WritersApplyTheGainPerChannelWithTheExposure) {
  nph::test::ScratchDir dir("scene");
  RgbaImage img;
  img.width = 1;
  img.height = 1;
  img.rgba = {0.25f, 0.25f, 0.25f, 0.5f};  // premultiplied grey, half covered
  ImageOutputOptions o;
  o.exposure_ev = 1.0;
  o.white_balance_k = 8000.0;
  const glm::dvec3 g = whiteBalanceGain(8000.0);
  // EXR: premultiplied radiance × 2^1 × g, alpha untouched.
  const std::string exr = dir.file("wb.exr");
  writeExr(img, exr, o);
  auto in = OIIO::ImageInput::open(exr);
  ASSERT_TRUE(in);
  std::vector<float> px(4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, px.data()));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(px[std::size_t(c)], 0.5 * g[c], 1e-3 * 0.5 * g[c]) << c;  // half
  EXPECT_EQ(px[3], 0.5f);
  // PNG: the straight colour 2 · 0.5 · g through the tone curve.
  const std::vector<std::uint8_t> codes = encodeSrgb8(img, o);
  for (int c = 0; c < 3; ++c) {
    const float v = linearToSrgb(applyToneCurve(float(2.0 * 0.5 * g[c]), ToneCurve::AcesFitted));
    EXPECT_EQ(codes[std::size_t(c)], std::uint8_t(std::lround(v * 255.0f))) << c;
  }
  EXPECT_GT(codes[0], codes[2]);  // warmer
}

TEST(WhiteBalance, SceneKeyAndItsRange) {
  EXPECT_EQ(parseSceneText(R"({"output": {"white_balance_k": 8000}})", "wb.json").output.image.white_balance_k, 8000.0);
  try {
    (void)parseSceneText(R"({"output": {"white_balance_k": 1800}})", "wb.json");
    FAIL() << "1800 K accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("wb.json"), std::string::npos) << what;
    EXPECT_NE(what.find("white_balance_k"), std::string::npos) << what;
    EXPECT_NE(what.find("2500"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace nph::scene

#pragma once
// A camera's white balance (issue 14, nineteenth session; docs/atmosphere.md "A camera white
// balance"): a grade, not physics. The renderer's linear Rec.709 image is what a camera balanced
// for the sun above the air would record — the sun's irradiance is white, (1, 1, 1) — so a 6° sun,
// reddened by the air, lights the ground orange and the haze in front of a distant anvil stays
// blue (docs/atmosphere.md "The golden-hour light, measured"). A broadcast camera at golden hour is
// rarely set so: set to "shade" it warms the scene, set to the light's own temperature it makes
// the light white. This is that knob (scene file `output.white_balance_k`, the C API's
// `white_balance_k`).
//
// The gain is von Kries's (1902) adaptation applied on the camera's channels, as a camera applies
// its white-balance gains to the raw channels before its tone curve: a diagonal 3×3 on the linear
// image, after the exposure and before the tone curve (where Muth 2026 §3.4.10 has its straight
// RGB before the per-channel Reinhard curve; Thomann 2021 §5.10's time-of-day shots, "a golden
// sunset" among them, are the look a station grades towards),
//
//     c'_k = g_k(T) · c_k,     g_k(T) = P_k(T_ref) / P_k(T),     k ∈ {R, G, B},
//
// with P(T) the linear Rec.709 colour (luminance Y = 1) of the light a camera set to T renders
// white, and T_ref = kNeutralWhiteBalanceK = 6504 K, the temperature of the renderer's own white
// (D65, Rec.709's white). So a light of colour P(T) comes out white, (1, 1, 1)·Y, its luminance
// kept, and T = T_ref is the identity, exactly: each gain is a number divided by itself. T above
// T_ref warms the picture (the camera expects bluer light and holds blue back), below it cools it.
//
// P(T): the Planckian locus in CIE 1931 xy by the cubic splines of Kang et al. 2002 ("Design of
// advanced color temperature control system for HDTV applications", J. Korean Phys. Soc. 41(6),
// 865–871; valid 1667–25000 K; CIE illuminant A, the Planckian radiator at 2856 K, is
// (0.44757, 0.40745) in CIE 15:2004 and (0.44707, 0.40751) here), moved by the constant offset
// that puts 6504 K on D65, (0.3127, 0.3290): D65 lies 0.0054 above the Planckian locus (a green
// tint), and without the offset every balanced light would come out with the Planckian's magenta
// against the renderer's white (P_R, P_G, P_B of the plain locus at 6504 K are 1.042, 0.984,
// 1.035). Then xyY → XYZ and XYZ → linear Rec.709 with the matrix of IEC 61966-2-1
// (scene/ocio/config.ocio's).
//
// The tint (a camera's green–magenta axis): the light a camera set to (T, Duv) renders white lies
// Duv off that locus along its normal in the CIE 1960 uv plane (ANSI C78.377's Duv: positive
// above the locus, towards green). A camera set to a negative Duv expects magenta light and adds
// green. The golden-hour light of this model needs it: the ozone's Chappuis band, sampled at
// 550 nm, leaves a 5° sun's light 12.5 % short of green after its temperature is balanced
// (tests/scene/white_balance_test.cpp), so a temperature alone turns it salmon, not gold.
// Below 2500 K the moved locus's blue falls towards 0 (P_B(2500 K) = 0.12, a blue gain of 8;
// P_B(2000 K) = 0.005), so the knob's range starts there.
#include <glm/glm.hpp>

namespace nph::scene {

/// The neutral white balance [K]: the correlated colour temperature of CIE D65, the white of
/// Rec.709 and sRGB, which the renderer's white sun is displayed as. The default: no change.
inline constexpr double kNeutralWhiteBalanceK = 6504.0;
/// The knob's range [K] (the header comment: below 2500 K the blue gain exceeds 8).
inline constexpr double kMinWhiteBalanceK = 2500.0;
inline constexpr double kMaxWhiteBalanceK = 25000.0;

/// CIE 1931 (x, y) of the Planckian radiator at `kelvin` (Kang et al. 2002), for 1667–25000 K.
glm::dvec2 planckianXy(double kelvin);
/// The tint's range (Duv, CIE 1960 uv units): ANSI C78.377 allows white lights ±0.006; a grade
/// needs more, and ±0.02 spans the pinks and greens of a camera's tint slider.
inline constexpr double kMaxWhiteBalanceDuv = 0.02;

/// P(T, Duv): linear Rec.709 RGB, luminance Y = 1, of the light a camera set to `kelvin` and tint
/// `duv` renders white — planckianXy moved onto D65 at kNeutralWhiteBalanceK, then `duv` along the
/// locus's normal in CIE 1960 uv (header comment).
glm::dvec3 whiteBalanceLight(double kelvin, double duv = 0.0);
/// The per-channel gain g = P(kNeutralWhiteBalanceK, 0) / P(kelvin, duv) (header comment); exactly
/// (1, 1, 1) at the neutral setting. `kelvin` in [kMinWhiteBalanceK, kMaxWhiteBalanceK], |duv| ≤
/// kMaxWhiteBalanceDuv (UsageError otherwise; scene files and the C API check with their own messages).
glm::dvec3 whiteBalanceGain(double kelvin, double duv = 0.0);

}  // namespace nph::scene

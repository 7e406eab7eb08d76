#pragma once
// Writing the renderer's output: premultiplied linear RGBA float (+ optional depth) to
//   * OpenEXR — half RGBA, premultiplied ("associated") alpha, linear, exactly as rendered
//     (times the exposure), depth as a float Z channel; for compositing in Nuke/Fusion/Resolve;
//   * PNG — 8-bit sRGB with straight alpha, after exposure and a tone curve; for playout systems
//     that take PNG sequences.
// Files are written to a temporary name in the same folder and renamed into place, so a failed
// or interrupted write never leaves a partial file under the final name.
//
// 8-bit pipeline per pixel (Muth 2026 §3.4.10 does the same: un-premultiply, then tone-map):
//   c_lin = 2^exposure_ev · g(T) · C_premult / α   (straight colour; α = 0 -> black; g(T) the white
//                                                   balance's per-channel gain, scene/white_balance.h)
//   c_disp = curve(c_lin)                           (per channel, into [0, 1])
//   code = round(255 · sRGB_encode(c_disp)),  alpha code = round(255 · clamp(α, 0, 1))
// Tone curves:
//   Clamp      — min(c, 1); for images already in display range (tests, flat colours).
//   Reinhard   — c / (1 + c) (Reinhard et al. 2002, "Photographic Tone Reproduction", eq. 3,
//                applied per channel as Muth 2026 §3.4.10).
//   AcesFitted — Narkowicz 2016, "ACES Filmic Tone Mapping Curve": x = 0.6·c,
//                (x(2.51x + 0.03)) / (x(2.43x + 0.59) + 0.14), clamped to [0, 1]; a fit of the
//                ACES RRT+ODT luminance response (toe, shoulder, white at c ≈ 13). The default:
//                it keeps sunlit cloud tops (c ≈ 1-3) from clipping while keeping contrast.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "scene/white_balance.h"

namespace nph::scene {

/// An extra layer of a multi-layer OpenEXR (scene/passes.h): channels `name.C` for each C.
struct ImageLayer {
  std::string name;                   ///< e.g. "cloud"
  std::vector<std::string> channels;  ///< e.g. {"R", "G", "B", "A"} or {"Y"}
  std::vector<float> values;          ///< width·height·channels.size(), interleaved
  bool radiance = true;               ///< scaled by the exposure (a matte is not)
};

/// What the pixels are: light (exposure, tone curve and sRGB apply to PNG; exposure to EXR) or
/// data such as a matte (stored as it is: PNG codes round(255·v), EXR values).
enum class ImageContent { Radiance, Data };

/// Premultiplied linear RGBA, row 0 at the top, RGBA interleaved; depth (optional) per pixel [m].
/// A depth-only image (rgba empty, depth_m filled) writes an OpenEXR with just Z.
struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;     ///< width·height·4, or empty for a depth-only image
  std::vector<float> depth_m;  ///< empty or width·height (e.g. transmittance-weighted depth)
  ImageContent content = ImageContent::Radiance;
  std::vector<ImageLayer> layers{};  ///< OpenEXR only: extra layers after R G B A (Z)
};

enum class ToneCurve { Clamp, Reinhard, AcesFitted };

/// "clamp" | "reinhard" | "aces"; InputError otherwise.
ToneCurve toneCurveFromName(std::string_view name);
std::string_view toneCurveName(ToneCurve curve);
/// The curve on one linear channel value (≥ 0), result in [0, 1]; non-finite input counts as 0.
/// Computed by glsl/common/display.glsl compiled as C++: the viewer and the plugin API run the same
/// source on the GPU.
float applyToneCurve(float linear, ToneCurve curve);
/// sRGB transfer function (IEC 61966-2-1): linear [0, 1] -> encoded (glsl/common/display.glsl).
float linearToSrgb(float linear);

/// Default exposure (issue 12): with the sun an irradiance E = 1 and clouds in E·p units
/// (docs/rendering.md "Conventions"), a thick sunlit cloud top has a radiance of ≈ 0.2–0.3, the
/// sunlit ocean ≈ 0.02; +2.5 EV puts cloud tops just under the ACES curve's shoulder (white, not
/// clipped) and keeps shadowed sides and the ground readable (chosen by looking at the demo, before
/// and after pictures in docs/light-transport.md).
inline constexpr double kDefaultExposureEv = 2.5;

/// How the exposure is chosen (scene key `output.exposure`, docs/scene-file.md).
///   Fixed: 2^exposure_ev, whatever the light.
///   Sun:   exposure_ev is the exposure under the reference sun (35° high, where kDefaultExposureEv
///          was chosen), plus sunExposureOffsetEv for the frame's sun — a camera that follows the
///          daylight, so a golden-hour or twilight shot is not 3 EV darker than noon, and a
///          time-of-day animation brightens smoothly and the same in every render-farm chunk (it
///          depends on the sun alone, not on the picture).
enum class ExposureMode { Fixed = 0, Sun = 1 };
inline constexpr std::array<std::string_view, 2> kExposureModeNames{"fixed", "sun"};
/// The sun elevation at which ExposureMode::Sun adds nothing.
inline constexpr double kExposureReferenceSunElevationDeg = 35.0;
/// The EV that ExposureMode::Sun adds for a sun at `sun_elevation_deg`: half the drop in log₂ of
/// the horizontal illuminance 2 km up (atmosphere::horizontalIlluminance: direct sun + sky, Earth
///   atmosphere) against the reference sun,
///     ΔEV = ½·log₂(E_h(35°) / E_h(h)),   clamped to [−1, +4] EV.
/// Half: the eye adapts only partly, and a viewer expects a golden-hour scene darker than noon —
/// the full compensation (+3.3 EV at 5°) makes the haze of a low oblique view glare, none leaves
/// the clouds a dim grey (pictures in docs/atmosphere.md). Values: 60° −0.33, 35° 0, 20° +0.43,
/// 10° +1.03, 5° +1.65, 0° +3.1, −2° +3.9, the clamp +4 below (night: the sky, not the sun, lights it).
double sunExposureOffsetEv(double sun_elevation_deg);

struct ImageOutputOptions {
  double exposure_ev = 0.0;  ///< radiance scale 2^ev (EXR and PNG alike); scenes default to kDefaultExposureEv
  ToneCurve tone_curve = ToneCurve::AcesFitted;  ///< PNG only; EXR stays linear
  bool write_depth = true;                       ///< EXR: add Z when the image has depth
  /// EXR capDate ("YYYY:MM:DD hh:mm:ss"). Empty: OpenImageIO writes the wall-clock time, so two
  /// writes of one image differ; animations give the model time shown, for identical bytes.
  std::string date_time;
  /// Output colour through OpenColorIO (scene/colour_output.h, docs/colour.md): PNG codes for
  /// this display of the config (empty: the tone curve + sRGB above, bit for bit as before) and
  /// view (empty: the display's default). HDR displays (PQ, HLG) give 16-bit PNGs. EXR stays
  /// scene-linear.
  std::string display{};
  std::string view{};
  std::string ocio_config{};  ///< empty: scene::defaultOcioConfig()
  /// A camera's white balance [K] (scene/white_balance.h; issue 14, nineteenth session): the
  /// radiance times the gain g(T) of that temperature, EXR and PNG alike, with the exposure and
  /// before the tone curve. kNeutralWhiteBalanceK (the default) is no change, bit for bit. A grade,
  /// not physics: scene key output.white_balance_k.
  double white_balance_k = kNeutralWhiteBalanceK;
  /// Its tint, Duv (scene/white_balance.h): negative adds green, positive magenta; 0: none.
  double white_balance_duv = 0.0;
};

/// What every writer multiplies linear radiance by, per channel: 2^exposure_ev times the white
/// balance's gain (float, as the images are). The GPU paths (glsl/render/present.frag,
/// glsl/api/composite.frag) take it as their u_exposure_scale.
glm::vec3 radianceScale(const ImageOutputOptions& options);

/// The 8-bit straight-alpha sRGB codes of `image` (RGBA interleaved), as writePng stores them
/// when options.display is empty.
std::vector<std::uint8_t> encodeSrgb8(const RgbaImage& image, const ImageOutputOptions& options);
/// The straight-alpha code values in [0, 1] (RGBA interleaved) of `image` on options.display
/// through OpenColorIO, before quantisation (writePng: 8 bits, 16 for HDR displays).
std::vector<float> encodeDisplay(const RgbaImage& image, const ImageOutputOptions& options);

/// Throws UsageError for an inconsistent image, IoError when the file cannot be written; writePng
/// throws InputError for a depth-only image (a depth pass needs OpenEXR).
void writeExr(const RgbaImage& image, const std::string& path, const ImageOutputOptions& options = {});
void writePng(const RgbaImage& image, const std::string& path, const ImageOutputOptions& options = {});
/// By extension: .exr or .png (case-insensitive); InputError for anything else.
void writeImage(const RgbaImage& image, const std::string& path, const ImageOutputOptions& options = {});

}  // namespace nph::scene

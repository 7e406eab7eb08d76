#pragma once
// Compositing passes (AOVs) of one frame (issue 15), as a broadcast compositor takes them apart and
// lays them back together: the beauty is
//
//   beauty.rgb = cloud.rgb + (1 − cloud.a) · (ground.rgb + sky.rgb)
//
// exactly (glsl/render/clouds.comp writes all of them from the same values), so a compositor can
// swap the ground for the station's own map, grade the sky alone, or multiply its map by the
// cloud shadow matte.
//
//   beauty  the frame (RGBA, α = 1)
//   cloud   the premultiplied cloud layer (RGBA), aerial perspective included
//   ground  the lit ground alone (RGB), after the air's transmittance to the eye
//   sky     the sky alone (RGB): the sky's radiance, or the air's in-scattering in front of the ground
//   shadow  the cloud shadow matte at the ground point (one channel): the deep light map's
//           transmittance of sunlight, 1 = no shadow (also 1 where the ray meets no ground)
//   depth   Z (one channel, metres along the camera's view axis, as Nuke and Cycles read Z): the
//           cloud's transmittance-weighted mean depth; 10^10 m where no cloud is seen
//
// Multi-layer OpenEXR (one part) stores them as `R G B A Z` (beauty and depth) plus `cloud.R …`,
// `ground.R …`, `sky.R …`, `shadow.Y` (the layer.channel names Nuke, Fusion, Resolve and
// OpenImageIO split into layers). Separately, each is an image of its own (scene file
// `output.pass_files`, `nephele render --pass NAME=FILE`).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/output_image.h"

namespace nph::scene {

enum class Pass { Beauty, Cloud, Ground, Sky, Shadow, Depth };

/// "beauty" | "cloud" | "ground" | "sky" | "shadow" | "depth"; nullopt otherwise.
std::optional<Pass> passFromName(std::string_view name);
std::string_view passName(Pass pass);
/// The names above joined for messages: "beauty, cloud, ground, sky, shadow, depth".
std::string passNames();

/// The per-pixel passes besides the beauty and the cloud layer, row 0 at the top.
struct FramePasses {
  int width = 0, height = 0;
  std::vector<float> ground_rgb;  ///< width·height·3, linear radiance
  std::vector<float> sky_rgb;     ///< width·height·3, linear radiance
  std::vector<float> shadow;      ///< width·height, [0, 1]
  std::vector<float> depth_m;     ///< width·height, metres along the view axis
};

/// Z where no cloud is seen (the value Blender Cycles writes for its background; finite, so
/// compositors' depth operations stay defined). Mirrors kNoCloudDepth_m in clouds.comp.
inline constexpr float kNoCloudDepth_m = 1.0e10f;

/// One pass as an image of its own: beauty and cloud as rendered; ground and sky with α = 1;
/// shadow as a grey data image (written without exposure, tone curve or sRGB encoding: a matte is
/// a multiplier, not a colour); depth as a depth-only image (OpenEXR `Z`; PNG refuses it).
RgbaImage passImage(Pass pass, const RgbaImage& frame, const RgbaImage& cloud, const FramePasses& passes);

/// The frame with the passes as extra layers of one OpenEXR (cloud, ground, sky, shadow) and the
/// cloud depth as its Z channel; PNG writes only the beauty.
RgbaImage withPassLayers(const RgbaImage& frame, const RgbaImage& cloud, const FramePasses& passes);

/// The frame with the cloud depth as its Z channel only (scene file `output.depth`).
RgbaImage withDepth(const RgbaImage& frame, const FramePasses& passes);

}  // namespace nph::scene

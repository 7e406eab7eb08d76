#pragma once
// The "animation" section of a scene file and camera keyframe files (docs/scene-file.md): what
// `nephele animate` renders — a time range of the data, a frame rate, how fast model time runs,
// camera keyframes and whether the sun follows the clock. Parsed as strictly as the rest of the
// scene file; evaluated per frame by engine/animation.h.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene_file.h"

namespace nph::scene {

/// A frame rate as an exact rational: 59.94 is 60000/1001, so frame k lies at k·1001/60000 s
/// exactly and no rounding accumulates over a long sequence (SMPTE ST 12-1 rates).
struct FrameRate {
  std::int64_t num = 25;
  std::int64_t den = 1;

  double fps() const { return double(num) / double(den); }
  /// Seconds of video time at frame k: k·den/num.
  double secondsAt(std::int64_t frame) const { return double(frame) * double(den) / double(num); }
  /// "25", "60000/1001" (the NTSC family written as a decimal — 23.976, 29.97, 59.94, 119.88 — is
  /// the matching n·1000/1001), any other decimal with up to 3 digits after the point. InputError.
  static FrameRate parse(std::string_view text);
  std::string text() const;  ///< "25" or "60000/1001" (ffmpeg's -framerate syntax)
};

/// One end of the animated time range: a (fractional) timestep index or a UTC time.
struct TimePoint {
  std::optional<double> index;
  std::optional<std::string> utc;
};

enum class TimeInterpolation {
  Linear,  ///< fractional time cross-fades the two timesteps around it (engine/dataset.h TimeBlend)
  Step,    ///< each frame shows the last timestep at or before its time (held frames reuse the DLM)
  Motion   ///< fractional time blends both timesteps carried along their winds (engine/dataset.h
           ///< TimeBlend::Motion; the cross-fade where the data has no U, V or no times)
};

/// The names of TimeInterpolation, in one table for the scene files' "interpolation" and
/// `nephele animate --interpolation` (the first is the default).
inline constexpr std::array<std::pair<std::string_view, TimeInterpolation>, 3> kTimeInterpolationNames{
    {{"motion", TimeInterpolation::Motion}, {"linear", TimeInterpolation::Linear}, {"step", TimeInterpolation::Step}}};
/// The interpolation named `name` (kTimeInterpolationNames); UsageError listing the names otherwise.
TimeInterpolation timeInterpolationNamed(std::string_view name);

struct CameraKeyframe {
  double at_s = 0.0;  ///< video time of the keyframe
  CameraSpec camera;  ///< a preset (framed from the volume) or an explicit position/target, + fov
};

struct AnimationSpec {
  TimePoint from;  ///< default: the first timestep
  TimePoint to;    ///< default: the last timestep
  FrameRate fps;
  std::optional<double> duration_s;  ///< video length; or
  std::optional<double> speed;       ///< model seconds per video second
  TimeInterpolation interpolation = TimeInterpolation::Motion;
  /// The sun at each frame's UTC time (default: when sun.from_time without sun.time_utc).
  std::optional<bool> sun_follows_clock;
  double sun_step_s = 0.0;  ///< the sun's clock moves in steps of this many model seconds (0: every frame)
  std::vector<CameraKeyframe> keyframes;  ///< empty: the scene's camera throughout
  std::string keyframes_file;             ///< where the keyframes came from, for messages
};

/// Parses scene.animation_json (InputError naming the scene file and the JSON path); an empty
/// section gives the defaults. "keyframes_file" is read with loadCameraKeyframes.
AnimationSpec parseAnimation(const SceneDescription& scene);

/// A keyframe file: {"keyframes": [{"at_s": 0, "preset": "oblique"}, {"at_s": 4, "position_m": ...}]}.
/// Keyframes must be in increasing at_s order. InputError names the file and the JSON path.
std::vector<CameraKeyframe> loadCameraKeyframes(const std::string& path);

}  // namespace nph::scene

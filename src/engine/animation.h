#pragma once
// What frame k of an animation shows: model time, camera and sun, as a function of k alone, so
// that any sub-range of frames rendered anywhere (a render farm splitting one job) gives the same
// images as one run from the start.
//
// The clock. Frame k lies at video time k·den/num (scene::FrameRate, exact rational). Model time
// runs linearly in UTC from `from` to `to` over the video duration (or at `speed` model seconds per
// video second); frames run from k = 0 up to and including the last frame not past the end, so a
// 4 s animation at 25 fps has 101 frames and its last one shows `to` exactly. UTC maps to a
// fractional timestep index piecewise linearly between the dataset's timestep times (irregular
// output intervals are fine); the state between two timesteps is their blend in extinction
// (dataset.h; Thomann 2021 §5.5 interpolates hourly output the same way, Muth 2026 §5.2 leaves
// temporal blending as future work). Datasets without times run linearly in timestep index.
//
// The camera. Keyframes (presets resolved against the volume, or explicit position/target) are
// interpolated by a cubic Hermite spline with Catmull–Rom tangents for non-uniform keyframe times,
// m_i = (p_{i+1} − p_{i−1}) / (t_{i+1} − t_{i−1}) (one-sided at the ends): C¹, through every
// keyframe, no overshoot for evenly spaced keys. Position, target, up and field of view each follow
// their own spline; before the first and after the last keyframe the camera holds still.
//
// The sun. Fixed (the scene's) or following the clock: the solar position at the footprint
// centre at the frame's UTC time, optionally on a coarser clock (sun_step_s) so that frames
// between two steps share one deep light map (a sun change costs a DLM build, Nes 2008 §6.3).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/dataset.h"
#include "scene/animation_spec.h"
#include "scene/camera.h"
#include "scene/scene_setup.h"
#include "scene/solar_position.h"
#include "scene/sun.h"

namespace nph::engine {

struct AnimationFrame {
  std::int64_t index = 0;
  double video_s = 0.0;
  double time_index = 0.0;            ///< fractional timestep index for Session::setTime
  std::optional<scene::UtcTime> utc;  ///< model time, when the dataset has times
  scene::Camera camera;
  scene::Sun sun;
};

/// Cubic Hermite spline with Catmull–Rom tangents through (times[i], values[i]); clamped outside.
/// times strictly increasing, same length as values, at least one point.
template <class T>
T catmullRom(const std::vector<double>& times, const std::vector<T>& values, double t);

class AnimationPlan {
 public:
  /// `scene` and `prepared` (a Session's) must outlive the plan. InputError for a time range outside the data, a UTC
  /// range on data without times, a sun that follows the clock without times or without a place on Earth, or no
  /// duration for a single time.
  AnimationPlan(const scene::AnimationSpec& spec, const Dataset& dataset, const scene::SceneDescription& scene,
                const scene::PreparedScene& prepared);

  std::int64_t frameCount() const { return frame_count_; }
  const scene::FrameRate& fps() const { return spec_.fps; }
  double durationSeconds() const { return duration_s_; }
  double fromIndex() const { return from_index_; }
  double toIndex() const { return to_index_; }
  bool sunFollowsClock() const { return sun_follows_clock_; }
  /// Frame k (0 ≤ k < frameCount()).
  AnimationFrame frame(std::int64_t k) const;

 private:
  scene::UtcTime utcAt(double seconds) const;
  double indexAtSeconds(double seconds) const;
  double secondsAtIndex(double index) const;
  double resolve(const scene::TimePoint& p, double fallback, const char* what) const;

  scene::AnimationSpec spec_;
  const scene::SceneDescription* scene_ = nullptr;
  const scene::PreparedScene* prepared_ = nullptr;
  scene::UtcTime t0_;           ///< time of the first timestep
  std::vector<double> time_s_;  ///< per timestep, seconds since the first; empty without times
  std::size_t timestep_count_ = 0;
  double from_index_ = 0.0, to_index_ = 0.0;
  double duration_s_ = 0.0;
  std::int64_t frame_count_ = 1;
  bool sun_follows_clock_ = false;
  std::vector<double> key_times_;
  std::vector<glm::dvec3> key_position_, key_target_, key_up_;
  std::vector<double> key_fov_, key_near_, key_far_;
};

/// How a Session blends fractional time for a scene's interpolation (dataset.h TimeBlend): motion
/// for Motion; Linear and Step cross-fade (Step never asks for a fractional time: AnimationPlan
/// holds each timestep).
TimeBlend timeBlendFor(scene::TimeInterpolation interpolation);

}  // namespace nph::engine

#include "engine/animation.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/limits.h"
#include "scene/georeference.h"

namespace nph::engine {
namespace {

/// Slack for "is frame k's video time past the end": a frame exactly at the end is included even
/// when k·den/num rounds a few ulps above it.
constexpr double kFrameSlack_s = 1e-9;
/// Relative slack of "at or after a step" (a timestep or a sun step) against rounding.
constexpr double kStepSlack = 1e-9;

}  // namespace

template <class T>
T catmullRom(const std::vector<double>& times, const std::vector<T>& values, double t) {
  const std::size_t n = times.size();
  if (n == 0 || values.size() != n) throw UsageError("catmullRom: need as many values as times, at least one");
  if (n == 1 || t <= times.front()) return values.front();
  if (t >= times.back()) return values.back();
  const std::size_t i = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const auto tangent = [&](std::size_t j) -> T {
    const std::size_t lo = j == 0 ? 0 : j - 1, hi = std::min(j + 1, n - 1);
    return (values[hi] - values[lo]) * (1.0 / (times[hi] - times[lo]));
  };
  const double h = times[i + 1] - times[i];
  const double s = (t - times[i]) / h, s2 = s * s, s3 = s2 * s;
  const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = s3 - 2.0 * s2 + s;
  const double h01 = -2.0 * s3 + 3.0 * s2, h11 = s3 - s2;
  return values[i] * h00 + tangent(i) * (h10 * h) + values[i + 1] * h01 + tangent(i + 1) * (h11 * h);
}
template double catmullRom<double>(const std::vector<double>&, const std::vector<double>&, double);
template glm::dvec3 catmullRom<glm::dvec3>(const std::vector<double>&, const std::vector<glm::dvec3>&, double);

AnimationPlan::AnimationPlan(const scene::AnimationSpec& spec, const Dataset& dataset,
                             const scene::SceneDescription& scene, const scene::PreparedScene& prepared)
    : spec_(spec), scene_(&scene), prepared_(&prepared), timestep_count_(dataset.timestepCount()) {
  const std::string& file = scene.source_file;
  bool timed = true;
  for (const auto& t : dataset.times()) timed = timed && t.has_value();
  if (timed) {
    t0_ = *dataset.times().front();
    for (const auto& t : dataset.times()) time_s_.push_back(t->secondsSince(t0_));
    for (std::size_t i = 1; i < time_s_.size(); ++i) {
      if (!(time_s_[i] > time_s_[i - 1])) {
        throw InputError(fmt::format("{}: timesteps {} and {} are not in increasing time order ({}, {})",
                                     dataset.path(), i - 1, i, dataset.isoTime(i - 1), dataset.isoTime(i)));
      }
    }
  }
  from_index_ = resolve(spec.from, 0.0, "animation.from");
  to_index_ = resolve(spec.to, double(timestep_count_ - 1), "animation.to");
  if (to_index_ < from_index_) {
    throw InputError(fmt::format("{}: animation.to (timestep {:.3f}) lies before animation.from ({:.3f})", file,
                                 to_index_, from_index_));
  }
  if (spec.duration_s) {
    duration_s_ = *spec.duration_s;
  } else if (spec.speed) {
    if (time_s_.empty())
      throw InputError(fmt::format("{}: animation.speed needs timestep times; the data has none", file));
    duration_s_ = (secondsAtIndex(to_index_) - secondsAtIndex(from_index_)) / *spec.speed;
  } else {
    duration_s_ = to_index_ - from_index_;  // one video second per timestep interval
  }
  if (!(duration_s_ > 0.0) && spec.keyframes.size() > 1) duration_s_ = spec.keyframes.back().at_s;
  if (!(duration_s_ > 0.0)) {
    throw InputError(fmt::format("{}: the animation has no length: from and to are the same time; give "
                                 "animation.duration_s (nephele animate --duration)",
                                 file));
  }
  // Checked on the double, before the cast: animation.speed = 1e-10 or --duration 1e12 planned
  // 1.8e15 frames (and a cast beyond int64 is undefined behaviour).
  const double frames = std::floor(duration_s_ * spec.fps.fps() + kFrameSlack_s * spec.fps.fps()) + 1.0;
  if (!(frames <= double(limits::kMaxFrames))) {
    throw InputError(fmt::format("{}: the animation would have {:.3g} frames ({:.3g} s at {} frames/s), more than the "
                                 "limit of {} (limits::kMaxFrames, 10 h at 60 frames/s); check animation.speed / "
                                 "animation.duration_s (nephele animate --duration) or render a sub-range",
                                 file, frames, duration_s_, spec.fps.text(), limits::kMaxFrames));
  }
  frame_count_ = static_cast<std::int64_t>(frames);

  sun_follows_clock_ = spec.sun_follows_clock.value_or(scene.sun.from_time && !scene.sun.time_utc);
  if (sun_follows_clock_) {
    if (time_s_.empty())
      throw InputError(fmt::format("{}: the sun cannot follow the clock: the data has no times", file));
    if (!prepared.geo) {
      throw InputError(fmt::format("{}: the sun cannot follow the clock: the volume has no place on Earth (give "
                                   "centre_lonlat_deg)",
                                   file));
    }
  }

  for (const auto& key : spec.keyframes) {
    const scene::Camera c = scene::cameraFor(key.camera, prepared.frame, scene.output.width, scene.output.height);
    key_times_.push_back(key.at_s);
    key_position_.push_back(c.position_m);
    key_target_.push_back(c.target_m);
    key_up_.push_back(c.up);
    key_fov_.push_back(c.vertical_fov_deg);
    key_near_.push_back(c.near_m);
    key_far_.push_back(c.far_m);
  }
}

double AnimationPlan::resolve(const scene::TimePoint& p, double fallback, const char* what) const {
  const double last = double(timestep_count_ - 1);
  if (p.index) {
    if (*p.index > last) {
      throw InputError(fmt::format("{}: {}: timestep {} requested, the data has {} (0 to {})", scene_->source_file,
                                   what, *p.index, timestep_count_, timestep_count_ - 1));
    }
    return *p.index;
  }
  if (!p.utc) return fallback;
  if (time_s_.empty()) {
    throw InputError(
        fmt::format("{}: {}: a UTC time needs timestep times; the data has none", scene_->source_file, what));
  }
  const double s = scene::UtcTime::parse(*p.utc).secondsSince(t0_);
  constexpr double kSlack_s = 0.5;
  if (s < time_s_.front() - kSlack_s || s > time_s_.back() + kSlack_s) {
    throw InputError(fmt::format("{}: {}: {} lies outside the data ({} to {})", scene_->source_file, what, *p.utc,
                                 utcAt(time_s_.front()).iso8601(), utcAt(time_s_.back()).iso8601()));
  }
  return indexAtSeconds(s);
}

scene::UtcTime AnimationPlan::utcAt(double seconds) const { return t0_.plusSeconds(seconds); }

double AnimationPlan::indexAtSeconds(double s) const {
  if (time_s_.size() < 2 || s <= time_s_.front()) return 0.0;
  if (s >= time_s_.back()) return double(time_s_.size() - 1);
  const std::size_t i = std::size_t(std::upper_bound(time_s_.begin(), time_s_.end(), s) - time_s_.begin()) - 1;
  return double(i) + (s - time_s_[i]) / (time_s_[i + 1] - time_s_[i]);
}

double AnimationPlan::secondsAtIndex(double index) const {
  const TimeBracket b = bracketTime(index, time_s_.size());
  return time_s_[b.first] + b.weight * (time_s_[b.second] - time_s_[b.first]);
}

AnimationFrame AnimationPlan::frame(std::int64_t k) const {
  if (k < 0 || k >= frame_count_) {
    throw UsageError(
        fmt::format("frame {} requested, the animation has {} (0 to {})", k, frame_count_, frame_count_ - 1));
  }
  AnimationFrame f;
  f.index = k;
  f.video_s = spec_.fps.secondsAt(k);
  const double u = std::min(1.0, f.video_s / duration_s_);  // share of the model time range
  double clock_s = 0.0;                                     // model seconds since the first timestep
  if (time_s_.empty()) {
    f.time_index = from_index_ + u * (to_index_ - from_index_);
  } else {
    const double s0 = secondsAtIndex(from_index_), s1 = secondsAtIndex(to_index_);
    clock_s = s0 + u * (s1 - s0);
    f.time_index = indexAtSeconds(clock_s);
    f.utc = utcAt(clock_s);
  }
  if (spec_.interpolation == scene::TimeInterpolation::Step) {
    f.time_index = std::floor(f.time_index + kStepSlack);  // the last timestep at or before the frame
  }

  if (key_times_.empty()) {
    f.camera = prepared_->flat_camera;
  } else {
    scene::Camera& c = f.camera;
    c.width = scene_->output.width;
    c.height = scene_->output.height;
    c.position_m = catmullRom(key_times_, key_position_, f.video_s);
    c.target_m = catmullRom(key_times_, key_target_, f.video_s);
    c.up = glm::normalize(catmullRom(key_times_, key_up_, f.video_s));
    c.vertical_fov_deg = catmullRom(key_times_, key_fov_, f.video_s);
    c.near_m = *std::min_element(key_near_.begin(), key_near_.end());
    c.far_m = *std::max_element(key_far_.begin(), key_far_.end());
  }
  if (scene_->view == scene::ViewMode::Globe && prepared_->geo)
    f.camera = scene::globeCameraFrom(f.camera, *prepared_->geo);

  f.sun = prepared_->sun;
  if (sun_follows_clock_) {
    double sun_s = clock_s;
    if (spec_.sun_step_s > 0.0) {
      const double s0 = secondsAtIndex(from_index_);
      sun_s = s0 + std::floor((clock_s - s0) / spec_.sun_step_s + kStepSlack) * spec_.sun_step_s;
    }
    scene::SunSpec sun = scene_->sun;
    sun.from_time = true;
    sun.time_utc = utcAt(sun_s).iso8601();
    f.sun = scene::sunFor(sun, &*prepared_->geo, std::nullopt);
  }
  return f;
}

TimeBlend timeBlendFor(scene::TimeInterpolation interpolation) {
  return interpolation == scene::TimeInterpolation::Motion ? TimeBlend::Motion : TimeBlend::Linear;
}

}  // namespace nph::engine

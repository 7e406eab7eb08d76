#include "scene/animation_spec.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>

#include <fmt/format.h>

#include "core/error.h"
#include "core/input_file.h"
#include "core/json_limits.h"
#include "scene/json_object.h"
#include "scene/solar_position.h"

namespace nph::scene {
namespace {

using json_detail::json;
using json_detail::Object;
using json_detail::typeName;

constexpr double kMaxFps = 1000.0;
constexpr double kMaxVideoSeconds = 24.0 * 3600.0;
/// NTSC-family rates are n·1000/1001; a decimal within this of n/1.001 is taken to mean it
/// (59.94 · 1.001 = 59.99994).
constexpr double kNtscTolerance = 5e-3;

FrameRate reduced(std::int64_t num, std::int64_t den) {
  const std::int64_t g = std::gcd(num, den);
  return FrameRate{num / g, den / g};
}

TimePoint parseTimePoint(Object& o, std::string_view key) {
  TimePoint p;
  const json* v = o.get(key);
  if (!v) return p;
  if (v->is_number()) {
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < 0.0) o.fail(o.at(key), fmt::format("expected a timestep index ≥ 0, got {}", d));
    p.index = d;
  } else if (v->is_string()) {
    try {
      (void)UtcTime::parse(v->get<std::string>());
    } catch (const InputError& e) {
      o.fail(o.at(key), e.what());
    }
    p.utc = v->get<std::string>();
  } else {
    o.fail(o.at(key), "expected a timestep index or a UTC time string, got " + typeName(*v));
  }
  return p;
}

std::vector<CameraKeyframe> parseKeyframes(Object& o, std::string_view key) {
  std::vector<CameraKeyframe> keys;
  const json* v = o.get(key);
  if (!v) return keys;
  if (!v->is_array() || v->empty()) o.fail(o.at(key), "expected a non-empty array of keyframes, got " + typeName(*v));
  for (std::size_t i = 0; i < v->size(); ++i) {
    Object k((*v)[i], fmt::format("{}[{}]", o.at(key), i), o.file(), o.baseDir());
    CameraKeyframe kf;
    const auto at = k.optNumber("at_s", 0.0, kMaxVideoSeconds);
    if (!at) k.fail(k.at("at_s"), "required (video time of the keyframe in seconds)");
    kf.at_s = *at;
    if (!keys.empty() && kf.at_s <= keys.back().at_s) {
      k.fail(k.at("at_s"),
             fmt::format("keyframes must be in increasing time order ({} s follows {} s)", kf.at_s, keys.back().at_s));
    }
    json_detail::parseCameraObject(k, kf.camera);
    keys.push_back(kf);
  }
  return keys;
}

json parseFile(const std::string& path) {
  requireRegularFile(path, "a camera keyframe file (JSON)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the keyframe file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return json_limits::parse(text.str(), path, "the keyframe file", /*ignore_comments=*/true);
}

}  // namespace

FrameRate FrameRate::parse(std::string_view text) {
  const std::string s(text);
  const auto bad = [&](const std::string& why) -> FrameRate {
    throw InputError(fmt::format("frame rate \"{}\": {} (expected e.g. 25, 50, 59.94 or 60000/1001)", s, why));
  };
  if (const auto slash = s.find('/'); slash != std::string::npos) {
    std::int64_t num = 0, den = 0;
    std::size_t used_num = 0, used_den = 0;
    try {
      num = std::stoll(s.substr(0, slash), &used_num);
      den = std::stoll(s.substr(slash + 1), &used_den);
    } catch (const std::exception&) {
      return bad("not a fraction of two integers");
    }
    if (used_num != slash || used_den != s.size() - slash - 1) return bad("not a fraction of two integers");
    if (num <= 0 || den <= 0 || double(num) / double(den) > kMaxFps) return bad("out of range");
    return reduced(num, den);
  }
  double fps = 0.0;
  std::size_t used = 0;
  try {
    fps = std::stod(s, &used);
  } catch (const std::exception&) {
    return bad("not a number");
  }
  if (used != s.size() || !std::isfinite(fps) || fps <= 0.0 || fps > kMaxFps) return bad("out of range");
  if (fps == std::floor(fps)) return FrameRate{std::int64_t(fps), 1};
  const double ntsc = fps * 1.001;
  if (std::abs(ntsc - std::round(ntsc)) < kNtscTolerance) return reduced(std::int64_t(std::round(ntsc)) * 1000, 1001);
  const double milli = fps * 1000.0;
  if (std::abs(milli - std::round(milli)) > 1e-6) return bad("more than 3 decimals; give a fraction");
  return reduced(std::int64_t(std::round(milli)), 1000);
}

std::string FrameRate::text() const { return den == 1 ? fmt::format("{}", num) : fmt::format("{}/{}", num, den); }

std::vector<CameraKeyframe> loadCameraKeyframes(const std::string& path) {
  const json root = parseFile(path);
  const std::filesystem::path p(path);
  const std::string base = p.has_parent_path() ? p.parent_path().string() : std::string(".");
  Object top(root, "", path, base);
  (void)top.optString("description");
  auto keys = parseKeyframes(top, "keyframes");
  if (keys.empty()) top.fail("keyframes", "required (an array of camera keyframes)");
  top.finish();
  return keys;
}

TimeInterpolation timeInterpolationNamed(std::string_view name) {
  std::string list;
  for (const auto& [n, value] : kTimeInterpolationNames) {
    if (n == name) return value;
    list += fmt::format("{}{}", list.empty() ? "" : ", ", n);
  }
  throw UsageError(fmt::format("interpolation \"{}\": expected one of {}", name, list));
}

AnimationSpec parseAnimation(const SceneDescription& scene) {
  AnimationSpec a;
  if (scene.animation_json.empty()) return a;
  const json root = json_limits::parse(scene.animation_json, scene.source_file, "the animation section");
  Object o(root, "animation", scene.source_file, scene.base_dir);
  a.from = parseTimePoint(o, "from");
  a.to = parseTimePoint(o, "to");
  if (const json* f = o.get("fps")) {
    if (!f->is_number() && !f->is_string())
      o.fail(o.at("fps"), "expected a number or a string like \"60000/1001\", got " + typeName(*f));
    try {
      a.fps = FrameRate::parse(f->is_string() ? f->get<std::string>() : f->dump());
    } catch (const InputError& e) {
      o.fail(o.at("fps"), e.what());
    }
  }
  a.duration_s = o.optNumber("duration_s", 0.0, kMaxVideoSeconds);
  a.speed = o.optNumber("speed", 0.0, std::numeric_limits<double>::max());
  if (a.duration_s && a.speed) o.fail(o.at("speed"), "give either duration_s or speed, not both");
  if ((a.duration_s && *a.duration_s <= 0.0) || (a.speed && *a.speed <= 0.0)) {
    o.fail(o.at(a.speed ? "speed" : "duration_s"), "expected a positive number");
  }
  a.interpolation = o.choice("interpolation", kTimeInterpolationNames.front().second, kTimeInterpolationNames);
  if (o.get("sun_follows_clock")) a.sun_follows_clock = o.boolean("sun_follows_clock", false);
  a.sun_step_s = o.number("sun_step_s", 0.0, 0.0, 86400.0);
  a.keyframes = parseKeyframes(o, "camera_keyframes");
  const std::string file = o.path("keyframes_file", false);
  if (!file.empty()) {
    if (!a.keyframes.empty())
      o.fail(o.at("keyframes_file"), "give either camera_keyframes or keyframes_file, not both");
    a.keyframes = loadCameraKeyframes(file);
    a.keyframes_file = file;
  }
  o.finish();
  return a;
}

}  // namespace nph::scene

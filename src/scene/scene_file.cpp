#include "scene/scene_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"
#include "core/json_limits.h"
#include "core/limits.h"
#include "core/log.h"
#include "scene/colour_output.h"
#include "scene/json_object.h"
#include "scene/solar_position.h"

namespace nph::scene {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

constexpr int kMaxImageSide = 16384;  ///< largest output/basemap side accepted (GL_MAX_TEXTURE_SIZE on llvmpipe)
constexpr double kMaxExaggeration = 1000.0;
/// Explicit camera coordinates beyond 1e9 m leave float positions without precision in the ray
/// caster (a position of 1e300 m rendered a blank image).
constexpr double kMaxCameraCoordinate_m = 1e9;
/// sin of the smallest angle accepted between a camera's up vector and its view direction
/// (1e-6 rad: below, the image plane orientation is numerically undefined; exactly parallel
/// gave NaN and a blank image).
constexpr double kMinUpSine = 1e-6;
/// Largest sun colour component: the colour is a relative tint (intensity carries brightness);
/// 1e300 overflowed float radiance to Inf and rendered a blank image.
constexpr double kMaxSunColour = 100.0;

using json_detail::Object;
using json_detail::typeName;

// The keys of quality.overrides are the quality rows of the knob table (lighting/knobs.h), with
// their ranges; booleans are JSON true/false.
/// The keys of `o` that are knobs of `group` (lighting/knobs.h) into `q` (QualitySettings for
/// quality.overrides, StyleSettings for style), with the table's ranges and choices.
template <typename Settings>
void parseKnobs(Object& o, lighting::KnobGroup group, Settings& q) {
  for (const lighting::Knob& k : lighting::knobs()) {
    if (k.group() != group) continue;
    switch (k.type()) {
      case lighting::KnobType::Number: k.set(q, o.number(k.name, k.get(q), k.min, k.max)); break;
      case lighting::KnobType::Integer: k.set(q, o.integer(k.name, int(k.get(q)), int(k.min), int(k.max))); break;
      case lighting::KnobType::Boolean: k.set(q, o.boolean(k.name, k.get(q) != 0.0) ? 1.0 : 0.0); break;
      case lighting::KnobType::Choice: {
        const auto name = o.optString(k.name);
        if (!name) break;
        const auto it = std::find(k.choices.begin(), k.choices.end(), *name);
        if (it == k.choices.end()) {
          o.fail(o.at(k.name), fmt::format("expected {}, got \"{}\"", lighting::choiceList(k, " or "), *name));
        }
        k.set(q, double(it - k.choices.begin()));
        break;
      }
    }
  }
}

}  // namespace

namespace json_detail {

void parseCameraObject(Object& c, CameraSpec& cam) {
  const auto preset = c.optString("preset");
  cam.position_m = c.optVec3("position_m");
  cam.target_m = c.optVec3("target_m");
  const auto up = c.optVec3("up");
  if (up) {
    if (glm::length(*up) < 1e-9) c.fail(c.at("up"), "expected a non-zero vector");
    cam.up = glm::normalize(*up);
  }
  cam.fov_deg = c.number("fov_deg", cam.fov_deg, 1.0, 170.0);
  cam.azimuth_deg = c.optNumber("azimuth_deg", -360.0, 360.0);
  cam.elevation_deg = c.optNumber("elevation_deg", 1.0, 90.0);
  cam.distance_scale = c.number("distance_scale", cam.distance_scale, 0.01, 100.0);
  if (cam.position_m || cam.target_m) {
    if (!cam.position_m || !cam.target_m) {
      c.fail(c.at(cam.position_m ? "target_m" : "position_m"),
             "required with the other (an explicit camera needs position_m and target_m)");
    }
    if (preset) c.fail(c.at("preset"), "give either a preset or position_m/target_m, not both");
    // Degenerate cameras rendered a blank image with exit 0 (issue #18): points so far away that
    // float positions lose all precision, and an up vector along the view direction (no image
    // plane orientation).
    for (const char* key : {"position_m", "target_m"}) {
      const glm::dvec3& p = std::string_view(key) == "position_m" ? *cam.position_m : *cam.target_m;
      if (glm::any(glm::greaterThan(glm::abs(p), glm::dvec3(kMaxCameraCoordinate_m)))) {
        c.fail(c.at(key), fmt::format("expected coordinates within +-{} m (the Moon is at 3.8e8 m), got ({}, {}, {})",
                                      kMaxCameraCoordinate_m, p.x, p.y, p.z));
      }
    }
    if (glm::length(*cam.target_m - *cam.position_m) < 1e-6) {
      c.fail(c.at("target_m"), "expected a point different from position_m");
    }
    const glm::dvec3 view = glm::normalize(*cam.target_m - *cam.position_m);
    if (glm::length(glm::cross(view, cam.up)) < kMinUpSine) {
      c.fail(c.at(up ? "up" : "target_m"),
             fmt::format("up ({}, {}, {}) is parallel to the view direction ({:.6f}, {:.6f}, {:.6f}); expected an up "
                         "vector at an angle to it",
                         cam.up.x, cam.up.y, cam.up.z, view.x, view.y, view.z));
    }
    cam.preset.reset();
  } else if (up) {
    c.fail(c.at("up"), "only used with position_m/target_m (presets choose their own up)");
  }
  if (!cam.position_m && preset) {
    if (*preset == "overview") cam.preset = CameraPreset::Overview;
    else if (*preset == "oblique") cam.preset = CameraPreset::Oblique;
    else if (*preset == "top") cam.preset = CameraPreset::Top;
    else c.fail(c.at("preset"), fmt::format("expected \"overview\", \"oblique\" or \"top\", got \"{}\"", *preset));
  }
  c.finish();
}

}  // namespace json_detail

SceneDescription parseSceneText(std::string_view text, const std::string& name, const std::string& base_dir) {
  const json root = json_limits::parse(text, name, "the scene file", /*ignore_comments=*/true);
  SceneDescription s;
  s.source_file = name;
  s.base_dir = base_dir;
  Object top(root, "", name, base_dir);
  (void)top.optString("description");  // free text for humans

  if (auto d = top.optObject("data")) {
    DataSpec data;
    data.path = d->path("path", true);
    const bool hasStep = d->has("timestep");
    data.timestep = d->integer("timestep", 0, 0, std::numeric_limits<int>::max());
    data.time_utc = d->optString("time_utc");
    if (data.time_utc) {
      if (hasStep) d->fail(d->at("time_utc"), "give either timestep or time_utc, not both");
      try {
        (void)UtcTime::parse(*data.time_utc);
      } catch (const InputError& e) {
        d->fail(d->at("time_utc"), e.what());
      }
    }
    d->finish();
    s.data = data;
  }

  if (auto c = top.optObject("camera")) json_detail::parseCameraObject(*c, s.camera);

  if (auto u = top.optObject("sun")) {
    SunSpec& sun = s.sun;
    sun.from_time = u->boolean("from_time", false);
    sun.time_utc = u->optString("time_utc");
    const auto az = u->optNumber("azimuth_deg", -360.0, 360.0);
    const auto el = u->optNumber("elevation_deg", -90.0, 90.0);
    if (sun.from_time && (az || el)) {
      u->fail(u->at(az ? "azimuth_deg" : "elevation_deg"), "not allowed with \"from_time\": true");
    }
    if (sun.time_utc) {
      if (!sun.from_time) u->fail(u->at("time_utc"), "only used with \"from_time\": true");
      try {
        (void)UtcTime::parse(*sun.time_utc);
      } catch (const InputError& e) {
        u->fail(u->at("time_utc"), e.what());
      }
    }
    sun.azimuth_deg = az.value_or(sun.azimuth_deg);
    sun.elevation_deg = el.value_or(sun.elevation_deg);
    if (auto col = u->optVec3("colour")) {
      if (col->x < 0.0 || col->y < 0.0 || col->z < 0.0 || col->x > kMaxSunColour || col->y > kMaxSunColour ||
          col->z > kMaxSunColour) {
        u->fail(u->at("colour"), fmt::format("expected components in [0, {}] (a tint; intensity sets the "
                                             "brightness)",
                                             kMaxSunColour));
      }
      sun.colour = *col;
    }
    sun.intensity = u->number("intensity", sun.intensity, 0.0, 1e6);
    u->finish();
  }

  if (const json* b = top.get("basemap"); b && !b->is_null()) {
    Object o(*b, "basemap", name, base_dir);
    BasemapSpec bm;
    bm.path = o.path("path", true);
    bm.margin = o.number("margin", bm.margin, 0.0, 10.0);
    bm.pixels_long_side = o.integer("pixels_long_side", bm.pixels_long_side, 16, kMaxImageSide);
    bm.night_lights = o.path("night_lights", false);
    o.finish();
    s.basemap = bm;
  }

  if (const json* t = top.get("terrain"); t && !t->is_null()) {
    Object o(*t, "terrain", name, base_dir);
    TerrainSpec terrain;
    terrain.dem = o.path("dem", true);
    o.finish();
    s.terrain = terrain;
  }

  if (const json* q = top.get("quality")) {
    if (q->is_string()) {
      try {
        s.quality = lighting::qualityPreset(q->get<std::string>());
      } catch (const InputError& e) {
        top.fail("quality", e.what());
      }
    } else {
      Object o(*q, "quality", name, base_dir);
      const std::string presetName = o.optString("preset").value_or("broadcast");
      try {
        s.quality = lighting::qualityPreset(presetName);
      } catch (const InputError& e) {
        o.fail("quality.preset", e.what());
      }
      if (auto ov = o.optObject("overrides")) {
        parseKnobs(*ov, lighting::KnobGroup::Quality, s.quality);
        ov->finish();
      }
      o.finish();
    }
  }

  // Style: how the scene looks rather than how accurately it is computed (phase asymmetries, sky
  // light, ground albedo, the atmosphere); the knob table's style rows, e.g. "style": {"atmosphere": false}.
  if (auto o = top.optObject("style")) {
    parseKnobs(*o, lighting::KnobGroup::Style, s.style);
    o->finish();
  }

  if (const json* a = top.get("animation")) {
    (void)Object(*a, "animation", name, base_dir);  // must be an object; parsed by parseAnimation
    s.animation_json = a->dump();
  }

  if (auto o = top.optObject("output")) {
    OutputSpec& out = s.output;
    // An image path: a string ending in .png or .exr, relative to the scene file's folder.
    const auto imagePath = [&](const std::string& where, const json& e) {
      if (!e.is_string()) o->fail(where, "expected a string, got " + typeName(e));
      std::string ext = fs::path(e.get<std::string>()).extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(),
                     [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
      if (ext != ".png" && ext != ".exr")
        o->fail(where, "expected a .png or .exr file, got \"" + e.get<std::string>() + "\"");
      const fs::path path(e.get<std::string>());
      return path.is_absolute() || base_dir.empty() ? path.string()
                                                    : (fs::path(base_dir) / path).lexically_normal().string();
    };
    if (const json* p = o->get("paths")) {
      if (!p->is_array()) o->fail(o->at("paths"), "expected an array of file paths, got " + typeName(*p));
      for (std::size_t i = 0; i < p->size(); ++i)
        out.paths.push_back(imagePath(fmt::format("{}[{}]", o->at("paths"), i), (*p)[i]));
    }
    out.passes = o->boolean("passes", false);
    if (const json* p = o->get("pass_files")) {
      if (!p->is_object()) o->fail(o->at("pass_files"), "expected an object {\"pass\": \"file\"}, got " + typeName(*p));
      for (const auto& [pass_name, file] : p->items()) {
        const std::string where = fmt::format("{}.{}", o->at("pass_files"), pass_name);
        const auto pass = passFromName(pass_name);
        if (!pass) o->fail(where, fmt::format("unknown pass '{}': expected one of {}", pass_name, passNames()));
        const std::string path = imagePath(where, file);
        if (*pass == Pass::Depth && fs::path(path).extension() != ".exr") {
          o->fail(where, "the depth pass holds distances, not colours: expected an .exr file");
        }
        out.pass_files.emplace_back(*pass, path);
      }
    }
    out.width = o->integer("width", out.width, 1, kMaxImageSide);
    out.height = o->integer("height", out.height, 1, kMaxImageSide);
    if (std::uint64_t(out.width) * std::uint64_t(out.height) > limits::kMaxImagePixels) {
      o->fail(o->at("width"), fmt::format("{} x {} pixels is more than the limit of {} (limits::kMaxImagePixels: a "
                                          "16384^2 image ran out of GL memory after 565 s)",
                                          out.width, out.height, limits::kMaxImagePixels));
    }
    out.image.exposure_ev = o->number("exposure_ev", kDefaultExposureEv, -20.0, 20.0);
    if (const auto mode = o->optString("exposure")) {
      const auto it = std::find(kExposureModeNames.begin(), kExposureModeNames.end(), *mode);
      if (it == kExposureModeNames.end()) {
        o->fail(o->at("exposure"), fmt::format("unknown exposure '{}': expected \"fixed\" (2^exposure_ev) or \"sun\" "
                                               "(exposure_ev at a 35° sun, following the daylight)",
                                               *mode));
      }
      out.exposure = ExposureMode(it - kExposureModeNames.begin());
    }
    // A camera's white balance (scene/white_balance.h): a grade on the radiance, neutral by default.
    out.image.white_balance_k =
        o->number("white_balance_k", kNeutralWhiteBalanceK, kMinWhiteBalanceK, kMaxWhiteBalanceK);
    out.image.white_balance_duv = o->number("white_balance_duv", 0.0, -kMaxWhiteBalanceDuv, kMaxWhiteBalanceDuv);
    if (const auto curve = o->optString("tone_curve")) {
      try {
        out.image.tone_curve = toneCurveFromName(*curve);
      } catch (const InputError& e) {
        o->fail(o->at("tone_curve"), e.what());
      }
    }
    out.image.write_depth = o->boolean("depth", false);
    // Output colour through OpenColorIO (docs/colour.md); checked now, so a typo fails before rendering.
    if (const auto config = o->optString("ocio_config")) {
      const fs::path p(*config);
      out.image.ocio_config =
          p.is_absolute() || base_dir.empty() ? p.string() : (fs::path(base_dir) / p).lexically_normal().string();
    }
    if (const auto display = o->optString("display")) out.image.display = *display;
    if (const auto view = o->optString("view")) out.image.view = *view;
    if (out.image.display.empty() && (!out.image.view.empty() || !out.image.ocio_config.empty())) {
      o->fail(o->at(out.image.view.empty() ? "ocio_config" : "view"),
              "needs output.display (e.g. \"sRGB\", \"Rec.2100-PQ\")");
    }
    if (!out.image.display.empty()) {
      try {
        (void)DisplayOutput::open(out.image.ocio_config, out.image.display, out.image.view);
      } catch (const InputError& e) {
        o->fail(o->at("display"), e.what());
      }
    }
    o->finish();
  }

  s.height_exaggeration = top.number("height_exaggeration", 1.0, 0.01, kMaxExaggeration);
  s.view = top.choice("view", ViewMode::Flat, {{"flat", ViewMode::Flat}, {"globe", ViewMode::Globe}});
  if (const auto off = top.optNumbers<2>("lonlat_offset_deg")) {
    if (std::abs((*off)[0]) > 180.0 || std::abs((*off)[1]) > 90.0) {
      top.fail("lonlat_offset_deg", "expected [dlon, dlat] within ±180° and ±90°");
    }
    s.lonlat_offset = {(*off)[0], (*off)[1]};
  }
  if (const auto centre = top.optNumbers<2>("centre_lonlat_deg")) {
    if (std::abs((*centre)[0]) > 360.0 || std::abs((*centre)[1]) > 90.0) {
      top.fail("centre_lonlat_deg", "expected [lon, lat] with |lat| ≤ 90");
    }
    s.centre_if_cartesian = LonLat{(*centre)[0], (*centre)[1]};
  }
  top.finish();
  return s;
}

ImageOutputOptions imageOptionsFor(const OutputSpec& spec, double sun_elevation_deg) {
  ImageOutputOptions o = spec.image;
  if (spec.exposure == ExposureMode::Sun) o.exposure_ev += sunExposureOffsetEv(sun_elevation_deg);
  return o;
}

RgbaImage outputFrame(const OutputSpec& spec, const RgbaImage& frame, const RgbaImage& cloud,
                      const FramePasses* passes) {
  if (!spec.wantsPasses()) return frame;
  if (!passes) throw UsageError("the scene asks for compositing passes but the renderer made none");
  if (spec.passes) return withPassLayers(frame, cloud, *passes);
  return spec.image.write_depth ? withDepth(frame, *passes) : frame;
}

SceneDescription loadSceneFile(const std::string& path) {
  requireRegularFile(path, "a scene file (JSON)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the scene file", path));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{}: cannot read the scene file", path));
  const fs::path p(path);
  return parseSceneText(text.str(), path, p.has_parent_path() ? p.parent_path().string() : std::string("."));
}

Camera cameraFor(const CameraSpec& spec, const volume::VolumeFrame& frame, int width, int height) {
  if (width <= 0 || height <= 0) throw UsageError("cameraFor: image size must be positive");
  if (std::uint64_t(width) * std::uint64_t(height) > limits::kMaxImagePixels) {
    throw UsageError(fmt::format("image of {} x {} pixels: more than the limit of {} pixels (limits::kMaxImagePixels; "
                                 "a 16384^2 image ran out of GL memory after 565 s)",
                                 width, height, limits::kMaxImagePixels));
  }
  Camera cam;
  cam.width = width;
  cam.height = height;
  cam.vertical_fov_deg = spec.fov_deg;
  if (!spec.preset) {
    if (!spec.position_m || !spec.target_m) throw UsageError("cameraFor: explicit camera without position/target");
    cam.position_m = *spec.position_m;
    cam.target_m = *spec.target_m;
    cam.up = spec.up;
    return cam;
  }
  // Bounding sphere of the volume's box; the camera looks at the centre of its footprint at half
  // the volume's height, from a distance at which the sphere fits the narrower field of view.
  const glm::dvec3 size = frame.size_m();
  const glm::dvec3 target = frame.min_m() + glm::dvec3(0.5 * size.x, 0.5 * size.y, 0.5 * size.z);
  const double radius = 0.5 * glm::length(size);
  const double vfov = glm::radians(spec.fov_deg);
  const double hfov = 2.0 * std::atan(std::tan(0.5 * vfov) * double(width) / double(height));
  const double fit = radius / std::sin(0.5 * std::min(vfov, hfov));
  double azimuth = 180.0, elevation = 55.0, closer = 1.0;
  glm::dvec3 up{0.0, 0.0, 1.0};
  switch (*spec.preset) {
    case CameraPreset::Overview: break;
    case CameraPreset::Oblique:
      azimuth = 200.0;
      elevation = 20.0;
      closer = 0.8;  // the far side may leave the frame: the near side is what the eye reads
      break;
    case CameraPreset::Top:
      elevation = 90.0;
      up = {0.0, 1.0, 0.0};  // north up
      break;
  }
  azimuth = spec.azimuth_deg.value_or(azimuth);
  elevation = spec.elevation_deg.value_or(elevation);
  const double distance = fit * closer * spec.distance_scale;
  const double az = glm::radians(azimuth), el = glm::radians(elevation);
  const glm::dvec3 toCamera{std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)};
  cam.target_m = target;
  cam.position_m = target + distance * toCamera;
  if (elevation > 89.0) {
    // Looking (almost) straight down: "up" in the image is the horizontal direction away from
    // the camera's azimuth (north for the default), never the view direction itself.
    up = *spec.preset == CameraPreset::Top && !spec.azimuth_deg ? glm::dvec3{0.0, 1.0, 0.0}
                                                                : glm::dvec3{-std::sin(az), -std::cos(az), 0.0};
  }
  cam.up = up;
  cam.near_m = std::max(10.0, 0.01 * distance);
  cam.far_m = distance + 4.0 * radius + 1.0e5;
  return cam;
}

Sun sunFor(const SunSpec& spec, const SceneGeoreference* geo, const geo::OptionalUtcTime& data_time) {
  Sun s;
  s.colour = spec.colour;
  s.intensity = spec.intensity;
  if (!spec.from_time) {
    s.azimuth_deg = spec.azimuth_deg;
    s.elevation_deg = spec.elevation_deg;
    return s;
  }
  const geo::OptionalUtcTime time = spec.time_utc ? UtcTime::parse(*spec.time_utc) : data_time;
  if (!time) {
    throw InputError("sun.from_time: the data carries no time and sun.time_utc is not given");
  }
  if (geo == nullptr) {
    throw InputError("sun.from_time: the volume has no place on Earth (Cartesian grid without "
                     "centre_lonlat_deg), so the sun's position cannot be computed");
  }
  const glm::dvec3 size = geo->frame().size_m();
  const glm::dvec2 centre{0.5 * size.x, 0.5 * size.y};
  const LonLat ll = geo->lonLatFromWorld(centre);
  const Sun geographic = sunAt(*time, ll.lon_deg, ll.lat_deg);
  s.azimuth_deg = geographic.azimuth_deg;
  s.elevation_deg = geographic.elevation_deg;
  if (s.elevation_deg <= 0.0) {
    log::warn("sun at {} over lon {:.2f} lat {:.2f} is {:.1f}° below the horizon: the clouds will be "
              "lit only by the ambient sky",
              time->iso8601(), ll.lon_deg, ll.lat_deg, -s.elevation_deg);
  }
  return geo->sunInWorld(s, centre);
}

}  // namespace nph::scene

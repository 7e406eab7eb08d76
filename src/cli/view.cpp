// `nephele view`: an interactive window (GLFW) on a scene file, through engine::Session — the
// same volume, DLM and ray caster as `nephele render`. Each frame: Session::dispatch() of the
// current camera into the renderer's frame texture, then a full-screen pass
// (glsl/render/present.frag: exposure, tone curve, sRGB) blits it to the window.
// Progressive: while the camera moves or the animation plays, frames are ray cast at 1/kPreviewDivisor
// of the resolution on each axis and scaled up; one full-resolution frame follows when it stops,
// then, while everything stays still, one more sample per pixel at a time (refine()) up to
// kRefineSamples: the idle view converges to the anti-aliased, jitter-free picture. The moving
// preview frames accumulate their jitter, reprojected (render/raycast/temporal_accumulation.h).
// Non-interactive use (tests, scripts): --frames N renders N full-resolution frames and exits,
// --screenshot PATH writes the window's last frame (8-bit sRGB PNG, what the window shows).
#define GLFW_INCLUDE_NONE  // GL comes from the loader (render/gl/gl.h)
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "cli/commands.h"
#include "cli/quick_look.h"
#include "core/error.h"
#include "core/log.h"
#include "engine/dataset.h"
#include "engine/session.h"
#include "lighting/knobs.h"
#include "render/gl/context.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "scene/image_codec.h"
#include "scene/scene_file.h"

namespace nph::cli {
namespace {

constexpr int kPreviewDivisor = 2;       // progressive preview: half resolution per axis
constexpr double kSettleSeconds = 0.25;  // full resolution once nothing moved for this long
constexpr int kRefineSamples = 16;       // a still frame is refined up to this many samples per pixel
// While moving, the preview frames accumulate their jitter over up to this many frames, reprojected
// (RenderSettings::temporal_history; `--temporal N`; docs/rendering.md "Temporal accumulation": 4
// measured the least error for a camera orbiting by a pixel per frame, 8 and more lag behind).
constexpr int kMovingHistory = 4;
constexpr double kOrbitDegPerPixel = 0.3;
constexpr double kZoomPerScrollStep = 0.9;
constexpr double kScrubStep = 0.1;  // [ ] : a tenth of a timestep
constexpr double kSunStep_deg = 5.0;

constexpr const char* kHelp = "nephele view\n"
                              "  left drag      orbit            right drag   pan            wheel   zoom\n"
                              "  left / right   previous / next timestep      [ / ]   scrub by 0.1 timestep\n"
                              "  space          play / pause                  + / -   playback speed x2 / /2\n"
                              "  A / D          sun azimuth -/+ 5 deg         W / S   sun elevation +/- 5 deg\n"
                              "  Q              quality preset (draft, broadcast, reference)\n"
                              "  H              this help                     Esc     quit\n";

struct ViewOptions {
  std::string scene;
  int width = 1280, height = 720;
  int frames = 0;  ///< > 0: render this many frames and exit
  std::string screenshot;
  int timestep = -1;
  int temporal = kMovingHistory;  ///< RenderSettings::temporal_history of the moving preview (0: off)
};

/// Orbit camera around a target: azimuth clockwise from north, elevation above the local horizon,
/// in the local east/north/up frame of the target (flat: the world axes; globe: ECEF at the target).
struct Orbit {
  glm::dvec3 target{0.0};
  double distance_m = 1.0, azimuth_deg = 180.0, elevation_deg = 45.0;
  bool globe = false;

  glm::dmat3 enu() const {
    if (!globe) return glm::dmat3(1.0);
    const glm::dvec3 up = glm::normalize(target);
    glm::dvec3 east = glm::cross(glm::dvec3(0.0, 0.0, 1.0), up);
    east = glm::length(east) > 1e-9 ? glm::normalize(east) : glm::dvec3(1.0, 0.0, 0.0);
    return glm::dmat3(east, glm::cross(up, east), up);
  }
  static Orbit from(const scene::Camera& c, bool globe) {
    Orbit o;
    o.globe = globe;
    o.target = c.target_m;
    const glm::dmat3 f = o.enu();
    const glm::dvec3 off = c.position_m - c.target_m;
    o.distance_m = glm::length(off);
    o.elevation_deg = glm::degrees(std::asin(std::clamp(glm::dot(off, f[2]) / o.distance_m, -1.0, 1.0)));
    const glm::dvec3 h = std::abs(o.elevation_deg) > 89.9 ? -c.up : off;  // straight down: up = −h
    o.azimuth_deg = glm::degrees(std::atan2(glm::dot(h, f[0]), glm::dot(h, f[1])));
    return o;
  }
  void apply(scene::Camera& c) const {
    const glm::dmat3 f = enu();
    const double az = glm::radians(azimuth_deg), el = glm::radians(elevation_deg);
    const glm::dvec3 h = std::sin(az) * f[0] + std::cos(az) * f[1];
    c.target_m = target;
    c.position_m = target + distance_m * (std::cos(el) * h + std::sin(el) * f[2]);
    c.up = std::cos(el) * f[2] - std::sin(el) * h;  // perpendicular to the view direction
  }
};

class Viewer {
 public:
  Viewer(gl::Context& ctx, engine::Session& session, const ViewOptions& o)
      : ctx_(ctx),
        session_(session),
        window_(ctx.window()),
        opts_(o),
        present_(gl::Program::graphics("render/fullscreen.vert", "render/present.frag")),
        sampler_(gl::Sampler::create(GL_LINEAR, GL_CLAMP_TO_EDGE)),
        vao_(gl::VertexArray::create()) {
    camera_ = session.prepared().camera;
    orbit_ = Orbit::from(camera_, session.scene().view == scene::ViewMode::Globe);
    sun_ = session.sun();
    time_ = session.time();
    const auto& presetName = session.quality().preset;
    for (std::size_t i = 0; i < lighting::kPresetNames.size(); ++i) {
      if (presetName == lighting::kPresetNames[i]) quality_ = i;
    }
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
      static_cast<Viewer*>(glfwGetWindowUserPointer(w))->onKey(key, action, mods);
    });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
      static_cast<Viewer*>(glfwGetWindowUserPointer(w))->onButton(button, action);
    });
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
      static_cast<Viewer*>(glfwGetWindowUserPointer(w))->onCursor(x, y);
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
      static_cast<Viewer*>(glfwGetWindowUserPointer(w))->onScroll(dy);
    });
  }

  int run() {
    if (opts_.frames <= 0) std::fputs(kHelp, stdout);
    double last = glfwGetTime();
    for (int frame = 0; !glfwWindowShouldClose(window_); ++frame) {
      const double now = glfwGetTime();
      if (playing_) setTime(time_ + speed_ * (now - last));
      last = now;
      const bool moving = playing_ || now - last_input_ < kSettleSeconds;
      const bool batch = opts_.frames > 0;
      if (batch || moving || !full_res_shown_) {
        draw(batch || !moving ? 1 : kPreviewDivisor);
        full_res_shown_ = batch || !moving;
        if (batch && frame + 1 >= opts_.frames) {
          if (!opts_.screenshot.empty()) screenshot(opts_.screenshot);
          ctx_.swapBuffers();
          break;
        }
        ctx_.swapBuffers();
        glfwPollEvents();
      } else if (samples_shown_ < kRefineSamples) {
        refine();  // still: one more sample per pixel into the frame shown
        ctx_.swapBuffers();
        glfwPollEvents();
      } else {
        glfwWaitEventsTimeout(0.1);  // idle: nothing to redraw until an event
      }
    }
    return kExitOk;
  }

 private:
  void draw(int divisor) {
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(window_, &fbw, &fbh);
    if (fbw <= 0 || fbh <= 0) return;
    camera_.width = std::max(1, fbw / divisor);
    camera_.height = std::max(1, fbh / divisor);
    render::RenderSettings& rs = session_.renderSettings();
    const int kept = rs.temporal_history;
    if (divisor > 1) rs.temporal_history = opts_.temporal;  // the moving preview: its frames accumulate
    session_.dispatch(render::ViewRays::fromCamera(camera_));
    rs.temporal_history = kept;
    samples_shown_ = std::max(1, session_.renderSettings().samples_per_pixel);
    present(fbw, fbh);
  }

  // Progressive refinement of a still frame (issue 19, the interactive path): the next sample per
  // pixel (RenderSettings::first_sample; its own sub-pixel position and jitter) folds into the
  // frame on screen, so an idle view converges to the anti-aliased, noise-free picture of
  // kRefineSamples samples. Only a still camera, sun and time are refined — any change starts a
  // fresh frame — so nothing ghosts.
  void refine() {
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(window_, &fbw, &fbh);
    if (fbw <= 0 || fbh <= 0 || camera_.width != fbw || camera_.height != fbh) {
      full_res_shown_ = false;  // resized: draw afresh
      return;
    }
    render::RenderSettings& rs = session_.renderSettings();
    const render::RenderSettings kept = rs;
    rs.first_sample = samples_shown_;
    rs.samples_per_pixel = 1;
    session_.dispatch(render::ViewRays::fromCamera(camera_));
    rs = kept;
    ++samples_shown_;
    present(fbw, fbh);
  }

  void present(int fbw, int fbh) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fbw, fbh);
    present_.use();
    present_.set("u_exposure_scale",
                 scene::radianceScale(scene::imageOptionsFor(session_.scene().output, session_.sun().elevation_deg)));
    present_.set("u_tone_curve", int(session_.scene().output.image.tone_curve));
    glBindTextureUnit(gl::binding::UNIT_PRESENT_FRAME, session_.renderer().frame().id());
    glBindSampler(gl::binding::UNIT_PRESENT_FRAME, sampler_.id());
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindSampler(gl::binding::UNIT_PRESENT_FRAME, 0);
    const auto& st = session_.stats();
    const double ms = st.raycast_ms + st.dlm_ms;
    glfwSetWindowTitle(
        window_, fmt::format("nephele view — t {:.2f}{} — sun {:.0f}/{:.0f} deg — {} — {}x{} {:.0f} ms ({:.1f} fps), "
                             "{} sample{} per pixel",
                             time_, playing_ ? fmt::format(" (playing x{:g})", speed_) : "", sun_.azimuth_deg,
                             sun_.elevation_deg, lighting::kPresetNames[quality_], camera_.width, camera_.height, ms,
                             ms > 0.0 ? 1000.0 / ms : 0.0, samples_shown_, samples_shown_ > 1 ? "s" : "")
                     .c_str());
  }

  void screenshot(const std::string& path) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    std::vector<unsigned char> px(std::size_t(w) * std::size_t(h) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    if (auto dir = std::filesystem::path(path).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    // GL rows go bottom-up: flip them, then write through the image codec module (loaded now).
    const std::size_t row = std::size_t(w) * 4;
    std::vector<unsigned char> flipped(px.size());
    for (int y = 0; y < h; ++y)
      std::copy_n(px.data() + std::size_t(h - 1 - y) * row, row, flipped.data() + std::size_t(y) * row);
    scene::image_codec::WriteSpec spec;
    spec.width = w;
    spec.height = h;
    spec.channels = 4;
    scene::image_codec::write(path, path, spec, flipped.data(), scene::image_codec::Type::UInt8);
    log::info("wrote {} ({}x{})", path, w, h);
  }

  void setTime(double t) {
    const double last = double(session_.dataset().timestepCount() - 1);
    if (playing_ && t > last) t = 0.0;  // playback wraps around
    time_ = std::clamp(t, 0.0, last);
    session_.setTime(time_);
  }
  void touched() { last_input_ = glfwGetTime(); }

  void onKey(int key, int action, int mods) {
    if (action == GLFW_RELEASE) return;
    const double last = double(session_.dataset().timestepCount() - 1);
    switch (key) {
      case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_, 1); break;
      case GLFW_KEY_H:
        std::fputs(kHelp, stdout);
        std::fflush(stdout);
        break;
      case GLFW_KEY_RIGHT: setTime(std::min(std::floor(time_ + 1e-9) + 1.0, last)); break;
      case GLFW_KEY_LEFT: setTime(std::max(std::ceil(time_ - 1e-9) - 1.0, 0.0)); break;
      case GLFW_KEY_RIGHT_BRACKET: setTime(std::min(time_ + kScrubStep, last)); break;
      case GLFW_KEY_LEFT_BRACKET: setTime(std::max(time_ - kScrubStep, 0.0)); break;
      case GLFW_KEY_SPACE: playing_ = !playing_; break;
      case GLFW_KEY_EQUAL:
      case GLFW_KEY_KP_ADD: speed_ = std::min(speed_ * 2.0, 64.0); break;
      case GLFW_KEY_MINUS:
      case GLFW_KEY_KP_SUBTRACT: speed_ = std::max(speed_ / 2.0, 1.0 / 64.0); break;
      case GLFW_KEY_A:
      case GLFW_KEY_D:
      case GLFW_KEY_W:
      case GLFW_KEY_S: {
        if (key == GLFW_KEY_A || key == GLFW_KEY_D)
          sun_.azimuth_deg += key == GLFW_KEY_D ? kSunStep_deg : -kSunStep_deg;
        else
          sun_.elevation_deg =
              std::clamp(sun_.elevation_deg + (key == GLFW_KEY_W ? kSunStep_deg : -kSunStep_deg), -10.0, 90.0);
        sun_.azimuth_deg = std::fmod(sun_.azimuth_deg + 360.0, 360.0);
        session_.setSun(sun_);
        break;
      }
      case GLFW_KEY_Q: {
        quality_ = (quality_ + ((mods & GLFW_MOD_SHIFT) != 0 ? lighting::kPresetNames.size() - 1 : 1)) %
                   lighting::kPresetNames.size();
        session_.setQuality(lighting::qualityPreset(lighting::Preset(quality_)));  // keeps the style
        log::info("quality preset {}", lighting::kPresetNames[quality_]);
        break;
      }
      default: return;
    }
    touched();
  }
  void onButton(int button, int action) {
    if (button == GLFW_MOUSE_BUTTON_LEFT) orbiting_ = action == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_RIGHT) panning_ = action == GLFW_PRESS;
    glfwGetCursorPos(window_, &cursor_.x, &cursor_.y);
  }
  void onCursor(double x, double y) {
    const glm::dvec2 d = glm::dvec2(x, y) - cursor_;
    cursor_ = {x, y};
    if (!orbiting_ && !panning_) return;
    if (orbiting_) {
      orbit_.azimuth_deg -= kOrbitDegPerPixel * d.x;
      orbit_.elevation_deg = std::clamp(orbit_.elevation_deg + kOrbitDegPerPixel * d.y, 1.0, 89.9);
    } else {  // pan in the view plane, one pixel = one pixel's footprint at the target
      int h = 1;
      glfwGetFramebufferSize(window_, nullptr, &h);
      const double m =
          2.0 * orbit_.distance_m * std::tan(glm::radians(0.5 * camera_.vertical_fov_deg)) / std::max(h, 1);
      const glm::dvec3 fwd = glm::normalize(camera_.target_m - camera_.position_m);
      const glm::dvec3 right = glm::normalize(glm::cross(fwd, camera_.up));
      orbit_.target += m * (-d.x * right + d.y * glm::normalize(camera_.up));
    }
    orbit_.apply(camera_);
    touched();
  }
  void onScroll(double dy) {
    orbit_.distance_m *= std::pow(kZoomPerScrollStep, dy);
    orbit_.apply(camera_);
    touched();
  }

  gl::Context& ctx_;
  engine::Session& session_;
  GLFWwindow* window_;
  ViewOptions opts_;
  gl::Program present_;
  gl::Sampler sampler_;
  gl::VertexArray vao_;
  scene::Camera camera_;
  Orbit orbit_;
  scene::Sun sun_;
  double time_ = 0.0, speed_ = 1.0;  // speed: timesteps per second
  bool playing_ = false, orbiting_ = false, panning_ = false, full_res_shown_ = false;
  int samples_shown_ = 0;  ///< samples per pixel in the frame on screen (refine())
  std::size_t quality_ = 1;
  double last_input_ = -1e9;
  glm::dvec2 cursor_{0.0};
};

int runView(const ViewOptions& o) {
  std::optional<QuickLook> quick;  // a data file instead of a scene: framed automatically
  if (isDataFile(o.scene)) quick = makeQuickLook({o.scene, {}, o.width, o.height});
  scene::SceneDescription s = quick ? quick->scene : scene::loadSceneFile(o.scene);
  if (!s.data) throw InputError(o.scene + ": no \"data\" section: which .nph or model file to view?");
  if (o.timestep >= 0) {
    s.data->timestep = o.timestep;
    s.data->time_utc.reset();
  }
  // The camera presets frame the volume for the window's aspect ratio.
  s.output.width = o.width;
  s.output.height = o.height;
  const auto dataset = quick ? quick->dataset : engine::Dataset::open(s.data->path);
  gl::ContextOptions co;
  co.backend = gl::Backend::Glfw;
  co.width = o.width;
  co.height = o.height;
  co.title = "nephele view";
  auto ctx = gl::createContext(co);
  engine::Session session(dataset, s);
  Viewer viewer(*ctx, session, o);
  return viewer.run();
}

}  // namespace

void addViewCommand(CLI::App& app, Action& run) {
  auto opts = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand(
      "view", "Interactive viewer of a scene file in a GLFW window: orbit/pan/zoom with the mouse, timesteps, "
              "playback, sun and quality from the keyboard (H prints the keys). --frames N --screenshot F "
              "renders N frames without interaction and writes the last one.");
  cmd->add_option("scene", opts->scene, "scene file (JSON), or a wrfout / ICON / .nph file for a quick look")
      ->required()
      ->check(CLI::ExistingPath);  // a folder: GRIB2 quick look
  cmd->add_option("--width", opts->width, "window width")->capture_default_str()->check(CLI::Range(16, 16384));
  cmd->add_option("--height", opts->height, "window height")->capture_default_str()->check(CLI::Range(16, 16384));
  cmd->add_option("--frames", opts->frames, "render this many frames, then exit (non-interactive)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--screenshot", opts->screenshot, "with --frames: write the last frame (PNG, as shown)");
  cmd->add_option("--timestep", opts->timestep, "timestep index to start at");
  cmd->add_option("--temporal", opts->temporal,
                  "while the camera moves, accumulate each preview frame's jitter over up to N frames, "
                  "reprojected (0: every frame on its own)")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  cmd->callback([opts, &run] {
    if (!opts->screenshot.empty() && opts->frames <= 0) throw CLI::ValidationError("--screenshot", "needs --frames N");
    run = [opts] { return runView(*opts); };
  });
}

}  // namespace nph::cli

#include "api/renderer.h"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "api/gl_state_guard.h"
#include "api/handles.h"
#include "core/error.h"
#include "render/gl/objects.h"

namespace nph::api {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

scene::SceneDescription sceneFor(const engine::Dataset& dataset, const RendererOptions& o) {
  scene::SceneDescription s;
  s.source_file = "<plugin API>";
  scene::DataSpec data;
  data.path = dataset.path();
  const engine::TimeBracket b = engine::bracketTime(o.time_index, dataset.timestepCount());
  data.timestep = int(b.first);
  s.data = data;
  s.quality = lighting::qualityPreset(o.quality_preset);
  s.height_exaggeration = o.height_exaggeration;
  return s;
}

/// The width and height of level `level` of a host 2-D texture; INVALID_ARGUMENT if it is none.
glm::ivec2 hostTextureSize(unsigned texture, int level, const char* what) {
  if (texture == 0 || glIsTexture(texture) == GL_FALSE) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                   fmt::format("{} {} is not a texture of the current context", what, texture));
  }
  GLint target = 0;
  glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
  if (target != GL_TEXTURE_2D) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                   fmt::format("{} {} is not a GL_TEXTURE_2D (target 0x{:04x})", what, texture, target));
  }
  glm::ivec2 size{0};
  glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_WIDTH, &size.x);
  glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_HEIGHT, &size.y);
  if (size.x <= 0 || size.y <= 0) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("{} {} has no storage at level {}", what, texture, level));
  }
  return size;
}

}  // namespace

Renderer::Renderer(std::shared_ptr<const engine::Dataset> dataset, const RendererOptions& options) {
  if (!(options.height_exaggeration >= 1.0 && options.height_exaggeration <= 100.0)) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                   fmt::format("height_exaggeration {}: expected 1 to 100 (0 means 1)", options.height_exaggeration));
  }
  if (!std::isfinite(options.time_index)) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, "time_index is not finite");
  scene::SceneDescription s;
  try {
    s = sceneFor(*dataset, options);
  } catch (const InputError& e) {  // an unknown quality preset
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, e.what());
  }
  GlStateGuard guard;
  session_ = std::make_unique<engine::Session>(std::move(dataset), std::move(s));
  session_->setTime(options.time_index);
}

void Renderer::setTime(double time_index) {
  if (!std::isfinite(time_index)) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, "time index is not finite");
  session_->setTime(time_index);
}

void Renderer::setCamera(const HostCamera& c) {
  if (c.width <= 0 || c.height <= 0 || c.width > 16384 || c.height > 16384) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("camera size {}x{}: expected 1..16384", c.width, c.height));
  }
  for (const glm::dmat4* m : {&c.view_from_world, &c.clip_from_view}) {
    for (int i = 0; i < 16; ++i) {
      if (!std::isfinite((*m)[i / 4][i % 4]))
        throw ApiError(NPH_ERROR_INVALID_ARGUMENT, "camera matrix has a NaN or infinity");
    }
  }
  if (std::abs(glm::determinant(c.view_from_world)) < 1e-12 || std::abs(glm::determinant(c.clip_from_view)) < 1e-30) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                   "camera matrix is singular (expected a rigid view and a perspective projection)");
  }
  camera_ = c;
}

void Renderer::setCameraPreset(std::string_view preset, int width, int height) {
  scene::CameraSpec spec;
  if (preset == "overview") {
    spec.preset = scene::CameraPreset::Overview;
  } else if (preset == "oblique") {
    spec.preset = scene::CameraPreset::Oblique;
  } else if (preset == "top") {
    spec.preset = scene::CameraPreset::Top;
  } else {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                   fmt::format("camera preset '{}': expected overview, oblique or top", preset));
  }
  if (width <= 0 || height <= 0)
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("camera size {}x{}", width, height));
  const scene::Camera cam = scene::cameraFor(spec, frame(), width, height);
  setCamera({cam.viewFromWorld(), cam.clipFromView(), width, height});
}

void Renderer::setSun(double azimuth_deg, double elevation_deg) {
  if (!std::isfinite(azimuth_deg) || !(elevation_deg >= -90.0 && elevation_deg <= 90.0)) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                   fmt::format("sun azimuth {} / elevation {}: expected a finite azimuth and -90..90 deg", azimuth_deg,
                               elevation_deg));
  }
  scene::Sun sun = session_->sun();
  sun.azimuth_deg = azimuth_deg;
  sun.elevation_deg = elevation_deg;
  session_->setSun(sun);
}

void Renderer::setQualityPreset(std::string_view preset) {
  try {
    session_->setQuality(lighting::qualityPreset(preset));
  } catch (const InputError& e) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, e.what());
  }
}

template <typename Draw>
void Renderer::intoHostTarget(unsigned texture, int level, const char* what, Draw&& draw) {
  gl::Framebuffer target;
  if (texture != 0) {
    if (level < 0) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("texture level {}", level));
    const glm::ivec2 size = hostTextureSize(texture, level, what);
    target = gl::Framebuffer::create();
    target.attach(GL_COLOR_ATTACHMENT0, gl::Texture::wrap(texture, GL_TEXTURE_2D), level);
    target.checkComplete(what);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.id());
    glViewport(0, 0, size.x, size.y);
    glDisable(GL_SCISSOR_TEST);
  }
  draw();
}

void Renderer::render(unsigned texture, int level) {
  if (!camera_) throw ApiError(NPH_ERROR_WRONG_ORDER, "no camera yet: call set_camera or set_camera_preset first");
  const auto t0 = std::chrono::steady_clock::now();
  {
    GlStateGuard guard;
    if (host_depth_ != 0) {
      const glm::ivec2 size = hostTextureSize(host_depth_, 0, "host depth texture");
      if (size != glm::ivec2(camera_->width, camera_->height)) {
        throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("host depth texture is {}x{}, the camera {}x{}", size.x,
                                                               size.y, camera_->width, camera_->height));
      }
    }
    intoHostTarget(texture, level, "render_to_texture target", [&] {
      const HostCamera& c = *camera_;
      last_render_had_passes_ = false;
      session_->dispatch(render::ViewRays::fromMatrices(c.view_from_world, c.clip_from_view, c.width, c.height),
                         render::HostDepth{host_depth_});
      last_render_had_passes_ = session_->renderer().passes();
      const auto t1 = std::chrono::steady_clock::now();
      const auto& r = session_->renderer();
      compositor_.draw(ground_ ? r.frame() : r.cloudLayer(), composite_);
      nph_stats st{};
      st.composite_ms = msSince(t1);
      const engine::FrameStats& f = session_->stats();
      st.struct_size = sizeof(nph_stats);
      st.volume_changed = f.volume_changed ? 1 : 0;
      st.dlm_rebuilt = f.dlm_rebuilt ? 1 : 0;
      st.time_index = f.time_index;
      st.load_ms = f.load_ms;
      st.upload_ms = f.upload_ms;
      st.dlm_ms = f.dlm_ms;
      st.raycast_ms = f.raycast_ms;
      st.frames = ++frames_;
      st.dlm_builds = f.dlm_builds;
      st.dlm_reuses = f.dlm_reuses;
      st.volume_uploads = f.volume_uploads;
      stats_ = st;
    });
  }
  stats_->total_ms = msSince(t0);
}

void Renderer::passToTexture(scene::Pass pass, unsigned texture, int level) {
  if (!last_render_had_passes_) {
    throw ApiError(NPH_ERROR_WRONG_ORDER,
                   "the last render made no passes: call set_passes(renderer, 1) and render first");
  }
  if (texture == 0) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, "texture 0: name a host GL_TEXTURE_2D");
  GlStateGuard guard;
  intoHostTarget(texture, level, "pass_to_texture target", [&] {
    const auto& r = session_->renderer();
    const glm::dvec3 exposure = std::exp2(composite_.exposure_ev) *
                                scene::whiteBalanceGain(composite_.white_balance_k, composite_.white_balance_duv);
    using Select = Compositor::Select;
    switch (pass) {
      case scene::Pass::Beauty: return compositor_.copy(r.frame(), Select::Rgba, exposure);
      case scene::Pass::Cloud: return compositor_.copy(r.cloudLayer(), Select::Rgba, exposure);
      case scene::Pass::Ground: return compositor_.copy(r.groundPass(), Select::RgbOpaque, exposure);
      case scene::Pass::Sky: return compositor_.copy(r.skyPass(), Select::RgbOpaque, exposure);
      case scene::Pass::Shadow: return compositor_.copy(r.groundPass(), Select::AlphaAsGrey, glm::dvec3(1.0));
      case scene::Pass::Depth: return compositor_.copy(r.skyPass(), Select::AlphaAsGrey, glm::dvec3(1.0));
    }
  });
}

}  // namespace nph::api

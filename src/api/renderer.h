#pragma once
// The object behind an nph_renderer handle: an engine::Session in the host's GL context plus the
// composite pass, the host's camera and the output settings. Knows nothing of handles, threads
// or status codes (api.cpp checks those); every GL-touching method runs inside a GlStateGuard.
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "api/compositor.h"
#include "engine/dataset.h"
#include "engine/session.h"
#include "nephele/nephele.h"
#include "scene/passes.h"

namespace nph::api {

struct RendererOptions {
  std::string quality_preset = "broadcast";
  double time_index = 0.0;
  double height_exaggeration = 1.0;
};

/// A camera as the host gives it (matrices) or as a preset makes it.
struct HostCamera {
  glm::dmat4 view_from_world{1.0};
  glm::dmat4 clip_from_view{1.0};
  int width = 0, height = 0;
};

class Renderer {
 public:
  /// Needs the host's context current with the entry points loaded (api.cpp does both).
  Renderer(std::shared_ptr<const engine::Dataset> dataset, const RendererOptions& options);

  const volume::VolumeFrame& frame() const { return session_->prepared().frame; }
  void setTime(double time_index);
  void setCamera(const HostCamera& camera);
  /// "overview" | "oblique" | "top": scene::cameraFor with the preset's defaults.
  void setCameraPreset(std::string_view preset, int width, int height);
  const std::optional<HostCamera>& camera() const { return camera_; }
  void setSun(double azimuth_deg, double elevation_deg);
  void setQualityPreset(std::string_view preset);
  void setParameter(std::string_view name, double value);
  double parameter(std::string_view name) const;
  void setHostDepth(unsigned texture) { host_depth_ = texture; }

  /// Ray casts and composites into the bound draw framebuffer (0 = as bound) or into level
  /// `level` of the host texture `texture`. WRONG_ORDER without a camera.
  void render(unsigned texture = 0, int level = 0);
  /// Compositing passes for the next renders (scene/passes.h; API v2 set_passes).
  void setPasses(bool on) { session_->setPasses(on); }
  /// Copies `pass` of the last render into level `level` of the host texture (API v2
  /// pass_to_texture). WRONG_ORDER when the last render had no passes.
  void passToTexture(scene::Pass pass, unsigned texture, int level);
  /// nullopt before the first render.
  const std::optional<nph_stats>& stats() const { return stats_; }
  GLuint contextProbe() const { return compositor_.contextProbe(); }

  // For the parameter table (parameters.cpp).
  engine::Session& session() const { return *session_; }
  CompositeSettings& composite() { return composite_; }
  const CompositeSettings& composite() const { return composite_; }
  bool& ground() { return ground_; }
  bool ground() const { return ground_; }

 private:
  std::unique_ptr<engine::Session> session_;
  Compositor compositor_;
  std::optional<HostCamera> camera_;
  unsigned host_depth_ = 0;
  CompositeSettings composite_;
  bool ground_ = false;  ///< composite the frame (clouds over the lit ground) instead of the layer
  /// Runs `draw` with the host texture's level bound as the draw framebuffer (the bound one when
  /// `texture` is 0) and its whole level as the viewport.
  template <typename Draw>
  void intoHostTarget(unsigned texture, int level, const char* what, Draw&& draw);

  std::optional<nph_stats> stats_;
  std::uint64_t frames_ = 0;
  bool last_render_had_passes_ = false;
};

}  // namespace nph::api

#pragma once
// Temporal accumulation of the eye pass's jitter for the interactive path (issue 19 item 4; Muth
// 2026 §3.4.9; glsl/render/temporal.comp). The interactive path renders one sample per pixel per
// frame; with RenderSettings::temporal_history = N > 0 each frame takes the next sample of the
// jitter and sub-pixel sequence (its own ray start offset and position in the pixel), and
// CloudRenderer::dispatch() folds it into a history of the last frames: still pixels become the
// mean of up to N samples (anti-aliased, the banding jitter averaged out, as samples_per_pixel = N
// would give them), moving ones are reprojected through the scene's depth and clamped into their
// neighbourhood's range, so a camera move leaves no trail. The trade-off between noise and lag is
// measured in docs/rendering.md "Temporal accumulation".
//
// Only the eye pass accumulates; the DLM, the sun and the data are those of the frame. Anything
// but the camera that changes the picture (sun, time, data, settings, size) starts the history
// afresh: CloudRenderer compares a key of them, and callers may reset() it themselves.
#include <cstddef>
#include <string>

#include <glm/glm.hpp>

#include "render/gl/objects.h"
#include "render/gl/program.h"

namespace nph::render {

struct ViewRays;

class TemporalAccumulation {
 public:
  /// Before the frame's eye pass: decides whether the history holds (the same `key` — everything
  /// but the view the images depend on —, the same size, no cut: the view turned by less than
  /// half its vertical field of view) and returns the index the frame's samples start at in the
  /// jitter and sub-pixel sequence (render::subpixelPosition): one more per frame, 0 after a
  /// fresh start (so the first frame is the one a render without the accumulation gives).
  int begin(const ViewRays& view, const std::string& key);
  /// Folds the eye pass's layers for `view` — `cloud_layer` (premultiplied RGBA32F), its mean
  /// depth `cloud_depth` (R32F) and `background` (RGBA32F: ground + sky, its depth) — into the
  /// histories and writes the resolved cloud layer and the frame recomposed from the layers into
  /// `cloud_layer` and `frame`; `view` is begin()'s, `max_history` N.
  void resolve(const gl::Texture& frame, const gl::Texture& cloud_layer, const gl::Texture& cloud_depth,
               const gl::Texture& background, const ViewRays& view, int max_history);
  /// Starts the history afresh at the next frame.
  void reset() { valid_ = false; }
  /// Drops the histories (the accumulation turned off): textureBytes() 0 until the next begin().
  void release();
  /// Frames in the history of the last resolve (1 after a reset), where nothing moved.
  int frames() const { return frames_; }
  /// Bytes of the history textures.
  std::size_t textureBytes() const;

 private:
  gl::Program program_;
  // ping-pong: read one, write the other. The background's count of frames is its alpha.
  gl::Texture history_background_[2], history_cloud_[2], history_count_[2];
  int current_ = 0;  // the history last written
  glm::ivec2 size_{0};
  bool valid_ = false, moved_ = false;
  std::string key_;
  int frame_index_ = 0, frames_ = 0;
  // The previous frame's view (ViewRays' fields).
  glm::dvec3 position_m_{0.0};
  glm::dmat3 world_from_view_{1.0};
  glm::dmat4 view_from_clip_{1.0};
};

}  // namespace nph::render

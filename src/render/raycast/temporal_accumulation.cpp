// Temporal accumulation of the eye pass's jitter (issue 19 item 4): see temporal_accumulation.h
// and glsl/render/temporal.comp.
#include "render/raycast/temporal_accumulation.h"

#include <algorithm>
#include <cmath>

#include "render/gl/bindings.h"
#include "render/gl/debug.h"
#include "render/raycast/cloud_renderer.h"

namespace nph::render {

int TemporalAccumulation::begin(const ViewRays& view, const std::string& key) {
  const glm::ivec2 size{view.width, view.height};
  if (size_ != size) {
    for (int i = 0; i < 2; ++i) {
      const auto history = [&](GLenum format, const char* name) {
        return gl::Texture::create2D(format, size.x, size.y).label(name).sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
      };
      history_background_[i] = history(GL_RGBA32F, "temporal history: background, frames");
      history_cloud_[i] = history(GL_RGBA32F, "temporal history: cloud layer");
      history_count_[i] = history(GL_R32F, "temporal history: cloud layer's frames");
    }
    size_ = size;
    valid_ = false;
  }
  if (key != key_) {
    key_ = key;
    valid_ = false;
  }
  moved_ = view.position_m != position_m_ || view.world_from_view != world_from_view_ ||
           view.view_from_clip != view_from_clip_;
  // A cut: the view turned by more than half its vertical field of view since the last frame. Its
  // history shows the scene from elsewhere (other sides lit, other parallax) and would only be
  // clamped into place; it starts afresh as a camera cut in a host's timeline would.
  if (valid_ && moved_) {
    const glm::dvec4 top = view.view_from_clip * glm::dvec4(0.0, 1.0, 0.0, 1.0);
    const double halfFov = std::atan2(std::abs(top.y / top.w), std::abs(top.z / top.w));
    const glm::dvec3 forward = glm::normalize(view.world_from_view * glm::dvec3(0.0, 0.0, -1.0));
    const glm::dvec3 previousForward = glm::normalize(world_from_view_ * glm::dvec3(0.0, 0.0, -1.0));
    if (std::acos(std::clamp(glm::dot(forward, previousForward), -1.0, 1.0)) > halfFov) valid_ = false;
  }
  // A fresh history starts the sequence again: its first frame is sample 0 (the pixels' centres),
  // the frame a render without the accumulation gives.
  if (!valid_) frame_index_ = 0;
  return frame_index_;
}

void TemporalAccumulation::resolve(const gl::Texture& frame, const gl::Texture& cloud_layer,
                                   const gl::Texture& cloud_depth, const gl::Texture& background, const ViewRays& view,
                                   int max_history) {
  gl::DebugGroup group("temporal accumulation");
  const glm::ivec2 size{view.width, view.height};
  const bool moved = moved_;
  if (!program_) program_ = gl::Program::compute("render/temporal.comp");
  const int next = 1 - current_;
  program_.use();
  program_.set("u_size", size);
  program_.set("u_view_from_clip", glm::mat4(view.view_from_clip));
  program_.set("u_world_from_view", glm::mat3(view.world_from_view));
  program_.set("u_cam_delta_m", glm::vec3(view.position_m - position_m_));
  program_.set("u_prev_view_from_world", glm::mat3(glm::transpose(world_from_view_)));
  program_.set("u_prev_clip_from_view", glm::mat4(glm::inverse(view_from_clip_)));
  program_.set("u_history_valid", valid_ ? 1 : 0);
  program_.set("u_view_moved", moved ? 1 : 0);
  program_.set("u_max_history", float(std::max(max_history, 1)));
  namespace b = gl::binding;
  glBindTextureUnit(b::UNIT_TEMPORAL_CLOUD, cloud_layer.id());
  glBindTextureUnit(b::UNIT_TEMPORAL_DEPTH, cloud_depth.id());
  glBindTextureUnit(b::UNIT_TEMPORAL_BACKGROUND, background.id());
  const auto bindHistory = [&](int which) {
    glBindTextureUnit(b::UNIT_TEMPORAL_HISTORY_BACKGROUND, history_background_[which].id());
    glBindTextureUnit(b::UNIT_TEMPORAL_HISTORY_CLOUD, history_cloud_[which].id());
    glBindTextureUnit(b::UNIT_TEMPORAL_HISTORY_COUNT, history_count_[which].id());
  };
  bindHistory(current_);
  glBindImageTexture(b::IMAGE_TEMPORAL_BACKGROUND_OUT, history_background_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                     GL_RGBA32F);
  glBindImageTexture(b::IMAGE_TEMPORAL_CLOUD_OUT, history_cloud_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(b::IMAGE_TEMPORAL_COUNT_OUT, history_count_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glBindImageTexture(b::IMAGE_FRAME, frame.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(b::IMAGE_CLOUD_LAYER, cloud_layer.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  program_.set("u_role", 0);
  program_.dispatchCovering({size.x, size.y, 1});
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  bindHistory(next);  // role 1 reads the new histories
  program_.set("u_role", 1);
  program_.dispatchCovering({size.x, size.y, 1});
  current_ = next;
  frames_ = valid_ && !moved ? std::min(frames_ + 1, std::max(max_history, 1)) : 1;
  valid_ = true;
  ++frame_index_;
  position_m_ = view.position_m;
  world_from_view_ = view.world_from_view;
  view_from_clip_ = view.view_from_clip;
}

void TemporalAccumulation::release() {
  for (int i = 0; i < 2; ++i) {
    history_background_[i] = {};
    history_cloud_[i] = {};
    history_count_[i] = {};
  }
  size_ = glm::ivec2(0);
  valid_ = false;
}

std::size_t TemporalAccumulation::textureBytes() const {
  std::size_t b = 0;
  for (const gl::Texture* t : {&history_background_[0], &history_background_[1], &history_cloud_[0], &history_cloud_[1],
                               &history_count_[0], &history_count_[1]})
    b += t->bytes();
  return b;
}

}  // namespace nph::render

#pragma once
// The sub-grid detail's periodic noise tile on the GPU (issue 13; volume/noise.h): an RGBA8
// kNoiseTexels³ texture filled once by glsl/render/noise.comp (Thomann 2021 §4.4), sampled with
// GL_LINEAR and GL_REPEAT. Shared by every upload of a session (engine::Session keeps one).
#include <memory>

#include "render/gl/objects.h"

namespace nph::render {

class NoiseTexture {
 public:
  /// Generates the tile with the compute shader (needs a current GL context).
  static std::shared_ptr<const NoiseTexture> generate();
  const gl::Texture& texture() const { return texture_; }

 private:
  gl::Texture texture_;
};

}  // namespace nph::render

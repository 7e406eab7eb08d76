#pragma once
// The composite pass of the plugin API: a full-screen triangle that blends a premultiplied RGBA
// layer "over" the host's currently bound draw framebuffer within its viewport
// (glsl/api/composite.frag has the equation and the output transforms).
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "scene/output_image.h"

namespace nph::api {

struct CompositeSettings {
  double exposure_ev = scene::kDefaultExposureEv;  ///< radiance scale 2^ev
  /// A camera's white balance [K] (scene/white_balance.h): radiance × its gain; neutral by default.
  double white_balance_k = scene::kNeutralWhiteBalanceK;
  double white_balance_duv = 0.0;  ///< its tint (scene/white_balance.h)
  bool display = false;            ///< ACES + sRGB like `nephele render`'s PNG, else linear
};

class Compositor {
 public:
  Compositor();
  /// Draws `layer` (row 0 = top) into the bound draw framebuffer over the current viewport.
  /// Sets the blend, depth, cull, ... state it needs; the caller's GlStateGuard restores it.
  void draw(const gl::Texture& layer, const CompositeSettings& settings) const;
  /// What a packed pass texture's channels are (glsl/api/composite.frag u_select).
  enum class Select { Rgba = 0, RgbOpaque = 1, AlphaAsGrey = 2 };
  /// Copies `source` (row 0 = top) into the bound draw framebuffer over the current viewport,
  /// replacing it (no blending), RGB times `scale` (per channel), linear (no display transform).
  void copy(const gl::Texture& source, Select select, glm::dvec3 scale) const;
  /// A GL object that exists only in the context the compositor was created in: glIsVertexArray
  /// on it tells whether that context is current (vertex arrays are never shared).
  GLuint contextProbe() const { return vertex_array_.id(); }

 private:
  void drawTriangle(const gl::Texture& source, bool blend) const;
  gl::Program program_;
  gl::VertexArray vertex_array_;
  gl::Sampler sampler_;
};

}  // namespace nph::api

#pragma once
// Saves every piece of the host's OpenGL state that a plugin API call may change and puts it back
// when the guard goes out of scope (the host owns the context; Nes 2008 §7.2: the renderer was
// built to live inside a broadcast graphics framework that does not expect its state to move).
//
// What nephele's passes touch, and therefore what is saved (docs/plugin-api.md lists it too):
//   program, vertex array, active texture unit, textures of every target and the sampler on units
//   0..kTextureUnits-1, image units 0..kImageUnits-1, the generic and indexed shader storage
//   buffer bindings 0..kStorageBindings-1 and uniform buffer bindings 0..kUniformBindings-1 (the
//   counts follow render/gl/bindings.h), pixel pack/unpack buffers and every pixel store
//   parameter, draw and read framebuffers, viewport, clip control, polygon mode, and the enables
//   and functions of blending (draw buffer 0), depth, stencil, culling, dither, rasterizer
//   discard, alpha-to-coverage, colour logic op and the colour write mask of draw buffer 0.
// While the guard lives, the state the passes rely on is put in a known condition: no sampler
// objects on those units, no pixel buffers bound, default pixel store (tight rows, alignment 4).
#include <algorithm>
#include <array>
#include <vector>

#include "render/gl/bindings.h"
#include "render/gl/gl.h"

namespace nph::api {

class GlStateGuard {
 public:
  static constexpr int kTextureUnits =
      32;  ///< the passes' units (0 … 30: UNIT_MC_MOMENTS is 7 units); the test checks 32
  /// IMAGE_MC_MOMENTS is an array of 7 image units (render/dlm/radiance_volume.cpp).
  static constexpr int kImageUnits =
      std::max(int(gl::binding::highest("IMAGE_")) + 1, int(gl::binding::IMAGE_MC_MOMENTS) + 7);
  static constexpr int kStorageBindings = int(gl::binding::highest("SSBO_")) + 1;
  static constexpr int kUniformBindings = int(gl::binding::highest("UBO_")) + 1;
  static_assert(kTextureUnits > int(gl::binding::highest("UNIT_")), "a pass binds a unit the guard does not save");
  static_assert(kTextureUnits >= int(gl::binding::UNIT_MC_MOMENTS) + 7, "the radiance volume's units are not saved");

  GlStateGuard();
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

 private:
  struct ImageUnit {
    GLint name = 0, level = 0, layered = 0, layer = 0, access = GL_READ_ONLY, format = GL_R8;
  };
  struct IndexedBuffer {
    GLint name = 0;
    GLint64 start = 0, size = 0;
  };
  struct PixelStore {
    GLenum pname;
    GLint value;
  };

  GLint program_ = 0, vertex_array_ = 0, active_texture_ = GL_TEXTURE0;
  std::array<std::vector<GLint>, kTextureUnits> textures_;  // per unit: one name per target
  std::array<GLint, kTextureUnits> samplers_{};
  std::array<ImageUnit, kImageUnits> images_{};
  GLint storage_buffer_ = 0, uniform_buffer_ = 0;
  std::array<IndexedBuffer, kStorageBindings> storage_{};
  std::array<IndexedBuffer, kUniformBindings> uniform_{};
  GLint pack_buffer_ = 0, unpack_buffer_ = 0, dispatch_indirect_buffer_ = 0;
  std::vector<PixelStore> pixel_store_;
  GLint draw_framebuffer_ = 0, read_framebuffer_ = 0;
  std::array<GLint, 4> viewport_{};
  GLint clip_origin_ = GL_LOWER_LEFT, clip_depth_ = GL_NEGATIVE_ONE_TO_ONE;
  std::array<GLint, 2> polygon_mode_{GL_FILL, GL_FILL};
  GLboolean blend_ = GL_FALSE;
  std::array<GLint, 4> blend_func_{};      // src rgb, dst rgb, src alpha, dst alpha (buffer 0)
  std::array<GLint, 2> blend_equation_{};  // rgb, alpha (buffer 0)
  std::array<GLboolean, 4> colour_mask_{};
  std::vector<std::pair<GLenum, GLboolean>> enables_;
};

}  // namespace nph::api

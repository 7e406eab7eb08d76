#include "api/gl_state_guard.h"

#include <utility>

#include "core/log.h"

namespace nph::api {
namespace {

// Every texture target of GL 4.5 core with the query of its binding on the active unit.
constexpr std::pair<GLenum, GLenum> kTextureTargets[] = {
    {GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D},
    {GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D},
    {GL_TEXTURE_1D_ARRAY, GL_TEXTURE_BINDING_1D_ARRAY},
    {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BINDING_2D_ARRAY},
    {GL_TEXTURE_RECTANGLE, GL_TEXTURE_BINDING_RECTANGLE},
    {GL_TEXTURE_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP},
    {GL_TEXTURE_CUBE_MAP_ARRAY, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY},
    {GL_TEXTURE_BUFFER, GL_TEXTURE_BINDING_BUFFER},
    {GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE},
    {GL_TEXTURE_2D_MULTISAMPLE_ARRAY, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY},
};

// Pixel store parameters and the values the passes expect (GL 4.5 core defaults).
constexpr std::pair<GLenum, GLint> kPixelStoreDefaults[] = {
    {GL_PACK_SWAP_BYTES, 0},   {GL_PACK_LSB_FIRST, 0},     {GL_PACK_ROW_LENGTH, 0},    {GL_PACK_IMAGE_HEIGHT, 0},
    {GL_PACK_SKIP_ROWS, 0},    {GL_PACK_SKIP_PIXELS, 0},   {GL_PACK_SKIP_IMAGES, 0},   {GL_PACK_ALIGNMENT, 4},
    {GL_UNPACK_SWAP_BYTES, 0}, {GL_UNPACK_LSB_FIRST, 0},   {GL_UNPACK_ROW_LENGTH, 0},  {GL_UNPACK_IMAGE_HEIGHT, 0},
    {GL_UNPACK_SKIP_ROWS, 0},  {GL_UNPACK_SKIP_PIXELS, 0}, {GL_UNPACK_SKIP_IMAGES, 0}, {GL_UNPACK_ALIGNMENT, 4},
};

// Capabilities the composite pass switches; saved and restored as they were.
constexpr GLenum kEnables[] = {GL_DEPTH_TEST,
                               GL_STENCIL_TEST,
                               GL_CULL_FACE,
                               GL_SCISSOR_TEST,
                               GL_DITHER,
                               GL_RASTERIZER_DISCARD,
                               GL_SAMPLE_ALPHA_TO_COVERAGE,
                               GL_COLOR_LOGIC_OP};

void setEnabled(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }

// Indexed buffer bindings (shader storage, uniform): name, start and size of each index.
template <class Bindings>
void saveIndexed(GLenum bindingQuery, GLenum startQuery, GLenum sizeQuery, Bindings& saved) {
  for (std::size_t i = 0; i < saved.size(); ++i) {
    glGetIntegeri_v(bindingQuery, GLuint(i), &saved[i].name);
    glGetInteger64i_v(startQuery, GLuint(i), &saved[i].start);
    glGetInteger64i_v(sizeQuery, GLuint(i), &saved[i].size);
  }
}

template <class Bindings>
void restoreIndexed(GLenum target, const Bindings& saved) {
  for (std::size_t i = 0; i < saved.size(); ++i) {
    const auto& b = saved[i];
    if (b.name != 0 && b.size > 0) {
      glBindBufferRange(target, GLuint(i), GLuint(b.name), GLintptr(b.start), GLsizeiptr(b.size));
    } else {
      glBindBufferBase(target, GLuint(i), GLuint(b.name));
    }
  }
}

}  // namespace

GlStateGuard::GlStateGuard() {
  // Errors the host left pending would be blamed on nephele's passes (checkErrors): take them
  // now and say so. (The GL error flags are the one piece of state not put back.)
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
    log::warn("plugin API: the host left GL error 0x{:04x} pending; cleared before rendering", e);
  }
  glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
  for (int unit = 0; unit < kTextureUnits; ++unit) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    for (const auto& [target, binding] : kTextureTargets) {
      GLint name = 0;
      glGetIntegerv(binding, &name);
      textures_[std::size_t(unit)].push_back(name);
    }
    glGetIntegeri_v(GL_SAMPLER_BINDING, GLuint(unit), &samplers_[std::size_t(unit)]);
    glBindSampler(GLuint(unit), 0);
  }
  glActiveTexture(GLenum(active_texture_));
  for (int i = 0; i < kImageUnits; ++i) {
    ImageUnit& u = images_[std::size_t(i)];
    glGetIntegeri_v(GL_IMAGE_BINDING_NAME, GLuint(i), &u.name);
    glGetIntegeri_v(GL_IMAGE_BINDING_LEVEL, GLuint(i), &u.level);
    glGetIntegeri_v(GL_IMAGE_BINDING_LAYERED, GLuint(i), &u.layered);
    glGetIntegeri_v(GL_IMAGE_BINDING_LAYER, GLuint(i), &u.layer);
    glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, GLuint(i), &u.access);
    glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, GLuint(i), &u.format);
  }
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &storage_buffer_);
  saveIndexed(GL_SHADER_STORAGE_BUFFER_BINDING, GL_SHADER_STORAGE_BUFFER_START, GL_SHADER_STORAGE_BUFFER_SIZE,
              storage_);
  glGetIntegerv(GL_UNIFORM_BUFFER_BINDING, &uniform_buffer_);
  saveIndexed(GL_UNIFORM_BUFFER_BINDING, GL_UNIFORM_BUFFER_START, GL_UNIFORM_BUFFER_SIZE, uniform_);
  glGetIntegerv(GL_DISPATCH_INDIRECT_BUFFER_BINDING, &dispatch_indirect_buffer_);  // the DLM's retries
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer_);
  glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer_);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  for (const auto& [pname, value] : kPixelStoreDefaults) {
    GLint v = 0;
    glGetIntegerv(pname, &v);
    pixel_store_.push_back({pname, v});
    glPixelStorei(pname, value);
  }
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer_);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer_);
  glGetIntegerv(GL_VIEWPORT, viewport_.data());
  glGetIntegerv(GL_CLIP_ORIGIN, &clip_origin_);
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip_depth_);
  glGetIntegerv(GL_POLYGON_MODE, polygon_mode_.data());
  blend_ = glIsEnabledi(GL_BLEND, 0);
  glGetIntegeri_v(GL_BLEND_SRC_RGB, 0, &blend_func_[0]);
  glGetIntegeri_v(GL_BLEND_DST_RGB, 0, &blend_func_[1]);
  glGetIntegeri_v(GL_BLEND_SRC_ALPHA, 0, &blend_func_[2]);
  glGetIntegeri_v(GL_BLEND_DST_ALPHA, 0, &blend_func_[3]);
  glGetIntegeri_v(GL_BLEND_EQUATION_RGB, 0, &blend_equation_[0]);
  glGetIntegeri_v(GL_BLEND_EQUATION_ALPHA, 0, &blend_equation_[1]);
  glGetBooleani_v(GL_COLOR_WRITEMASK, 0, colour_mask_.data());
  for (GLenum cap : kEnables) enables_.emplace_back(cap, glIsEnabled(cap));
}

GlStateGuard::~GlStateGuard() {
  for (const auto& [cap, on] : enables_) setEnabled(cap, on);
  glColorMaski(0, colour_mask_[0], colour_mask_[1], colour_mask_[2], colour_mask_[3]);
  glBlendEquationSeparatei(0, GLenum(blend_equation_[0]), GLenum(blend_equation_[1]));
  glBlendFuncSeparatei(0, GLenum(blend_func_[0]), GLenum(blend_func_[1]), GLenum(blend_func_[2]),
                       GLenum(blend_func_[3]));
  blend_ ? glEnablei(GL_BLEND, 0) : glDisablei(GL_BLEND, 0);
  // Core profiles only set FRONT_AND_BACK; the query returns that mode twice.
  glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygon_mode_[0]));
  glClipControl(GLenum(clip_origin_), GLenum(clip_depth_));
  glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_framebuffer_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_framebuffer_));
  for (const auto& p : pixel_store_) glPixelStorei(p.pname, p.value);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, GLuint(dispatch_indirect_buffer_));
  glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer_));
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpack_buffer_));
  restoreIndexed(GL_SHADER_STORAGE_BUFFER, storage_);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(storage_buffer_));
  restoreIndexed(GL_UNIFORM_BUFFER, uniform_);
  glBindBuffer(GL_UNIFORM_BUFFER, GLuint(uniform_buffer_));
  for (int i = 0; i < kImageUnits; ++i) {
    const ImageUnit& u = images_[std::size_t(i)];
    glBindImageTexture(GLuint(i), GLuint(u.name), u.level, GLboolean(u.layered), u.layer, GLenum(u.access),
                       GLenum(u.format));
  }
  for (int unit = 0; unit < kTextureUnits; ++unit) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    std::size_t t = 0;
    for (const auto& [target, binding] : kTextureTargets) {
      glBindTexture(target, GLuint(textures_[std::size_t(unit)][t++]));
    }
    glBindSampler(GLuint(unit), GLuint(samplers_[std::size_t(unit)]));
  }
  glActiveTexture(GLenum(active_texture_));
  glBindVertexArray(GLuint(vertex_array_));
  glUseProgram(GLuint(program_));
}

}  // namespace nph::api

#include "render/gl/objects.h"

#include <algorithm>
#include <string_view>

#include <string>

#include <fmt/format.h>

#include "core/error.h"

namespace nph::gl {
namespace detail {
void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteProgram(GLuint id) { glDeleteProgram(id); }
void deleteShader(GLuint id) { glDeleteShader(id); }
void deleteQuery(GLuint id) { glDeleteQueries(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteSampler(GLuint id) { glDeleteSamplers(1, &id); }
void setLabel(GLenum identifier, GLuint id, std::string_view label) {
  glObjectLabel(identifier, id, static_cast<GLsizei>(label.size()), label.data());
}
}  // namespace detail

namespace {
void requirePositive(std::string_view what, int w, int h, int d, int levels) {
  if (w <= 0 || h <= 0 || d <= 0 || levels <= 0) {
    throw UsageError(fmt::format("{}: invalid texture size {}x{}x{} with {} levels", what, w, h, d, levels));
  }
}
}  // namespace

Texture Texture::create2D(GLenum internalFormat, int width, int height, int levels) {
  requirePositive("Texture::create2D", width, height, 1, levels);
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  Texture t;
  t.handle_ = ObjectHandle<&detail::deleteTexture>(id, Ownership::Owned);
  t.target_ = GL_TEXTURE_2D;
  t.width_ = width;
  t.height_ = height;
  t.depth_ = 1;
  t.format_ = internalFormat;
  t.levels_ = levels;
  glTextureStorage2D(id, levels, internalFormat, width, height);
  return t;
}

Texture Texture::create3D(GLenum internalFormat, int width, int height, int depth, int levels) {
  requirePositive("Texture::create3D", width, height, depth, levels);
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &id);
  Texture t;
  t.handle_ = ObjectHandle<&detail::deleteTexture>(id, Ownership::Owned);
  t.target_ = GL_TEXTURE_3D;
  t.width_ = width;
  t.height_ = height;
  t.depth_ = depth;
  t.format_ = internalFormat;
  t.levels_ = levels;
  glTextureStorage3D(id, levels, internalFormat, width, height, depth);
  return t;
}

Texture Texture::wrap(GLuint id, GLenum target) {
  Texture t;
  t.handle_ = ObjectHandle<&detail::deleteTexture>(id, Ownership::Wrapped);
  t.target_ = target;
  glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_WIDTH, &t.width_);
  glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_HEIGHT, &t.height_);
  glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_DEPTH, &t.depth_);
  return t;
}

std::size_t bytesPerTexel(GLenum internalFormat) {
  switch (internalFormat) {
    case GL_R8: return 1;
    case GL_R16F:
    case GL_R16:
    case GL_R16I:
    case GL_RG8: return 2;
    case GL_R32F:
    case GL_R32UI:
    case GL_R32I:
    case GL_RG16F:
    case GL_RGBA8:
    case GL_SRGB8_ALPHA8: return 4;
    case GL_RG32F:
    case GL_RGBA16F: return 8;
    case GL_RGBA32F: return 16;
    default: throw UsageError(fmt::format("bytesPerTexel: internal format 0x{:x} is not in the table", internalFormat));
  }
}

std::size_t Texture::bytes() const {
  if (!handle_ || !owned() || format_ == GL_NONE) return 0;
  std::size_t total = 0;
  for (int l = 0; l < levels_; ++l) {
    const std::size_t w = std::size_t(std::max(1, width_ >> l)), h = std::size_t(std::max(1, height_ >> l));
    const std::size_t d = target_ == GL_TEXTURE_3D ? std::size_t(std::max(1, depth_ >> l)) : 1;
    total += w * h * d;
  }
  return total * bytesPerTexel(format_);
}

Texture& Texture::label(std::string_view name) & {
  detail::setLabel(GL_TEXTURE, id(), name);
  return *this;
}

Texture& Texture::sampling(GLenum filter, GLenum wrapMode) & {
  const auto f = static_cast<GLint>(filter);
  const auto w = static_cast<GLint>(wrapMode);
  glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, f);
  glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, f);
  glTextureParameteri(id(), GL_TEXTURE_WRAP_S, w);
  glTextureParameteri(id(), GL_TEXTURE_WRAP_T, w);
  glTextureParameteri(id(), GL_TEXTURE_WRAP_R, w);
  return *this;
}

int mipLevelsFor(int width, int height) {
  int levels = 1;
  for (int side = std::max(width, height); side > 1; side /= 2) ++levels;
  return levels;
}

Texture& Texture::mipmapped(GLenum wrapMode) & {
  sampling(GL_LINEAR, wrapMode);
  glGenerateTextureMipmap(id());
  glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  return *this;
}

Buffer Buffer::create(std::size_t bytes, const void* data, GLbitfield flags) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  Buffer b;
  b.handle_ = ObjectHandle<&detail::deleteBuffer>(id, Ownership::Owned);
  b.bytes_ = bytes;
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(bytes), data, flags);
  return b;
}

Buffer Buffer::wrap(GLuint id) {
  Buffer b;
  b.handle_ = ObjectHandle<&detail::deleteBuffer>(id, Ownership::Wrapped);
  GLint64 size = 0;
  glGetNamedBufferParameteri64v(id, GL_BUFFER_SIZE, &size);
  b.bytes_ = static_cast<std::size_t>(size);
  return b;
}

Buffer& Buffer::label(std::string_view name) & {
  detail::setLabel(GL_BUFFER, id(), name);
  return *this;
}

void Buffer::upload(std::size_t offset, std::size_t bytes, const void* data) {
  if (offset + bytes > bytes_) throw UsageError("Buffer::upload: range past the end of the buffer");
  glNamedBufferSubData(id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
}

void Buffer::download(std::size_t offset, std::size_t bytes, void* data) const {
  if (offset + bytes > bytes_) throw UsageError("Buffer::download: range past the end of the buffer");
  glGetNamedBufferSubData(id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
}

Framebuffer Framebuffer::create() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  Framebuffer f;
  f.handle_ = ObjectHandle<&detail::deleteFramebuffer>(id, Ownership::Owned);
  return f;
}

Framebuffer Framebuffer::wrap(GLuint id) {
  Framebuffer f;
  f.handle_ = ObjectHandle<&detail::deleteFramebuffer>(id, Ownership::Wrapped);
  return f;
}

Framebuffer& Framebuffer::label(std::string_view name) & {
  detail::setLabel(GL_FRAMEBUFFER, id(), name);
  return *this;
}

Framebuffer& Framebuffer::attach(GLenum attachment, const Texture& texture, int level) {
  glNamedFramebufferTexture(id(), attachment, texture.id(), level);
  return *this;
}

void Framebuffer::checkComplete(std::string_view what) const {
  const GLenum status = glCheckNamedFramebufferStatus(id(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw GlError(fmt::format("{}: framebuffer incomplete (status 0x{:04x})", what, status));
  }
}

VertexArray VertexArray::create() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  VertexArray v;
  v.handle_ = ObjectHandle<&detail::deleteVertexArray>(id, Ownership::Owned);
  return v;
}

Sampler Sampler::create(GLenum filter, GLenum wrapMode) {
  GLuint id = 0;
  glCreateSamplers(1, &id);
  Sampler s;
  s.handle_ = ObjectHandle<&detail::deleteSampler>(id, Ownership::Owned);
  const auto f = static_cast<GLint>(filter);
  const auto w = static_cast<GLint>(wrapMode);
  glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, f);
  glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, f);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_S, w);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_T, w);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_R, w);
  return s;
}

Query Query::create(GLenum target) {
  GLuint id = 0;
  glCreateQueries(target, 1, &id);
  Query q;
  q.handle_ = ObjectHandle<&detail::deleteQuery>(id, Ownership::Owned);
  q.target_ = target;
  return q;
}

std::uint64_t Query::result() const {
  GLuint64 value = 0;
  glGetQueryObjectui64v(handle_.id(), GL_QUERY_RESULT, &value);
  return value;
}

}  // namespace nph::gl

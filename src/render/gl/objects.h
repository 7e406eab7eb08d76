#pragma once
// Move-only RAII wrappers for OpenGL objects (STYLE.md 5, after Magnum's GL/Texture.h), using
// direct state access (GL 4.5). Each wrapper either owns its name (deleted on destruction) or
// wraps a host-owned name with wrap(): then it is never deleted — the plugin API renders into
// the host's framebuffers and textures this way. release() gives up ownership and returns the name.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <utility>

#include "render/gl/gl.h"

namespace nph::gl {

enum class Ownership { Owned, Wrapped };

/// The ownership mechanics shared by every object type. `Deleter` is a function deleting one name.
template <void (*Deleter)(GLuint)>
class ObjectHandle {
 public:
  ObjectHandle() = default;
  ObjectHandle(GLuint id, Ownership ownership) : id_(id), owned_(ownership == Ownership::Owned) {}
  ~ObjectHandle() { reset(); }
  ObjectHandle(ObjectHandle&& o) noexcept : id_(std::exchange(o.id_, 0u)), owned_(o.owned_) {}
  ObjectHandle& operator=(ObjectHandle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0u);
      owned_ = o.owned_;
    }
    return *this;
  }
  ObjectHandle(const ObjectHandle&) = delete;
  ObjectHandle& operator=(const ObjectHandle&) = delete;

  GLuint id() const { return id_; }
  bool owned() const { return owned_ && id_ != 0; }
  explicit operator bool() const { return id_ != 0; }
  /// Gives up ownership: the caller is now responsible for the name. The wrapper becomes empty.
  GLuint release() { return std::exchange(id_, 0u); }
  void reset() {
    if (id_ != 0 && owned_) Deleter(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
  bool owned_ = true;
};

namespace detail {
void deleteTexture(GLuint id);
void deleteBuffer(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteProgram(GLuint id);
void deleteShader(GLuint id);
void deleteQuery(GLuint id);
void deleteVertexArray(GLuint id);
void deleteSampler(GLuint id);
void setLabel(GLenum identifier, GLuint id, std::string_view label);
}  // namespace detail

/// Levels of a full mipmap chain for a w × h image: floor(log2(max(w, h))) + 1.
int mipLevelsFor(int width, int height);

class Texture {
 public:
  Texture() = default;
  /// Immutable 2-D storage (glTextureStorage2D).
  static Texture create2D(GLenum internalFormat, int width, int height, int levels = 1);
  /// Immutable 3-D storage (glTextureStorage3D).
  static Texture create3D(GLenum internalFormat, int width, int height, int depth, int levels = 1);
  /// Wraps a host-owned texture: never deleted by this wrapper.
  static Texture wrap(GLuint id, GLenum target);

  GLuint id() const { return handle_.id(); }
  GLenum target() const { return target_; }
  bool owned() const { return handle_.owned(); }
  GLuint release() { return handle_.release(); }
  explicit operator bool() const { return bool(handle_); }
  int width() const { return width_; }
  int height() const { return height_; }
  int depth() const { return depth_; }
  GLenum internalFormat() const { return format_; }
  /// Bytes of the storage this wrapper allocated, all mip levels (issue 19's memory accounting:
  /// on llvmpipe texture storage is process memory). 0 for a wrapped (host-owned) texture.
  std::size_t bytes() const;
  Texture& label(std::string_view name) &;
  Texture&& label(std::string_view name) && { return std::move(label(name)); }
  /// Sets min/mag filter and wrap mode on the texture object.
  Texture& sampling(GLenum filter, GLenum wrap) &;
  Texture&& sampling(GLenum filter, GLenum wrap) && { return std::move(sampling(filter, wrap)); }
  /// Imagery seen at a slant (issue 14 item 3): builds the mipmap chain from level 0
  /// (glGenerateTextureMipmap; the texture needs mipLevelsFor() levels) and filters trilinearly.
  /// The anisotropic taps are the shader's (glsl/common/imagery.glsl textureAnisotropic, given the
  /// footprint: compute shaders have no implicit derivatives); the sampler's own anisotropy stays
  /// 1 (llvmpipe's returned wrong texels for strongly elongated footprints, docs/imagery.md).
  Texture& mipmapped(GLenum wrap) &;

 private:
  ObjectHandle<&detail::deleteTexture> handle_;
  GLenum target_ = GL_NONE;
  GLenum format_ = GL_NONE;  ///< internal format of owned storage (GL_NONE when wrapped)
  int width_ = 0, height_ = 0, depth_ = 0, levels_ = 0;
};

/// Bytes per texel of the uncompressed internal formats nephele allocates (GL 4.5 table 8.12);
/// UsageError for any other.
std::size_t bytesPerTexel(GLenum internalFormat);

class Buffer {
 public:
  Buffer() = default;
  /// Immutable storage (glNamedBufferStorage) of `bytes`, optionally initialised from `data`.
  static Buffer create(std::size_t bytes, const void* data = nullptr, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
  static Buffer wrap(GLuint id);

  GLuint id() const { return handle_.id(); }
  bool owned() const { return handle_.owned(); }
  GLuint release() { return handle_.release(); }
  std::size_t size() const { return bytes_; }
  Buffer& label(std::string_view name) &;
  Buffer&& label(std::string_view name) && { return std::move(label(name)); }
  void upload(std::size_t offset, std::size_t bytes, const void* data);
  void download(std::size_t offset, std::size_t bytes, void* data) const;

 private:
  ObjectHandle<&detail::deleteBuffer> handle_;
  std::size_t bytes_ = 0;
};

class Framebuffer {
 public:
  Framebuffer() = default;
  static Framebuffer create();
  static Framebuffer wrap(GLuint id);
  GLuint id() const { return handle_.id(); }
  bool owned() const { return handle_.owned(); }
  GLuint release() { return handle_.release(); }
  Framebuffer& label(std::string_view name) &;
  Framebuffer&& label(std::string_view name) && { return std::move(label(name)); }
  Framebuffer& attach(GLenum attachment, const Texture& texture, int level = 0);
  /// Throws GlError unless the framebuffer is complete.
  void checkComplete(std::string_view what) const;

 private:
  ObjectHandle<&detail::deleteFramebuffer> handle_;
};

class VertexArray {
 public:
  VertexArray() = default;
  static VertexArray create();
  GLuint id() const { return handle_.id(); }

 private:
  ObjectHandle<&detail::deleteVertexArray> handle_;
};

class Sampler {
 public:
  Sampler() = default;
  static Sampler create(GLenum filter, GLenum wrap);
  GLuint id() const { return handle_.id(); }

 private:
  ObjectHandle<&detail::deleteSampler> handle_;
};

/// A query object (GL_TIME_ELAPSED, GL_SAMPLES_PASSED, ...).
class Query {
 public:
  Query() = default;
  static Query create(GLenum target);
  GLuint id() const { return handle_.id(); }
  GLenum target() const { return target_; }
  void begin() { glBeginQuery(target_, handle_.id()); }
  void end() { glEndQuery(target_); }
  /// Waits for the result.
  std::uint64_t result() const;

 private:
  ObjectHandle<&detail::deleteQuery> handle_;
  GLenum target_ = GL_NONE;
};

/// Measures GPU time of the commands between start() and stop() with a GL_TIME_ELAPSED query.
class GpuTimer {
 public:
  GpuTimer() : query_(Query::create(GL_TIME_ELAPSED)) {}
  void start() { query_.begin(); }
  void stop() { query_.end(); }
  /// Nanoseconds; waits for the GPU.
  std::uint64_t elapsedNs() const { return query_.result(); }

 private:
  Query query_;
};

}  // namespace nph::gl

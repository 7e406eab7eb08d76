#pragma once
// Shader programs from the embedded GLSL library (STYLE.md 3, after Bruneton's model.cc): a pass is
// a short stage file that #includes the shared library; parameters are injected as generated
// `#define`s right after the #version line, so one source serves several variants.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "render/gl/bindings.h"  // binding points every pass shares with its GLSL
#include "render/gl/objects.h"

namespace nph::gl {

/// Compile-time parameters: {"NAME", "value"} becomes `#define NAME value`.
using Defines = std::vector<std::pair<std::string, std::string>>;

/// Inserts the defines after the #version line of `source`.
std::string injectDefines(std::string_view source, const Defines& defines);

class Program {
 public:
  Program() = default;
  /// Compute program from an embedded stage file, e.g. "test/gradient3d.comp".
  static Program compute(std::string_view name, const Defines& defines = {});
  /// Vertex + fragment program from embedded stage files.
  static Program graphics(std::string_view vertexName, std::string_view fragmentName, const Defines& defines = {});
  /// Compiles and links explicit sources (stage type, label, source). Throws nph::GlError with
  /// the label and the driver's info log on failure.
  static Program fromSources(const std::vector<std::pair<GLenum, std::pair<std::string, std::string>>>& stages);

  GLuint id() const { return handle_.id(); }
  /// The stage files it was built from, e.g. "api/composite.vert + api/composite.frag".
  const std::string& label() const { return label_; }
  explicit operator bool() const { return bool(handle_); }
  void use() const { glUseProgram(id()); }

  /// Location of an active uniform. A name that is not an active uniform of this program — misspelt,
  /// never declared, or declared but optimised away because the shader does not use it — is an
  /// error in strict mode (see setStrictUniforms): GlError naming the program and the uniform.
  /// Otherwise it gives -1 and glProgramUniform* ignores the value, as GL does.
  GLint location(const char* name) const;
  void set(const char* name, int v) const { glProgramUniform1i(id(), location(name), v); }
  void set(const char* name, float v) const { glProgramUniform1f(id(), location(name), v); }
  void set(const char* name, const glm::vec2& v) const { glProgramUniform2f(id(), location(name), v.x, v.y); }
  void set(const char* name, const glm::vec3& v) const { glProgramUniform3f(id(), location(name), v.x, v.y, v.z); }
  void set(const char* name, const glm::vec4& v) const { glProgramUniform4f(id(), location(name), v.x, v.y, v.z, v.w); }
  void set(const char* name, const glm::ivec2& v) const { glProgramUniform2i(id(), location(name), v.x, v.y); }
  void set(const char* name, const glm::ivec3& v) const { glProgramUniform3i(id(), location(name), v.x, v.y, v.z); }
  void set(const char* name, const glm::mat3& m) const;
  void set(const char* name, const glm::mat4& m) const;

  /// Work-group size declared by a compute program.
  glm::ivec3 workGroupSize() const;
  /// glDispatchCompute with enough groups to cover `size` invocations.
  void dispatchCovering(glm::ivec3 size) const;

 private:
  ObjectHandle<&detail::deleteProgram> handle_;
  std::string label_;
};

/// Strict uniforms: setting a uniform that is not active in the program throws GlError (Magnum's
/// AbstractShaderProgram::uniformLocation warns; a silently ignored uniform is a bug that renders
/// plausibly). On by default in debug builds (no NDEBUG) and with NEPHELE_GL_DEBUG=strict; the GL
/// test fixture turns it on for every GL test. Release builds keep GL's rule (ignored), because
/// another driver may optimise away a uniform that llvmpipe keeps.
void setStrictUniforms(bool strict);
bool strictUniforms();

}  // namespace nph::gl

#include "render/gl/program.h"

#include <atomic>

#include <fmt/format.h>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "render/gl/debug.h"
#include "render/gl/shader_sources.h"

namespace nph::gl {
namespace {

std::atomic<bool>& strictUniformsRef() {
  static std::atomic<bool> s{strictByDefault()};
  return s;
}

}  // namespace

void setStrictUniforms(bool strict) { strictUniformsRef().store(strict); }
bool strictUniforms() { return strictUniformsRef().load(); }

GLint Program::location(const char* name) const {
  const GLint loc = glGetUniformLocation(id(), name);
  if (loc < 0 && strictUniforms()) {
    throw GlError(fmt::format("program '{}': '{}' is not an active uniform (misspelt, not declared, or "
                              "optimised away because the shader never reads it)",
                              label_, name));
  }
  return loc;
}

std::string injectDefines(std::string_view source, const Defines& defines) {
  if (defines.empty()) return std::string(source);
  const std::size_t eol = source.find('\n');
  if (source.substr(0, 8) != "#version" || eol == std::string_view::npos) {
    throw GlError("injectDefines: shader source does not start with a #version line");
  }
  std::string out(source.substr(0, eol + 1));
  for (const auto& [name, value] : defines) out += "#define " + name + " " + value + "\n";
  out += source.substr(eol + 1);
  return out;
}

namespace {

std::string infoLog(GLuint object, bool isProgram) {
  GLint length = 0;
  if (isProgram) {
    glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
  } else {
    glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  }
  std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  if (isProgram) {
    glGetProgramInfoLog(object, length, nullptr, log.data());
  } else {
    glGetShaderInfoLog(object, length, nullptr, log.data());
  }
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log;
}

}  // namespace

Program Program::fromSources(const std::vector<std::pair<GLenum, std::pair<std::string, std::string>>>& stages) {
  std::vector<ObjectHandle<&detail::deleteShader>> shaders;
  std::string labels;
  for (const auto& [type, labelled] : stages) {
    const auto& [label, source] = labelled;
    labels += (labels.empty() ? "" : " + ") + label;
    ObjectHandle<&detail::deleteShader> shader(glCreateShader(type), Ownership::Owned);
    const char* text = source.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) throw GlError("GLSL compile error in " + label + ":\n" + infoLog(shader.id(), false));
    shaders.push_back(std::move(shader));
  }
  Program p;
  p.handle_ = ObjectHandle<&detail::deleteProgram>(glCreateProgram(), Ownership::Owned);
  for (const auto& s : shaders) glAttachShader(p.id(), s.id());
  glLinkProgram(p.id());
  for (const auto& s : shaders) glDetachShader(p.id(), s.id());
  GLint ok = GL_FALSE;
  glGetProgramiv(p.id(), GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) throw GlError("GLSL link error in " + labels + ":\n" + infoLog(p.id(), true));
  detail::setLabel(GL_PROGRAM, p.id(), labels);
  p.label_ = labels;
  return p;
}

Program Program::compute(std::string_view name, const Defines& defines) {
  return fromSources({{GL_COMPUTE_SHADER, {std::string(name), injectDefines(shaderSource(name), defines)}}});
}

Program Program::graphics(std::string_view vertexName, std::string_view fragmentName, const Defines& defines) {
  return fromSources(
      {{GL_VERTEX_SHADER, {std::string(vertexName), injectDefines(shaderSource(vertexName), defines)}},
       {GL_FRAGMENT_SHADER, {std::string(fragmentName), injectDefines(shaderSource(fragmentName), defines)}}});
}

void Program::set(const char* name, const glm::mat3& m) const {
  glProgramUniformMatrix3fv(id(), location(name), 1, GL_FALSE, glm::value_ptr(m));
}

void Program::set(const char* name, const glm::mat4& m) const {
  glProgramUniformMatrix4fv(id(), location(name), 1, GL_FALSE, glm::value_ptr(m));
}

glm::ivec3 Program::workGroupSize() const {
  GLint size[3] = {0, 0, 0};
  glGetProgramiv(id(), GL_COMPUTE_WORK_GROUP_SIZE, size);
  return {size[0], size[1], size[2]};
}

void Program::dispatchCovering(glm::ivec3 size) const {
  const glm::ivec3 g = workGroupSize();
  auto groups = [](int n, int per) { return static_cast<GLuint>((n + per - 1) / per); };
  glDispatchCompute(groups(size.x, g.x), groups(size.y, g.y), groups(size.z, g.z));
}

}  // namespace nph::gl

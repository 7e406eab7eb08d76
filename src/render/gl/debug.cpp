#include "render/gl/debug.h"

#include <atomic>
#include <cstdlib>
#include <string>

#include "core/env.h"
#include "core/error.h"
#include "core/log.h"
#include "render/gl/gl.h"

namespace nph::gl {

bool strictByDefault() {
  if (auto v = env::get("NEPHELE_GL_DEBUG")) return *v == "strict";
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

namespace {

std::atomic<bool>& strictRef() {
  static std::atomic<bool> s{strictByDefault()};
  return s;
}

thread_local std::string t_errors;

const char* sourceName(GLenum s) {
  switch (s) {
    case GL_DEBUG_SOURCE_API: return "api";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM: return "window-system";
    case GL_DEBUG_SOURCE_SHADER_COMPILER: return "shader-compiler";
    case GL_DEBUG_SOURCE_THIRD_PARTY: return "third-party";
    case GL_DEBUG_SOURCE_APPLICATION: return "application";
    default: return "other";
  }
}

const char* typeName(GLenum t) {
  switch (t) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined-behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    case GL_DEBUG_TYPE_MARKER: return "marker";
    default: return "other";
  }
}

void APIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                             const GLchar* message, const void* userParam) {
  const bool verbose = userParam != nullptr;
  const std::string text(message, length >= 0 ? std::size_t(length) : std::char_traits<char>::length(message));
  if (type == GL_DEBUG_TYPE_ERROR && source == GL_DEBUG_SOURCE_SHADER_COMPILER) {
    // Compile and link failures are reported by Program with the shader's name and info log.
    log::debug("GL {} {} (id {}): {}", sourceName(source), typeName(type), id, text);
  } else if (type == GL_DEBUG_TYPE_ERROR) {
    log::error("GL {} {} (id {}): {}", sourceName(source), typeName(type), id, text);
    if (!t_errors.empty()) t_errors += "; ";
    t_errors += text;
    if (strictRef().load()) {
      log::error("GL error in strict mode (debug build or NEPHELE_GL_DEBUG=strict): aborting");
      std::abort();
    }
  } else if (type == GL_DEBUG_TYPE_PERFORMANCE) {
    // Advice, not a fault: NVIDIA's driver reports every read-back of a GL_DYNAMIC_DRAW buffer (the
    // passes' statistics) at medium severity — hundreds of lines per benchmark run at warn.
    log::debug("GL {} {} (id {}): {}", sourceName(source), typeName(type), id, text);
  } else if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM) {
    log::warn("GL {} {} (id {}): {}", sourceName(source), typeName(type), id, text);
  } else if (verbose && type != GL_DEBUG_TYPE_PUSH_GROUP && type != GL_DEBUG_TYPE_POP_GROUP) {
    log::debug("GL {} {} (id {}): {}", sourceName(source), typeName(type), id, text);
  }
}

// A non-null user parameter marks verbose mode.
constexpr int kVerboseTag = 1;

}  // namespace

void installDebugOutput(bool verbose) {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(&onDebugMessage, verbose ? &kVerboseTag : nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

void setStrictErrors(bool strict) { strictRef().store(strict); }
bool strictErrors() { return strictRef().load(); }

std::string takeErrors() {
  std::string out;
  out.swap(t_errors);
  // glGetError catches errors the driver did not report through KHR_debug.
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
    if (!out.empty()) out += "; ";
    out += fmt::format("glGetError 0x{:04x}", e);
  }
  return out;
}

void checkErrors(std::string_view where) {
  std::string errors = takeErrors();
  if (!errors.empty()) throw GlError(std::string(where) + ": OpenGL error: " + errors);
}

DebugGroup::DebugGroup(std::string_view name) {
  glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, static_cast<GLsizei>(name.size()), name.data());
}
DebugGroup::~DebugGroup() { glPopDebugGroup(); }

}  // namespace nph::gl

#include "render/gl/context.h"

#include <string>

#include "core/env.h"
#include "core/error.h"
#include "core/log.h"
#include "render/gl/debug.h"
#include "render/gl/gl.h"

namespace nph::gl {
namespace {
// Which GetProcAddress the global entry points currently come from. Contexts of one backend share
// entry points; switching to another backend's context re-resolves them.
void* (*g_loadedFrom)(const char*) = nullptr;

std::string glString(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s != nullptr ? std::string(s) : std::string("?");
}
}  // namespace

std::string_view backendName(Backend backend) {
  switch (backend) {
    case Backend::Auto: return "auto";
    case Backend::Egl: return "egl";
    case Backend::OSMesa: return "osmesa";
    case Backend::Glfw: return "glfw";
  }
  return "?";
}

std::optional<Backend> parseBackend(std::string_view name) {
  for (Backend b : {Backend::Auto, Backend::Egl, Backend::OSMesa, Backend::Glfw}) {
    if (backendName(b) == name) return b;
  }
  return std::nullopt;
}

Backend backendFromEnvironment() {
  const auto v = env::get("NEPHELE_GL");
  if (!v) return Backend::Auto;
  if (auto b = parseBackend(*v)) return *b;
  throw UsageError("NEPHELE_GL=" + *v + ": unknown OpenGL backend, expected auto, egl, osmesa or glfw");
}

void Context::ensureEntryPoints() {
  if (g_loadedFrom != getProc_) {
    loadGlFunctions(getProc_, std::string(backendName(info_.backend)));
    g_loadedFrom = getProc_;
  }
}

void Context::finishInit(Backend backend, std::string detail, bool debug, void* (*getProc)(const char*)) {
  getProc_ = getProc;
  info_.backend = backend;
  info_.detail = std::move(detail);
  g_loadedFrom = nullptr;
  ensureEntryPoints();
  info_.vendor = glString(GL_VENDOR);
  info_.renderer = glString(GL_RENDERER);
  info_.version = glString(GL_VERSION);
  info_.glsl_version = glString(GL_SHADING_LANGUAGE_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &info_.major);
  glGetIntegerv(GL_MINOR_VERSION, &info_.minor);
  if (info_.major * 10 + info_.minor < 45) {
    throw GlError(std::string(backendName(backend)) + ": got OpenGL " + info_.version + " on " + info_.renderer +
                  ", nephele needs 4.5 core");
  }
  info_.debug = debug;
  installDebugOutput(debug);
  log::info("OpenGL backend {} ({}): GL_RENDERER={} GL_VERSION={}", backendName(backend), info_.detail, info_.renderer,
            info_.version);
}

bool softwareRasteriser() {
  const std::string name = glString(GL_RENDERER);
  return name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos;
}

bool debugContextByDefault() {
#ifdef NDEBUG
  return env::get("NEPHELE_GL_DEBUG").has_value();
#else
  return true;
#endif
}

std::unique_ptr<Context> createHeadlessContext(ContextOptions options) {
  options.debug = options.debug.value_or(debugContextByDefault());
  switch (options.backend) {
    case Backend::Egl: return createEglContext(options);
    case Backend::OSMesa: return createOSMesaContext(options);
    case Backend::Glfw:
      throw GlError("glfw: a window needs nephele::render's createContext; nephele::headless makes EGL and OSMesa "
                    "contexts only");
    case Backend::Auto: break;
  }
  // Auto: headless EGL first (GPU or llvmpipe), then OSMesa.
  std::string reasons;
  try {
    return createEglContext(options);
  } catch (const GlError& e) {
    reasons += std::string("\n  egl: ") + e.what();
    log::warn("EGL context failed, trying OSMesa: {}", e.what());
  }
  try {
    return createOSMesaContext(options);
  } catch (const GlError& e) {
    reasons += std::string("\n  osmesa: ") + e.what();
  }
  throw GlError("no OpenGL 4.5 core context could be created:" + reasons);
}

std::unique_ptr<Context> createHeadlessContext(std::string_view gl_option) {
  const auto backend = parseBackend(gl_option);
  if (!backend || *backend == Backend::Glfw) {
    throw UsageError("--gl " + std::string(gl_option) + ": expected auto, egl or osmesa");
  }
  ContextOptions co;
  co.backend = *backend == Backend::Auto ? backendFromEnvironment() : *backend;
  if (co.backend == Backend::Glfw) {
    throw UsageError("NEPHELE_GL=glfw: this command renders headless; expected auto, egl or osmesa");
  }
  co.visible = false;
  return createHeadlessContext(co);
}

}  // namespace nph::gl

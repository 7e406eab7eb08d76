// Headless EGL backend: EGL_EXT_platform_device first, EGL_MESA_platform_surfaceless as fallback.
// No surface is ever created (EGL_KHR_surfaceless_context): nephele renders into FBOs.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/env.h"
#include "core/error.h"
#include "core/limits.h"
#include "core/log.h"
#include "render/gl/context.h"
#include "render/gl/gl.h"

namespace nph::gl {
namespace {

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

std::string eglErrorString(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error 0x" + fmt::format("{:x}", e);
  }
}

void* eglProc(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

class EglContext final : public Context {
 public:
  EglContext(EGLDisplay display, EGLContext context, std::string detail, bool debug)
      : display_(display), context_(context) {
    makeCurrentRaw();
    finishInit(Backend::Egl, std::move(detail), debug, &eglProc);
  }
  ~EglContext() override {
    if (eglGetCurrentContext() == context_) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display_, context_);
    // The display is left initialised: other contexts of this process may share it, and
    // eglTerminate on a shared display would destroy them too.
  }
  void makeCurrent() override {
    makeCurrentRaw();
    ensureEntryPoints();
  }
  void doneCurrent() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }

 private:
  void makeCurrentRaw() {
    if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
      throw GlError("egl: eglMakeCurrent failed: " + eglErrorString(eglGetError()));
    }
  }
  EGLDisplay display_;
  EGLContext context_;
};

/// Creates a GL 4.5 core context on an initialised display, or returns EGL_NO_CONTEXT and a reason.
EGLContext createOnDisplay(EGLDisplay dpy, bool debug, std::string& why) {
  const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
  if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
    why = "display lacks EGL_KHR_surfaceless_context";
    return EGL_NO_CONTEXT;
  }
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    why = "eglBindAPI(EGL_OPENGL_API) failed: " + eglErrorString(eglGetError());
    return EGL_NO_CONTEXT;
  }
  EGLConfig config = nullptr;
  if (!hasExtension(ext, "EGL_KHR_no_config_context")) {
    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(dpy, configAttribs, &config, 1, &count) != EGL_TRUE || count < 1) {
      why = "no EGL config with EGL_OPENGL_BIT";
      return EGL_NO_CONTEXT;
    }
  }
  const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_CONTEXT_OPENGL_DEBUG,
                               debug ? EGL_TRUE : EGL_FALSE,
                               EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctxAttribs);
  if (ctx == EGL_NO_CONTEXT) {
    why = "eglCreateContext(GL 4.5 core) failed: " + eglErrorString(eglGetError());
  }
  return ctx;
}

std::unique_ptr<Context> makeContext(EGLDisplay dpy, EGLContext ctx, std::string detail, bool debug) {
  try {
    return std::make_unique<EglContext>(dpy, ctx, std::move(detail), debug);
  } catch (...) {
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
    throw;
  }
}

}  // namespace

std::unique_ptr<Context> createEglContext(const ContextOptions& options) {
  const bool debug = options.debug.value_or(false);
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (clientExt == nullptr) throw GlError("egl: libEGL has no client extensions (EGL 1.5 needed)");
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (getPlatformDisplay == nullptr) throw GlError("egl: eglGetPlatformDisplayEXT is missing");
  std::string reasons;
  // NEPHELE_EGL_PLATFORM=device|surfaceless restricts the search to one platform (tests use it to
  // exercise both paths); unset tries device first, then surfaceless.
  const std::string platform = env::get("NEPHELE_EGL_PLATFORM").value_or("any");
  if (platform != "any" && platform != "device" && platform != "surfaceless") {
    throw UsageError("NEPHELE_EGL_PLATFORM=" + platform + ": expected device or surfaceless");
  }
  const bool tryDevice = platform != "surfaceless";
  const bool trySurfaceless = platform != "device";

  // 1. EGL_EXT_platform_device: every device EGL enumerates (NVIDIA GPUs, Mesa's software device).
  if (!tryDevice) {
    reasons += "\n    EGL_EXT_platform_device: skipped (NEPHELE_EGL_PLATFORM)";
  } else if (hasExtension(clientExt, "EGL_EXT_platform_device") &&
             hasExtension(clientExt, "EGL_EXT_device_enumeration")) {
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLint count = 0;
    if (queryDevices != nullptr && queryDevices(0, nullptr, &count) == EGL_TRUE && count > 0) {
      std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
      queryDevices(count, devices.data(), &count);
      // NEPHELE_EGL_DEVICE picks one device; by default the first that gives a 4.5 context.
      int only = -1;
      if (auto v = env::get("NEPHELE_EGL_DEVICE")) {
        only = static_cast<int>(
            limits::parseUnsignedStrict("NEPHELE_EGL_DEVICE", *v, 0, 1023));  // std::stoi named nothing
      }
      for (EGLint i = 0; i < count; ++i) {
        if (only >= 0 && i != only) continue;
        EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[std::size_t(i)], nullptr);
        EGLint major = 0, minor = 0;
        if (dpy == EGL_NO_DISPLAY || eglInitialize(dpy, &major, &minor) != EGL_TRUE) {
          reasons += fmt::format("\n    device {}: eglInitialize failed", i);
          continue;
        }
        std::string why;
        EGLContext ctx = createOnDisplay(dpy, debug, why);
        if (ctx == EGL_NO_CONTEXT) {
          reasons += fmt::format("\n    device {}: {}", i, why);
          continue;
        }
        return makeContext(
            dpy, ctx, fmt::format("EGL {}.{} EGL_EXT_platform_device, device {} of {}", major, minor, i, count), debug);
      }
    } else {
      reasons += "\n    EGL_EXT_platform_device: no devices";
    }
  } else {
    reasons += "\n    EGL_EXT_platform_device: not supported by libEGL";
  }

  // 2. EGL_MESA_platform_surfaceless.
  if (!trySurfaceless) {
    reasons += "\n    EGL_MESA_platform_surfaceless: skipped (NEPHELE_EGL_PLATFORM)";
  } else if (hasExtension(clientExt, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, &major, &minor) == EGL_TRUE) {
      std::string why;
      EGLContext ctx = createOnDisplay(dpy, debug, why);
      if (ctx != EGL_NO_CONTEXT) {
        return makeContext(dpy, ctx, fmt::format("EGL {}.{} EGL_MESA_platform_surfaceless", major, minor), debug);
      }
      reasons += "\n    surfaceless: " + why;
    } else {
      reasons += "\n    surfaceless: eglInitialize failed";
    }
  } else {
    reasons += "\n    EGL_MESA_platform_surfaceless: not supported by libEGL";
  }
  throw GlError("egl: no headless EGL display gave an OpenGL 4.5 core context:" + reasons);
}

}  // namespace nph::gl

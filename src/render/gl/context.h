#pragma once
// One interface for the three ways nephele gets an OpenGL 4.5 core context:
//   Egl     headless EGL: EGL_EXT_platform_device first, EGL_MESA_platform_surfaceless as fallback
//           (plain eglGetDisplay(EGL_DEFAULT_DISPLAY) needs X); Mesa llvmpipe and NVIDIA.
//   OSMesa  libOSMesa loaded with dlopen() (it exports its own gl* symbols, so it is never linked),
//           OSMesaCreateContextAttribs with a 4.5 core profile.
//   Glfw    a GLFW window, for the viewer and examples.
// Headless contexts have no usable default framebuffer: render into framebuffer objects.
//
// Two libraries (issue 17): nephele::headless (context.cpp, the EGL and OSMesa backends, the GL
// loader, debug output; needs only core, libEGL and dlopen) is what a host such as the frei0r plugin
// or the CLI links to get a context; createContext() with the GLFW window backend lives in
// nephele::render (context_factory.cpp), so the headless library never loads GLFW or X11.
#include <memory>
#include <optional>
#include <string>
#include <string_view>

struct GLFWwindow;

namespace nph::gl {

enum class Backend { Auto, Egl, OSMesa, Glfw };

std::string_view backendName(Backend backend);
/// "auto", "egl", "osmesa", "glfw" (case-sensitive); nullopt otherwise.
std::optional<Backend> parseBackend(std::string_view name);
/// The backend asked for by NEPHELE_GL, or Auto. Throws UsageError on an unknown value.
Backend backendFromEnvironment();

struct ContextOptions {
  Backend backend = Backend::Auto;
  /// Debug context + synchronous KHR_debug output routed to the log. Defaults: on in debug
  /// builds, and whenever NEPHELE_GL_DEBUG is set.
  std::optional<bool> debug;
  int width = 1280;  ///< window size (Glfw) or OSMesa's colour buffer
  int height = 720;
  bool visible = true;  ///< Glfw only
  std::string title = "nephele";
};

struct ContextInfo {
  Backend backend = Backend::Auto;
  std::string detail;  ///< e.g. "EGL_EXT_platform_device (device 0)"
  std::string vendor, renderer, version, glsl_version;
  int major = 0, minor = 0;
  bool debug = false;
};

class Context {
 public:
  virtual ~Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  /// Makes this context current on the calling thread (and re-resolves the GL entry points if
  /// another backend's were loaded).
  virtual void makeCurrent() = 0;
  /// Releases the context from the calling thread.
  virtual void doneCurrent() = 0;
  virtual void swapBuffers() {}
  virtual GLFWwindow* window() const { return nullptr; }

  const ContextInfo& info() const { return info_; }
  /// The backend's GetProcAddress (eglGetProcAddress, OSMesaGetProcAddress, glfwGetProcAddress):
  /// what a host hands to the plugin API so it loads entry points in this context.
  void* (*getProcAddress() const)(const char*) { return getProc_; }

 protected:
  Context() = default;
  /// Called by backends once current: loads entry points, queries strings, enables debug output.
  void finishInit(Backend backend, std::string detail, bool debug, void* (*getProc)(const char*));
  void ensureEntryPoints();

 private:
  ContextInfo info_;
  void* (*getProc_)(const char*) = nullptr;
};

/// Creates a context for `options.backend`; Auto tries EGL (device, then surfaceless), then
/// OSMesa. The chosen backend, GL_RENDERER and GL_VERSION are logged. Throws nph::GlError with
/// every attempt's reason when no context could be created. In nephele::render (it can open a
/// GLFW window).
std::unique_ptr<Context> createContext(ContextOptions options = {});

/// Whether the current context renders on the CPU (Mesa's llvmpipe or softpipe): its textures are
/// host memory and its compute work runs inside the dispatch call, so choices measured on a GPU
/// (render::ReadBack) may not pay there. Reads GL_RENDERER.
bool softwareRasteriser();

/// Debug contexts: on in debug builds, and whenever NEPHELE_GL_DEBUG is set.
bool debugContextByDefault();

/// createContext() without the window backend, in nephele::headless: Backend::Glfw is a GlError.
std::unique_ptr<Context> createHeadlessContext(ContextOptions options = {});
/// The context of a `--gl` command-line option: "auto" (NEPHELE_GL, else EGL then OSMesa), "egl"
/// or "osmesa"; invisible. UsageError naming the option for anything else.
std::unique_ptr<Context> createHeadlessContext(std::string_view gl_option);

// Backend factories (throw nph::GlError with the reason).
std::unique_ptr<Context> createEglContext(const ContextOptions& options);
std::unique_ptr<Context> createOSMesaContext(const ContextOptions& options);
std::unique_ptr<Context> createGlfwContext(const ContextOptions& options);

}  // namespace nph::gl

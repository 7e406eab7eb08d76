// GLFW window backend (viewer, examples): a GL 4.5 core context with a default framebuffer.
#define GLFW_INCLUDE_NONE  // GL comes from the loader (render/gl/gl.h), never <GL/gl.h>
#include <GLFW/glfw3.h>

#include <mutex>
#include <string>

#include "core/error.h"
#include "core/log.h"
#include "render/gl/context.h"
#include "render/gl/gl.h"

namespace nph::gl {
namespace {

void glfwErrorToLog(int code, const char* description) { log::warn("GLFW error 0x{:x}: {}", code, description); }

void* glfwProc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

/// glfwInit once per process; GLFW is terminated by the last window (see ~GlfwContext).
int& liveWindows() {
  static int n = 0;
  return n;
}

class GlfwContext final : public Context {
 public:
  GlfwContext(GLFWwindow* window, bool debug) : window_(window) {
    glfwMakeContextCurrent(window_);
    finishInit(Backend::Glfw, std::string("GLFW ") + glfwGetVersionString(), debug, &glfwProc);
  }
  ~GlfwContext() override {
    glfwDestroyWindow(window_);
    if (--liveWindows() == 0) glfwTerminate();
  }
  void makeCurrent() override {
    glfwMakeContextCurrent(window_);
    ensureEntryPoints();
  }
  void doneCurrent() override { glfwMakeContextCurrent(nullptr); }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  GLFWwindow* window() const override { return window_; }

 private:
  GLFWwindow* window_;
};

}  // namespace

std::unique_ptr<Context> createGlfwContext(const ContextOptions& options) {
  glfwSetErrorCallback(&glfwErrorToLog);
  if (liveWindows() == 0 && glfwInit() != GLFW_TRUE) {
    throw GlError("glfw: glfwInit failed (is there a display? DISPLAY or WAYLAND_DISPLAY; "
                  "use NEPHELE_GL=egl or osmesa for headless rendering)");
  }
  const bool debug = options.debug.value_or(false);
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    if (liveWindows() == 0) glfwTerminate();
    throw GlError("glfw: could not create a window with an OpenGL 4.5 core context");
  }
  ++liveWindows();
  try {
    return std::make_unique<GlfwContext>(window, debug);
  } catch (...) {
    glfwDestroyWindow(window);
    if (--liveWindows() == 0) glfwTerminate();
    throw;
  }
}

}  // namespace nph::gl

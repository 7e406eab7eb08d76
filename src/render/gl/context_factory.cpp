// createContext(): the headless backends of nephele::headless (context.cpp) plus the GLFW window
// (context_glfw.cpp), which is why this factory lives in nephele::render and not in the headless
// library that the frei0r plugin links (issue 17).
#include "core/error.h"
#include "render/gl/context.h"

namespace nph::gl {

std::unique_ptr<Context> createContext(ContextOptions options) {
  if (options.backend != Backend::Glfw) return createHeadlessContext(options);
  options.debug = options.debug.value_or(debugContextByDefault());
  return createGlfwContext(options);
}

#ifndef NEPHELE_HAVE_GLFW
std::unique_ptr<Context> createGlfwContext(const ContextOptions&) {
  throw GlError("glfw: this build of nephele has no GLFW backend (NEPHELE_BUILD_GLFW=OFF)");
}
#endif

}  // namespace nph::gl

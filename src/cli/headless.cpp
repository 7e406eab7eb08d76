#include "cli/headless.h"

#include "core/error.h"

namespace nph::cli {

std::unique_ptr<gl::Context> createHeadlessContext(const std::string& gl_option) {
  const auto backend = gl::parseBackend(gl_option);
  if (!backend) throw UsageError("--gl " + gl_option + ": expected auto, egl or osmesa");
  gl::ContextOptions co;
  co.backend = *backend == gl::Backend::Auto ? gl::backendFromEnvironment() : *backend;
  co.visible = false;
  return gl::createContext(co);
}

}  // namespace nph::cli

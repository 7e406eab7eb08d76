// nephele_glinfo: creates a context on the backend named by NEPHELE_GL (or auto) and prints it.
#include <cstdio>
#include <exception>

#include "render/gl/context.h"

int main() {
  try {
    nph::gl::ContextOptions options;
    options.backend = nph::gl::backendFromEnvironment();
    options.visible = false;
    auto ctx = nph::gl::createContext(options);
    const auto& info = ctx->info();
    std::printf("backend=%s (%s) GL_RENDERER=%s GL_VERSION=%s\n",
                std::string(nph::gl::backendName(info.backend)).c_str(), info.detail.c_str(), info.renderer.c_str(),
                info.version.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nephele_glinfo: %s\n", e.what());
    return 1;
  }
}

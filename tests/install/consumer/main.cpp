// Builds against an installed nephele and renders nothing but a context: proves the package
// config, exported targets, installed headers and generated loader header all fit together.
#include <cstdio>
#include <exception>

#include "render/gl/context.h"
#include "render/gl/gl.h"

int main() {
  try {
    auto ctx = nph::gl::createContext({});
    GLint major = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    std::printf("consumer: %s, GL major %d\n", ctx->info().renderer.c_str(), major);
    return major == 4 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}

#include "support/gl_fixture.h"

#include "core/env.h"
#include "core/log.h"
#include "render/gl/program.h"

namespace nph::test {

gl::Context& glContext() {
  static std::unique_ptr<gl::Context> ctx = [] {
    gl::ContextOptions options;
    options.backend = gl::backendFromEnvironment();
    options.debug = true;
    options.width = 64;
    options.height = 64;
    options.visible = false;
    return gl::createContext(options);
  }();
  return *ctx;
}

void GlTest::SetUp() {
  gl::Context& ctx = glContext();  // throws -> the test fails (never skips)
  ctx.makeCurrent();
  gl::setStrictUniforms(true);  // a uniform the shader does not have fails the test (program.h)
  (void)gl::takeErrors();
}

void GlTest::TearDown() {
  const std::string errors = gl::takeErrors();
  EXPECT_TRUE(errors.empty()) << "GL errors left by the test: " << errors;
}

}  // namespace nph::test

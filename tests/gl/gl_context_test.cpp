#include <gtest/gtest.h>

#include "core/env.h"
#include "core/error.h"
#include "render/gl/context.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

using GlContextTest = GlTest;

TEST_F(GlContextTest, IsTheRequestedBackendWithGl45Core) {
  const auto& info = glContext().info();
  const gl::Backend requested = gl::backendFromEnvironment();
  if (requested != gl::Backend::Auto) {
    EXPECT_EQ(info.backend, requested) << "no silent fallback to another backend";
  }
  if (auto platform = env::get("NEPHELE_EGL_PLATFORM")) {
    const std::string expected = *platform == "device" ? "EGL_EXT_platform_device" : "EGL_MESA_platform_surfaceless";
    EXPECT_NE(info.detail.find(expected), std::string::npos) << info.detail;
  }
  EXPECT_GE(info.major * 10 + info.minor, 45) << info.version;
  EXPECT_FALSE(info.renderer.empty());
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT) << "core profile expected";
  GLint invocations = 0;
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &invocations);
  EXPECT_GE(invocations, 1024) << "compute shaders (GL 4.3+) required";
  // On CI the renderer must be llvmpipe; set NEPHELE_EXPECT_RENDERER to check another.
  if (auto expect = env::get("NEPHELE_EXPECT_RENDERER")) {
    EXPECT_NE(info.renderer.find(*expect), std::string::npos) << info.renderer;
  }
  std::printf("[ backend  ] %s (%s): %s, %s\n", std::string(gl::backendName(info.backend)).c_str(), info.detail.c_str(),
              info.renderer.c_str(), info.version.c_str());
}

TEST_F(GlContextTest, MakeCurrentIsIdempotentAndDoneCurrentReleases) {
  glContext().makeCurrent();
  glContext().makeCurrent();
  GLint v = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &v);
  EXPECT_EQ(v, 4);
}

TEST(GlContextNoFixture, UnknownBackendNameIsAUsageError) {
  EXPECT_FALSE(gl::parseBackend("vulkan").has_value());
  EXPECT_EQ(gl::parseBackend("osmesa"), gl::Backend::OSMesa);
  const auto saved = env::get("NEPHELE_GL");
  ::setenv("NEPHELE_GL", "vulkan", 1);
  EXPECT_THROW(gl::backendFromEnvironment(), UsageError);
  if (saved) ::setenv("NEPHELE_GL", saved->c_str(), 1);
  else ::unsetenv("NEPHELE_GL");
}

TEST_F(GlContextTest, GlErrorIsReportedByCheckErrors) {
  // Strict mode (the default in Debug builds) aborts; this test checks the non-strict path.
  const bool savedStrict = gl::strictErrors();
  gl::setStrictErrors(false);
  glBindTexture(GL_TEXTURE_3D, 0xdeadbeefu);  // an invalid name: GL_INVALID_OPERATION
  try {
    gl::checkErrors("deliberate invalid bind");
    FAIL() << "checkErrors did not throw";
  } catch (const GlError& e) {
    EXPECT_NE(std::string(e.what()).find("deliberate invalid bind"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(gl::takeErrors().empty());
  gl::setStrictErrors(savedStrict);
}

TEST(GlStrictDeathTest, GlErrorAbortsInStrictMode) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        gl::setStrictErrors(true);
        glContext().makeCurrent();
        glBindTexture(GL_TEXTURE_3D, 0xdeadbeefu);
      },
      "strict mode");
}

}  // namespace
}  // namespace nph::test

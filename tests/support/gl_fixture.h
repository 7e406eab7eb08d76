#pragma once
// GL test fixture: one context per test binary, on the backend named by NEPHELE_GL (CTest runs the
// GL suite once per headless backend: egl-device, egl-surfaceless, osmesa). No GL test ever skips:
// a missing context is a failure, because CI has Mesa llvmpipe.
#include <gtest/gtest.h>

#include <memory>

#include "render/gl/context.h"
#include "render/gl/debug.h"
#include "render/gl/gl.h"

namespace nph::test {

/// The process-wide test context (created on first use; failure is fatal for the test).
gl::Context& glContext();

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
};

}  // namespace nph::test

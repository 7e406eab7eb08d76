#pragma once
// GL test fixture: one context per test binary, on the backend named by NEPHELE_GL (CTest runs the
// GL suite once per headless backend: egl-device, egl-surfaceless, osmesa). No GL test ever skips:
// a missing context is a failure, because CI has Mesa llvmpipe.
#include <gtest/gtest.h>

#include <memory>
#include <string_view>

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

/// True on a software rasteriser (Mesa llvmpipe or softpipe: CI's). There the texture filter
/// computes its weights in float like the CPU twins, and one compiler builds every program. On a
/// GPU (docs/benchmarks.md "On an NVIDIA GPU") the filter's weights are 8-bit fixed point, each
/// program is compiled on its own (FMA contraction may differ by an ulp), and float→unorm8 rounds
/// the driver's way: the GPU-against-CPU tests widen their bounds there to the H200's measured
/// figures with margin, and keep CI's strict bounds on llvmpipe.
inline bool softwareRasteriser() { return gl::softwareRasteriser(); }

}  // namespace nph::test

#include <gtest/gtest.h>

#include <vector>

#include "core/error.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "support/gl_fixture.h"
#include "support/image_compare.h"

namespace nph::test {
namespace {

using GlObjectsTest = GlTest;

// CPU side of glsl/test/gradient.glsl.
glm::vec4 gradientValue(int x, int y, int z, float scale) {
  return glm::vec4(float(x), float(y), float(z), float(x + 2 * y + 3 * z)) * scale;
}

// A known image: a compute shader writes a gradient into a 3-D RGBA32F texture, read back and
// compared exactly. Tolerance 0: every value is a small integer times a power of two, exactly
// representable in float, and no arithmetic in the shader rounds.
TEST_F(GlObjectsTest, ComputeGradientInto3DTextureIsExact) {
  const glm::ivec3 size(13, 7, 5);  // not multiples of the 4x4x4 work group: edge handling
  const float scale = 0.25f;
  auto tex = gl::Texture::create3D(GL_RGBA32F, size.x, size.y, size.z).label("gradient");
  auto prog = gl::Program::compute("test/gradient3d.comp", {{"GRADIENT_SCALE", "0.25"}});
  prog.use();
  prog.set("u_size", size);
  glBindImageTexture(gl::binding::IMAGE_TEST_OUT, tex.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  prog.dispatchCovering(size);
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
  std::vector<glm::vec4> got(std::size_t(size.x * size.y * size.z));
  glGetTextureImage(tex.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(got.size() * sizeof(glm::vec4)), got.data());
  gl::checkErrors("gradient compute");
  int mismatches = 0;
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const glm::vec4 want = gradientValue(x, y, z, scale);
        const glm::vec4 have = got[std::size_t((z * size.y + y) * size.x + x)];
        if (have != want && ++mismatches < 5) {
          ADD_FAILURE() << "voxel " << x << "," << y << "," << z << ": got " << have.x << " " << have.y << " " << have.z
                        << " " << have.w;
        }
      }
  EXPECT_EQ(mismatches, 0);
}

// The raster path: a full-screen triangle draws one slice of the same gradient into an RGBA32F
// framebuffer; compared with the image helper at tolerance 0 (exact, as above).
TEST_F(GlObjectsTest, RasterGradientSliceMatchesExactly) {
  const int w = 16, h = 9, slice = 3;
  auto colour = gl::Texture::create2D(GL_RGBA32F, w, h).label("slice colour");
  auto fbo = gl::Framebuffer::create().label("slice fbo");
  fbo.attach(GL_COLOR_ATTACHMENT0, colour);
  fbo.checkComplete("gradient slice");
  auto vao = gl::VertexArray::create();
  auto prog = gl::Program::graphics("render/fullscreen.vert", "test/gradient_slice.frag");
  prog.set("u_slice", slice);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glViewport(0, 0, w, h);
  prog.use();
  glBindVertexArray(vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  Image actual{w, h, 4, std::vector<float>(std::size_t(w * h * 4))};
  glGetTextureImage(colour.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(actual.pixels.size() * sizeof(float)),
                    actual.pixels.data());
  gl::checkErrors("gradient slice");
  Image expected{w, h, 4, std::vector<float>(std::size_t(w * h * 4))};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 v = gradientValue(x, y, slice, 1.0f);
      for (int c = 0; c < 4; ++c) expected.at(x, y, c) = v[c];
    }
  const auto r = compareImages(actual, expected, {0.0, 0.0}, "gl_gradient_slice");
  EXPECT_TRUE(r.pass) << r.message;
}

TEST_F(GlObjectsTest, HostOwnedTextureSurvivesTheWrapper) {
  GLuint hostId = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &hostId);
  glTextureStorage2D(hostId, 1, GL_R32F, 4, 4);
  const std::vector<float> data(16, 42.0f);
  glTextureSubImage2D(hostId, 0, 0, 0, 4, 4, GL_RED, GL_FLOAT, data.data());
  {
    auto wrapped = gl::Texture::wrap(hostId, GL_TEXTURE_2D);
    EXPECT_FALSE(wrapped.owned());
    EXPECT_EQ(wrapped.id(), hostId);
    EXPECT_EQ(wrapped.width(), 4);
    EXPECT_EQ(wrapped.height(), 4);
    gl::Texture moved = std::move(wrapped);  // moving keeps it non-owning
    EXPECT_FALSE(moved.owned());
  }
  EXPECT_EQ(glIsTexture(hostId), GL_TRUE) << "the wrapper deleted a host-owned texture";
  std::vector<float> back(16, 0.0f);
  glGetTextureImage(hostId, 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(back.size() * sizeof(float)), back.data());
  EXPECT_EQ(back, data) << "host texture contents changed";
  glDeleteTextures(1, &hostId);
}

TEST_F(GlObjectsTest, OwnedObjectsAreDeletedExactlyOnce) {
  GLuint texId = 0, bufId = 0, fboId = 0;
  {
    auto tex = gl::Texture::create2D(GL_RGBA8, 2, 2);
    auto buf = gl::Buffer::create(64);
    auto fbo = gl::Framebuffer::create();
    texId = tex.id();
    bufId = buf.id();
    fboId = fbo.id();
    EXPECT_TRUE(tex.owned());
    gl::Texture other = std::move(tex);  // moved-from wrapper must not delete
    EXPECT_EQ(tex.id(), 0u);             // NOLINT(bugprone-use-after-move): checking the moved-from state
    EXPECT_EQ(glIsTexture(texId), GL_TRUE);
  }
  EXPECT_EQ(glIsTexture(texId), GL_FALSE);
  EXPECT_EQ(glIsBuffer(bufId), GL_FALSE);
  EXPECT_EQ(glIsFramebuffer(fboId), GL_FALSE);
}

TEST_F(GlObjectsTest, ReleaseHandsOwnershipToTheCaller) {
  auto buf = gl::Buffer::create(16);
  const GLuint id = buf.release();
  EXPECT_EQ(buf.id(), 0u);
  EXPECT_EQ(glIsBuffer(id), GL_TRUE);
  glDeleteBuffers(1, &id);
}

TEST_F(GlObjectsTest, BufferRoundTripAndBoundsCheck) {
  const std::vector<std::uint32_t> in = {1, 2, 3, 4, 5, 6, 7, 8};
  auto buf = gl::Buffer::create(in.size() * 4, in.data()).label("roundtrip");
  std::vector<std::uint32_t> out(in.size());
  buf.download(0, out.size() * 4, out.data());
  EXPECT_EQ(out, in);
  EXPECT_THROW(buf.upload(16, 32, in.data()), UsageError);
}

TEST_F(GlObjectsTest, GpuTimerMeasuresWork) {
  gl::GpuTimer timer;
  auto tex = gl::Texture::create3D(GL_RGBA32F, 32, 32, 32);
  auto prog = gl::Program::compute("test/gradient3d.comp");
  prog.set("u_size", glm::ivec3(32));
  timer.start();
  prog.use();
  glBindImageTexture(gl::binding::IMAGE_TEST_OUT, tex.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  prog.dispatchCovering(glm::ivec3(32));
  timer.stop();
  EXPECT_GT(timer.elapsedNs(), 0u);
}

}  // namespace
}  // namespace nph::test

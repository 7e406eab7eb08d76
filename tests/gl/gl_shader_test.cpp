#include <gtest/gtest.h>

#include "core/error.h"
#include "render/gl/program.h"
#include "render/gl/shader_sources.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

using GlShaderTest = GlTest;

GLenum stageOf(std::string_view name) {
  if (name.ends_with(".comp")) return GL_COMPUTE_SHADER;
  if (name.ends_with(".vert")) return GL_VERTEX_SHADER;
  if (name.ends_with(".frag")) return GL_FRAGMENT_SHADER;
  return GL_GEOMETRY_SHADER;
}

// Real compile of every embedded stage on this context's driver (llvmpipe on CI). Vertex and
// fragment stages are compiled as shader objects (linking needs a pair); compute stages link.
TEST_F(GlShaderTest, EveryEmbeddedShaderCompiles) {
  ASSERT_GE(gl::embeddedShaders().size(), 4u);
  for (const auto& s : gl::embeddedShaders()) {
    SCOPED_TRACE(s.name);
    if (stageOf(s.name) == GL_COMPUTE_SHADER) {
      EXPECT_NO_THROW(gl::Program::compute(s.name));
      continue;
    }
    const GLuint shader = glCreateShader(stageOf(s.name));
    glShaderSource(shader, 1, &s.source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    EXPECT_EQ(ok, GL_TRUE);
    glDeleteShader(shader);
  }
}

TEST_F(GlShaderTest, IncludesAreResolvedAtEmbedTime) {
  const std::string_view src = gl::shaderSource("test/gradient3d.comp");
  EXPECT_EQ(src.find("#include"), std::string_view::npos);
  EXPECT_NE(src.find("vec4 gradientValue(ivec3 v)"), std::string_view::npos);
  EXPECT_NE(src.find("bool insideGrid("), std::string_view::npos);
}

TEST_F(GlShaderTest, CompileErrorNamesTheShader) {
  try {
    gl::Program::fromSources({{GL_COMPUTE_SHADER, {"broken.comp", "#version 450 core\nvoid main() { nope; }\n"}}});
    FAIL() << "expected a GlError";
  } catch (const GlError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.comp"), std::string::npos) << e.what();
  }
  (void)gl::takeErrors();
}

TEST(ShaderLibrary, DefinesGoAfterTheVersionLine) {
  const std::string out = gl::injectDefines("#version 450 core\nvoid main(){}\n", {{"STEPS", "64"}, {"FAST", "1"}});
  EXPECT_EQ(out, "#version 450 core\n#define STEPS 64\n#define FAST 1\nvoid main(){}\n");
  EXPECT_THROW(gl::injectDefines("void main(){}", {{"A", "1"}}), GlError);
  EXPECT_THROW(gl::shaderSource("no/such.comp"), GlError);
}

}  // namespace
}  // namespace nph::test

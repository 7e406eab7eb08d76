#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "render/gl/program.h"
#include "render/gl/shader_sources.h"
#include "render/gl/uniform_blocks.h"
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

// Issue #17 done criterion: a misspelt uniform name fails. In strict mode (debug builds,
// NEPHELE_GL_DEBUG=strict, every GL test through the fixture) setting a name the program does not
// have throws a GlError naming the program and the uniform; a declared but unused (optimised away)
// uniform is the same error. Outside strict mode GL's rule stands: location -1, value ignored.
TEST_F(GlShaderTest, MisspeltOrInactiveUniformIsAnErrorInStrictMode) {
  const bool saved = gl::strictUniforms();
  gl::setStrictUniforms(true);
  const gl::Program prog = gl::Program::compute("test/gradient3d.comp");
  EXPECT_NO_THROW(prog.set("u_size", glm::ivec3(4)));
  try {
    prog.set("u_sise", glm::ivec3(4));
    ADD_FAILURE() << "a misspelt uniform was accepted";
  } catch (const GlError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'u_sise'"), std::string::npos) << what;
    EXPECT_NE(what.find("test/gradient3d.comp"), std::string::npos) << what;
  }
  const gl::Program unused = gl::Program::fromSources(
      {{GL_COMPUTE_SHADER,
        {"unused.comp",
         "#version 450 core\nlayout(local_size_x = 1) in;\nuniform float u_unused;\nvoid main() {}\n"}}});
  EXPECT_THROW(unused.set("u_unused", 1.0f), GlError);
  gl::setStrictUniforms(false);
  EXPECT_EQ(prog.location("u_sise"), -1);
  EXPECT_NO_THROW(prog.set("u_sise", glm::ivec3(4)));
  gl::setStrictUniforms(saved);
}

// The binding points of render/gl/bindings.h reach every stage as #defines right after #version,
// and no stage writes a binding number itself.
TEST(ShaderLibrary, BindingsAreInjectedAndNeverLiteral) {
  const std::regex literalBinding(R"(binding\s*=\s*[0-9])");
  for (const auto& s : gl::embeddedShaders()) {
    SCOPED_TRACE(s.name);
    const std::string src = s.source;
    EXPECT_TRUE(src.substr(src.find('\n') + 1).starts_with("// ---- begin bindings"));
    for (const auto& e : gl::binding::kAll) {
      EXPECT_NE(src.find("#define " + std::string(e.name) + " "), std::string::npos) << e.name;
    }
    EXPECT_FALSE(std::regex_search(src, literalBinding));
  }
}

// Within one stage, every binding NAME it declares has its own number in that GL namespace (texture
// units, image units, SSBOs, uniform blocks): two samplers on one unit compile and link silently and
// read the same texture (issue 14's merge put the column depths and the transmittance table on unit
// 10: only a rendering test noticed). The stages' resolved sources include everything they use.
TEST(ShaderLibrary, BindingNumbersOfEachStageAreDistinct) {
  const std::regex use(R"(binding\s*=\s*([A-Z][A-Z0-9_]*))");
  for (const auto& s : gl::embeddedShaders()) {
    SCOPED_TRACE(s.name);
    const std::string src = s.source;
    std::vector<std::pair<std::string, unsigned>> seen;  // (name, value) of each binding used
    for (auto it = std::sregex_iterator(src.begin(), src.end(), use); it != std::sregex_iterator(); ++it) {
      const std::string name = (*it)[1];
      const auto entry = std::find_if(std::begin(gl::binding::kAll), std::end(gl::binding::kAll),
                                      [&](const gl::binding::Entry& e) { return e.name == name; });
      ASSERT_NE(entry, std::end(gl::binding::kAll)) << name << " is not in render/gl/bindings.h";
      const std::string prefix = name.substr(0, name.find('_') + 1);
      for (const auto& [other, value] : seen) {
        if (other != name && value == entry->value && other.starts_with(prefix)) {
          ADD_FAILURE() << s.name << ": " << name << " and " << other << " share " << prefix << " number " << value;
        }
      }
      seen.emplace_back(name, entry->value);
    }
  }
}

// Each std140 block of render/gl/uniform_blocks.h against the driver's layout of every program
// that declares it: block size, and each member's offset and block (GL 4.5 §7.3.1 interface
// queries). A member changed on one side only fails here.
TEST_F(GlShaderTest, UniformBlocksMatchTheLinkedPrograms) {
  struct Case {
    const char* block;
    unsigned binding;
    std::size_t size;
    std::span<const gl::BlockMember> members;
    std::vector<std::pair<const char*, gl::Defines>> programs;
  };
  const std::vector<Case> cases = {
      {gl::LightSpaceBlock::kGlslName,
       gl::LightSpaceBlock::kBinding,
       sizeof(gl::LightSpaceBlock),
       gl::kLightSpaceMembers,
       {{"dlm/march.comp", {}},
        {"dlm/march.comp", {{"PERIPHERAL", "1"}}},
        {"dlm/march.comp", {{"UNCOMPRESSED", "1"}}},
        {"dlm/scatter.comp", {}},
        {"render/clouds.comp", {}},
        {"test/dlm_lookup.comp", {}}}},
      {gl::VolumeBlock::kGlslName,
       gl::VolumeBlock::kBinding,
       sizeof(gl::VolumeBlock),
       gl::kVolumeMembers,
       {{"dlm/march.comp", {}}, {"dlm/scatter.comp", {}}, {"render/clouds.comp", {}}}},
      {gl::RaycastBlock::kGlslName,
       gl::RaycastBlock::kBinding,
       sizeof(gl::RaycastBlock),
       gl::kRaycastMembers,
       {{"render/clouds.comp", {}}}},
      {gl::GlobeBlock::kGlslName,
       gl::GlobeBlock::kBinding,
       sizeof(gl::GlobeBlock),
       gl::kGlobeMembers,
       {{"render/clouds.comp", {}}}},
      {gl::TerrainBlock::kGlslName,
       gl::TerrainBlock::kBinding,
       sizeof(gl::TerrainBlock),
       gl::kTerrainMembers,
       {{"render/clouds.comp", {}}}},
      {gl::AtmosphereBlock::kGlslName,
       gl::AtmosphereBlock::kBinding,
       sizeof(gl::AtmosphereBlock),
       gl::kAtmosphereMembers,
       {{"atmosphere/transmittance.comp", {}},
        {"atmosphere/multiscattering.comp", {}},
        {"atmosphere/sky_view.comp", {}},
        {"atmosphere/sky_irradiance.comp", {}},
        {"test/atmosphere_probe.comp", {}},
        {"render/clouds.comp", {}}}},
  };
  for (const Case& c : cases) {
    for (const auto& [name, defines] : c.programs) {
      SCOPED_TRACE(std::string(c.block) + " in " + name);
      const gl::Program p = gl::Program::compute(name, defines);
      const GLuint block = glGetProgramResourceIndex(p.id(), GL_UNIFORM_BLOCK, c.block);
      ASSERT_NE(block, GL_INVALID_INDEX);
      const GLenum blockProps[] = {GL_BUFFER_DATA_SIZE, GL_BUFFER_BINDING};
      GLint blockValues[2] = {0, 0};
      glGetProgramResourceiv(p.id(), GL_UNIFORM_BLOCK, block, 2, blockProps, 2, nullptr, blockValues);
      // The driver's size may leave out the std140 rounding of the block to 16 bytes.
      EXPECT_LE(std::size_t(blockValues[0]), c.size);
      EXPECT_GT(std::size_t(blockValues[0]) + 16, c.size);
      EXPECT_EQ(blockValues[1], GLint(c.binding));
      for (const gl::BlockMember& m : c.members) {
        const GLuint u = glGetProgramResourceIndex(p.id(), GL_UNIFORM, m.glsl_name);
        ASSERT_NE(u, GL_INVALID_INDEX) << m.glsl_name;
        const GLenum props[] = {GL_OFFSET, GL_BLOCK_INDEX};
        GLint values[2] = {-1, -1};
        glGetProgramResourceiv(p.id(), GL_UNIFORM, u, 2, props, 2, nullptr, values);
        EXPECT_EQ(std::size_t(values[0]), m.offset) << m.glsl_name;
        EXPECT_EQ(GLuint(values[1]), block) << m.glsl_name;
      }
    }
  }
}

// Texture and image units only have to be distinct among the samplers (images) one program uses
// (render/gl/bindings.h) — and there they must be: two samplers on one unit read the same texture,
// which compiles and links without a word (issue 14: the column depths and the transmittance table
// shared unit 10 and the ground came out 10x too dark). Every compute program, each variant the
// passes build, is asked for its active samplers and images and their units (GL 4.5 §7.3.1).
TEST_F(GlShaderTest, EveryProgramGivesEachSamplerAndImageItsOwnUnit) {
  std::vector<std::pair<std::string, gl::Defines>> programs;
  for (const auto& s : gl::embeddedShaders()) {
    if (stageOf(s.name) == GL_COMPUTE_SHADER) programs.push_back({s.name, {}});
  }
  programs.push_back({"dlm/march.comp", {{"PERIPHERAL", "1"}}});
  programs.push_back({"dlm/march.comp", {{"UNCOMPRESSED", "1"}}});
  ASSERT_GE(programs.size(), 8u);
  int samplers_seen = 0;
  for (const auto& [name, defines] : programs) {
    SCOPED_TRACE(name);
    const gl::Program p = gl::Program::compute(name, defines);
    GLint count = 0;
    glGetProgramInterfaceiv(p.id(), GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
    std::map<GLint, std::string> texture_units, image_units;
    for (GLint u = 0; u < count; ++u) {
      const GLenum props[] = {GL_TYPE, GL_LOCATION, GL_BLOCK_INDEX};
      GLint v[3] = {0, -1, -1};
      glGetProgramResourceiv(p.id(), GL_UNIFORM, GLuint(u), 3, props, 3, nullptr, v);
      if (v[2] != -1 || v[1] < 0) continue;  // block members have no unit
      char uniform_name[256] = {};
      glGetProgramResourceName(p.id(), GL_UNIFORM, GLuint(u), sizeof(uniform_name), nullptr, uniform_name);
      const GLenum type = GLenum(v[0]);
      const bool is_image = (type >= GL_IMAGE_1D && type <= GL_IMAGE_2D_MULTISAMPLE_ARRAY) ||
                            (type >= GL_INT_IMAGE_1D && type <= GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY);
      const bool is_sampler = (type >= GL_SAMPLER_1D && type <= GL_SAMPLER_2D_SHADOW) ||
                              (type >= GL_SAMPLER_1D_ARRAY && type <= GL_SAMPLER_CUBE_SHADOW) ||
                              (type >= GL_INT_SAMPLER_1D && type <= GL_UNSIGNED_INT_SAMPLER_2D_ARRAY) ||
                              type == GL_SAMPLER_2D_RECT || type == GL_SAMPLER_BUFFER ||
                              type == GL_INT_SAMPLER_BUFFER || type == GL_UNSIGNED_INT_SAMPLER_BUFFER;
      if (!is_image && !is_sampler) continue;
      GLint unit = -1;
      glGetUniformiv(p.id(), v[1], &unit);
      auto& units = is_image ? image_units : texture_units;
      const auto [it, fresh] = units.emplace(unit, uniform_name);
      EXPECT_TRUE(fresh) << uniform_name << " and " << it->second << " share " << (is_image ? "image" : "texture")
                         << " unit " << unit;
      if (is_sampler) ++samplers_seen;
    }
  }
  EXPECT_GE(samplers_seen, 20);  // the query found the samplers (clouds.comp alone has 15+)
}

TEST(ShaderLibrary, DefinesGoAfterTheVersionLine) {
  const std::string out = gl::injectDefines("#version 450 core\nvoid main(){}\n", {{"STEPS", "64"}, {"FAST", "1"}});
  EXPECT_EQ(out, "#version 450 core\n#define STEPS 64\n#define FAST 1\nvoid main(){}\n");
  EXPECT_THROW(gl::injectDefines("void main(){}", {{"A", "1"}}), GlError);
  EXPECT_THROW(gl::shaderSource("no/such.comp"), GlError);
}

}  // namespace
}  // namespace nph::test

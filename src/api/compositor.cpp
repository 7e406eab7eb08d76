#include "api/compositor.h"

#include <cmath>

#include "render/gl/bindings.h"
#include "render/gl/debug.h"

namespace nph::api {

Compositor::Compositor()
    : program_(gl::Program::graphics("api/composite.vert", "api/composite.frag")),
      vertex_array_(gl::VertexArray::create()),
      sampler_(gl::Sampler::create(GL_LINEAR, GL_CLAMP_TO_EDGE)) {}

void Compositor::draw(const gl::Texture& layer, const CompositeSettings& s) const {
  gl::DebugGroup group("nephele composite");
  program_.set("u_exposure_scale",
               glm::vec3(std::exp2(s.exposure_ev) * scene::whiteBalanceGain(s.white_balance_k, s.white_balance_duv)));
  program_.set("u_display", s.display ? 1 : 0);
  program_.set("u_select", int(Select::Rgba));
  drawTriangle(layer, /*blend=*/true);
}

void Compositor::copy(const gl::Texture& source, Select select, glm::dvec3 scale) const {
  gl::DebugGroup group("nephele pass copy");
  program_.set("u_exposure_scale", glm::vec3(scale));
  program_.set("u_display", 0);
  program_.set("u_select", int(select));
  drawTriangle(source, /*blend=*/false);
}

void Compositor::drawTriangle(const gl::Texture& source, bool blend) const {
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  program_.set("u_viewport", glm::vec4(float(viewport[0]), float(viewport[1]), float(viewport[2]), float(viewport[3])));
  // Unbind the compute program of the passes before binding ours. Mesa keeps, per shader stage,
  // a reference to the last program object bound while that stage's program changed; binding
  // this vertex+fragment program straight after a compute dispatch records it as the compute
  // stage's referenced program, and the host's graphics program never clears that slot, so
  // renderer_destroy's glDeleteProgram left it alive (issue 18; api.c99 counts the names).
  glUseProgram(0);
  program_.use();
  glBindVertexArray(vertex_array_.id());
  glBindTextureUnit(gl::binding::UNIT_COMPOSITE_LAYER, source.id());
  glBindSampler(gl::binding::UNIT_COMPOSITE_LAYER, sampler_.id());
  // Premultiplied "over" into draw buffer 0 (or a plain copy); nothing else may reject or alter
  // the fragments.
  if (blend) {
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparatei(0, GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparatei(0, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  } else {
    glDisablei(GL_BLEND, 0);
  }
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  for (GLenum cap : {GL_DEPTH_TEST, GL_STENCIL_TEST, GL_CULL_FACE, GL_DITHER, GL_RASTERIZER_DISCARD,
                     GL_SAMPLE_ALPHA_TO_COVERAGE, GL_COLOR_LOGIC_OP}) {
    glDisable(cap);
  }
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  gl::checkErrors("plugin API composite pass");
}

}  // namespace nph::api

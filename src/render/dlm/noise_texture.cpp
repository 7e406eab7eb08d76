#include "render/dlm/noise_texture.h"

#include "render/gl/bindings.h"
#include "render/gl/program.h"
#include "volume/noise.h"

namespace nph::render {

std::shared_ptr<const NoiseTexture> NoiseTexture::generate() {
  auto n = std::make_shared<NoiseTexture>();
  const int size = volume::kNoiseTexels;
  n->texture_ = gl::Texture::create3D(GL_RGBA8, size, size, size).label("detail noise tile");
  n->texture_.sampling(GL_LINEAR, GL_REPEAT);
  const gl::Program program = gl::Program::compute("render/noise.comp");
  program.use();
  program.set("u_size", size);
  glBindImageTexture(gl::binding::IMAGE_DETAIL_NOISE, n->texture_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
  program.dispatchCovering({size, size, size});
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  return n;
}

}  // namespace nph::render

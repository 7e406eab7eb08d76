#include "render/dlm/noise_texture.h"

#include <vector>

#include "render/gl/bindings.h"
#include "render/gl/program.h"
#include "volume/noise.h"

namespace nph::render {

std::shared_ptr<const NoiseTexture> NoiseTexture::generate() {
  auto n = std::make_shared<NoiseTexture>();
  const int size = volume::kNoiseTexels;
  n->texture_ = gl::Texture::create3D(GL_RGBA8, size, size, size, volume::kNoiseLevels).label("detail noise tile");
  n->texture_.sampling(GL_LINEAR, GL_REPEAT);
  // Read prefiltered to the pixel's footprint (glsl/common/detail_field.glsl detailNoiseLod).
  glTextureParameteri(n->texture_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  const gl::Program program = gl::Program::compute("render/noise.comp");
  program.use();
  program.set("u_size", size);
  glBindImageTexture(gl::binding::IMAGE_DETAIL_NOISE, n->texture_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
  program.dispatchCovering({size, size, size});
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  // The mipmap chain (the detail's level of detail): made from the generated level 0 by the CPU
  // twin's own rule (volume/noise.h noiseMipLevel), not glGenerateMipmap, whose filter is the
  // driver's: the GPU's levels are then the CPU's wherever their level 0 agrees. 1 MiB each way,
  // once per session.
  std::vector<std::uint8_t> level0(std::size_t(4) * std::size_t(size) * std::size_t(size) * std::size_t(size));
  // (RGBA8 rows are whole words: the default alignment of 4 holds)
  glGetTextureImage(n->texture_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(level0.size()), level0.data());
  const std::vector<std::vector<std::uint8_t>> chain = volume::noiseMipChain(level0);
  for (int k = 1; k < volume::kNoiseLevels; ++k) {
    const int s = size >> k;
    glTextureSubImage3D(n->texture_.id(), k, 0, 0, 0, s, s, s, GL_RGBA, GL_UNSIGNED_BYTE,
                        chain[std::size_t(k - 1)].data());
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  return n;
}

}  // namespace nph::render

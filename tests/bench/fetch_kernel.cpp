#include "fetch_kernel.h"

#include <string>

namespace nph::bench {

FetchKernel::FetchKernel(glm::ivec2 rays, int steps)
    : rays_(rays),
      steps_(steps),
      sum_(gl::Texture::create2D(GL_R32F, rays.x, rays.y)),
      program_(gl::Program::compute("bench/fetch3d.comp", {{"STEPS", std::to_string(steps)}})) {
  program_.set("u_rays", rays_);
}

void FetchKernel::dispatch(const gl::Texture& volume, const glm::vec3& step_uvw) const {
  program_.set("u_step_uvw", step_uvw);
  program_.use();
  glBindTextureUnit(gl::binding::UNIT_BENCH_VOLUME, volume.id());
  glBindImageTexture(gl::binding::IMAGE_BENCH_SUM, sum_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  program_.dispatchCovering({rays_.x, rays_.y, 1});
}

}  // namespace nph::bench

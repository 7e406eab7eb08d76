#pragma once
// The 3-D texture fetch throughput kernel (glsl/bench/fetch3d.comp): rays that do nothing but
// sample a volume, the "physical limit" of a ray caster on this GL. Shared by the fetch benchmark
// (gl_fetch_benchmark.cpp: formats, filters, directions) and the ray caster benchmark (achieved
// samples/s as a fraction of this limit, in the same run).
#include <glm/glm.hpp>

#include "render/gl/objects.h"
#include "render/gl/program.h"

namespace nph::bench {

class FetchKernel {
 public:
  FetchKernel(glm::ivec2 rays, int steps);
  /// Dispatches rays.x × rays.y rays of `steps` fetches each through `volume` (with the texture's
  /// own filter and wrap), starting on the w = 0 face and stepping by step_uvw (wrapping). Does
  /// not wait: the caller glFinish()es and times.
  void dispatch(const gl::Texture& volume, const glm::vec3& step_uvw) const;
  double fetchesPerDispatch() const { return double(rays_.x) * double(rays_.y) * double(steps_); }

 private:
  glm::ivec2 rays_;
  int steps_;
  gl::Texture sum_;
  gl::Program program_;
};

}  // namespace nph::bench

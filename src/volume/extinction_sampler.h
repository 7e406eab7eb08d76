#pragma once
// CPU sampling of the extinction volumes with exactly the GPU's rule: trilinear between voxel
// centres with zero outside the grid (GL: GL_LINEAR, GL_CLAMP_TO_BORDER with a zero border). β is
// continuous: it fades to 0 over the half voxel outside the box (no jump at the faces).
#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::scene {

struct ExtinctionSample {
  double ice_per_m = 0.0;
  double water_per_m = 0.0;
  double total() const { return ice_per_m + water_per_m; }
};

class ExtinctionSampler {
 public:
  ExtinctionSampler(const ExtinctionVolumes& volumes, const VolumeFrame& frame) : v_(volumes), f_(frame) {}
  ExtinctionSample at(const glm::dvec3& world_m) const;
  const VolumeFrame& frame() const { return f_; }

 private:
  double fetch(const std::vector<float>& a, int i, int j, int k) const;
  const ExtinctionVolumes& v_;
  VolumeFrame f_;
};

}  // namespace nph::scene

#include "volume/extinction_slices.h"

#include <algorithm>

namespace nph {

ExtinctionSlices::Slice VolumeSlices::slice(int k, std::vector<float>& scratch) const {
  const ExtinctionVolumes& v = *v_;
  const std::size_t layer = std::size_t(v.nx) * std::size_t(v.ny), base = std::size_t(k) * layer;
  const bool ice = v.ice_per_m.size() == v.voxelCount(), water = v.water_per_m.size() == v.voxelCount();
  if (!(ice && water)) scratch.assign(layer, 0.0f);  // the absent phase's zeros
  return {ice ? v.ice_per_m.data() + base : scratch.data(), water ? v.water_per_m.data() + base : scratch.data()};
}

ExtinctionVolumes ExtinctionSlices::materialise() const {
  if (const ExtinctionVolumes* w = whole()) return *w;
  ExtinctionVolumes v = volumes();
  const std::size_t layer = std::size_t(v.nx) * std::size_t(v.ny);
  v.ice_per_m.resize(v.voxelCount());
  v.water_per_m.resize(v.voxelCount());
  std::vector<float> scratch;
  for (int k = 0; k < v.nz; ++k) {
    const Slice s = slice(k, scratch);
    std::copy(s.ice, s.ice + layer, v.ice_per_m.begin() + std::ptrdiff_t(std::size_t(k) * layer));
    std::copy(s.water, s.water + layer, v.water_per_m.begin() + std::ptrdiff_t(std::size_t(k) * layer));
  }
  return v;
}

}  // namespace nph

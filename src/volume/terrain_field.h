#pragma once
// The ground's height field in the flat view's world frame (issue 14 item 2): the model's terrain
// (ExtinctionVolumes::terrain_height_m: WRF HGT, ICON HSURF) with the volume's height
// exaggeration, the bounds the eye pass's conservative march needs (extremes, Lipschitz bound of
// the slope), and the CPU twin of that march: glsl/common/terrain.glsl compiled as C++ in double
// precision (core/glsl_cpp.h), so the reference ray marcher stops its rays where the GPU does.
// Documentation of the surface and the march: glsl/common/terrain.glsl.
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::scene {

struct TerrainField {
  glm::ivec2 size{0};           ///< mass points nx, ny
  glm::dvec2 cell_m{0.0};       ///< world dx, dy
  double exaggeration = 1.0;    ///< heights in world metres are height_m × this
  double fade_m = 0.0;          ///< outside the footprint, heights fall linearly to 0 over this distance
  double max_m = 0.0;           ///< highest world height, ≥ 0 (the ground beyond the fade is at 0)
  double min_m = 0.0;           ///< lowest world height, ≤ 0
  double lipschitz = 0.0;       ///< upper bound of |∇(e·h)| of the bilinear, faded surface
  std::vector<float> height_m;  ///< nx·ny heights above MSL, x fastest (not exaggerated)

  /// false: no terrain (absent field or sea level everywhere): the ground is the plane z = 0.
  bool present() const { return max_m > 0.0 || min_m < 0.0; }
  /// World height (exaggerated) at world (x, y) [m] — the GPU's terrainHeight_m.
  double heightAt(const glm::dvec2& xy_m) const;
  /// Unit normal of the displaced surface at (x, y) — the GPU's terrainNormal.
  glm::dvec3 normalAt(const glm::dvec2& xy_m) const;
  /// First t in [t_min, t_max] where origin + t·dir (dir unit) is on or under the ground, the
  /// plane z = 0 included outside the terrain's rectangle; a negative value when there is none.
  double hitDistance(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max) const;
};

/// The terrain of `volumes` placed by `frame` (its exaggeration and cell size). The fade beyond
/// the footprint is a tenth of the footprint's longer side. Throws InputError for a field of the
/// wrong size or a non-finite height.
TerrainField terrainOf(const ExtinctionVolumes& volumes, const VolumeFrame& frame);

}  // namespace nph::scene

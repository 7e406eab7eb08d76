#pragma once
// Globe view (Nes 2008 §7.2 future work: "the clouds ... on a spherical Earth"): the eye rays are
// straight lines in Earth-centred coordinates (ECEF, metres, sphere of radius
// volume::kEarthRadius_m), while the extinction volumes, their occupancy bricks and the deep light
// map stay in the flat world frame of volume/volume_frame.h. Each ray sample p (ECEF) is carried
// into the world frame and looked up there:
//   world z  = |p| − R                      (world z already carries the height exaggeration, as
//                                            SceneGeoreference::ecefFromWorld puts it on the globe)
//   world xy = W(a, b)                      (a 2-D look-up table, bilinear)
// with (a, b) the longitude/latitude of p on a *rotated* sphere whose (0, 0) is the footprint
// centre (so the table never straddles the antimeridian and keeps float precision near the
// centre), and W the scene's exact PROJ transform (lon/lat → data projection → world) evaluated
// at the table's texel centres on the CPU — exact up to bilinear interpolation, whose error is
// measured at build time (max_interpolation_error_m, about a metre on a 1500 km footprint).
//
// Bounding the march. Every non-empty voxel (grown by one voxel, where β fades to 0) lies in the
// shell R + z_min ≤ |p| ≤ R + z_max and inside the cone around the footprint-centre axis c of
// half-angle α (measured on the grown footprint's outline). The ray is clipped to the lens
//   |p| ≤ R + z_max  and  p·c ≥ (R + z_min)·cos α,
// which contains shell ∩ cone (p·c ≥ |p| cos α ≥ (R + z_min) cos α), and to the ground sphere.
//
// Empty-space skipping stays conservative although the map is curved: moving s metres in ECEF
// moves the world point at most L_h·s horizontally and s vertically, where L_h bounds
// |ΔW| / (great-circle distance) over the table (measured, scaled by R / (R + z_min)). A ray
// sample in an empty brick can therefore jump s = min(d_h / L_h, d_z), d_h and d_z the world
// distances to the brick's side and top/bottom faces, and stay inside the brick (glsl/render/
// globe.glsl). Outside the grown box it jumps max(g_x/L_h, g_y/L_h, g_z) by the per-axis gaps.
#include <vector>

#include <glm/glm.hpp>

#include "scene/georeference.h"

namespace nph::render {

struct GlobeMapping {
  glm::dmat3 local_from_ecef{1.0};  ///< rows east, north, up at the footprint centre
  glm::dvec2 ab_min_rad{0.0};       ///< rotated lon/lat box the table covers (texel edges)
  glm::dvec2 ab_max_rad{0.0};
  int width = 0, height = 0;  ///< table size; world_xy is RG, row 0 at ab_min.y
  std::vector<float> world_xy_m;
  glm::dvec3 cap_axis{0.0, 0.0, 1.0};      ///< unit ECEF of the footprint centre
  double cap_cos = 1.0;                    ///< cos α of the grown footprint's cone
  double shell_min_m = 0.0;                ///< R + z_min (grown box bottom)
  double shell_max_m = 0.0;                ///< R + z_max (grown box top)
  double horizontal_lipschitz = 1.0;       ///< L_h: world-xy metres per ECEF metre, upper bound
  double max_interpolation_error_m = 0.0;  ///< table vs PROJ at texel-cell centres (measured)
  /// The table's margin beyond the grown footprint's outline [rad of arc]: terrain on the globe
  /// ramps to 0 over it (glsl/render/globe_terrain.glsl), so the ground has no cliff at the edge.
  double margin_rad = 0.0;
};

/// Rotated lon/lat (a, b) [rad] of an ECEF point: a = atan2(east, up), b = asin(north / |p|).
glm::dvec2 rotatedLonLat(const GlobeMapping& m, const glm::dvec3& ecef_m);

/// Builds the table for the scene's georeference (its frame: footprint, z range, voxel size).
/// `long_side` texels along the longer side of the box.
GlobeMapping buildGlobeMapping(const scene::SceneGeoreference& geo, int long_side = 256);

/// CPU twin of the shader's look-up: world xy of an ECEF point through the table (bilinear,
/// texel centres); NaN outside the table's box.
glm::dvec2 worldXyFromTable(const GlobeMapping& m, const glm::dvec3& ecef_m);

}  // namespace nph::render

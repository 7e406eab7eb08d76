#pragma once
// The ground's height field in the flat view's world frame (issue 14 item 2): the model's terrain
// (ExtinctionVolumes::terrain_height_m: WRF HGT, ICON HSURF) with the volume's height
// exaggeration, the bounds the eye pass's conservative march needs (extremes, Lipschitz bound of
// the slope), and the CPU twin of that march: glsl/common/terrain.glsl compiled as C++ in double
// precision (core/glsl_cpp.h), so the reference ray marcher stops its rays where the GPU does.
// Documentation of the surface and the march: glsl/common/terrain.glsl.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::volume {

/// A user DEM resampled for the terrain (scene/dem.h; issue 14 item 2): heights [m above MSL] on
/// the model's mass points, which replace the model's own field where they are not NaN (the DEM
/// wins, the model's field where the DEM has no data), and a far field over the far basemap's
/// square (scene::farBasemapRectangle), so the ground beyond the domain has the DEM's relief.
struct DemHeights {
  std::string source;  ///< the DEM file, for messages
  /// The lattice of model_m: the model's mass points refined `refine` times per cell each way
  /// (r·nx × r·ny texels at ((i + ½)·dx/r, (j + ½)·dy/r)), so a DEM finer than the model's grid
  /// keeps its ridges and valleys (docs/terrain.md "A DEM finer than the model"); 1 = the mass points.
  int refine = 1;
  std::vector<float> model_m;                 ///< (r·nx)·(r·ny), x fastest, NaN = no data; empty = none
  glm::ivec2 far_size{0};                     ///< far field pixels (0: none)
  glm::dvec2 far_min_m{0.0}, far_max_m{0.0};  ///< its world rectangle
  std::vector<float> far_m;                   ///< far_size.x·far_size.y, x fastest, row 0 south; NaN = no data
};

/// The most a DEM's lattice refines the model's mass points (per axis; scene::demRefinementFor).
inline constexpr int kMaxTerrainRefine = 8;

struct TerrainField {
  glm::ivec2 size{0};           ///< lattice points: the mass points nx, ny (× DemHeights::refine)
  glm::dvec2 cell_m{0.0};       ///< lattice spacing: world dx, dy (÷ DemHeights::refine)
  double exaggeration = 1.0;    ///< heights in world metres are height_m × this
  double fade_m = 0.0;          ///< outside the footprint, heights fall linearly to 0 over this distance
  double max_m = 0.0;           ///< highest world height, ≥ 0 (the ground beyond the fade is at 0)
  double min_m = 0.0;           ///< lowest world height, ≤ 0
  double lipschitz = 0.0;       ///< upper bound of |∇(e·h)| of the B-spline, faded surface
  std::vector<float> height_m;  ///< nx·ny heights above MSL, x fastest (not exaggerated)
  /// The surface's own texels: the interpolating cubic B-spline's coefficients of height_m on the
  /// same lattice (terrainOf; glsl/common/terrain.glsl terrainLatticeSpline reads these, the GPU's
  /// R32F texture holds them), so that the C² surface passes through height_m at every lattice point.
  std::vector<float> spline_m;
  /// The far field (a DEM's relief beyond the domain; glsl/common/terrain.glsl): empty without.
  glm::ivec2 far_size{0};
  glm::dvec2 far_min_m{0.0};
  glm::dvec2 far_cell_m{1.0};
  std::vector<float> far_height_m;  ///< far_size.x·far_size.y, x fastest, row 0 south, no NaN

  bool hasFar() const { return !far_height_m.empty(); }
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
/// the footprint is a tenth of the footprint's longer side. With `dem`, its heights replace the
/// model's where they are not NaN and its far field carries the relief beyond the footprint (NaN
/// there is sea level); a DEM on a refined lattice (DemHeights::refine > 1) makes the field that
/// lattice, the model's own heights bilinear between its mass points where the DEM has no data. Throws InputError for a
/// field of the wrong size or a non-finite height.
TerrainField terrainOf(const ExtinctionVolumes& volumes, const VolumeFrame& frame, const DemHeights* dem = nullptr);

}  // namespace nph::volume

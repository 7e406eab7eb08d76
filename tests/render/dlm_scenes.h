#pragma once
// Volumes for the deep light map tests: analytic ones and the generated sample scenes.
#include <string>

#include "scene/output_image.h"
#include "volume/extinction_volumes.h"

namespace nph::test {

/// nx × ny × nz voxels of 3 km × 3 km × 250 m, uniform water extinction `beta_per_m`.
ExtinctionVolumes homogeneousSlab(int nx, int ny, int nz, float beta_per_m);
/// Random (seeded) ice and water extinction up to 5e-3 /m: many light-function kinks.
ExtinctionVolumes noisyVolume(int nx, int ny, int nz, unsigned seed);
/// The tiny generated WRF hurricane (Thompson-like, Lambert) or ICON scene, timestep `t`,
/// written with the generator through NetCDF-C and converted by the real loaders and optics.
ExtinctionVolumes generatedHurricane(int t = 3);
ExtinctionVolumes generatedIconScene();
/// Issue 13's coarse storm (datagen::coarseStormSpec: 72×64 columns at 10 km, 30 levels),
/// timestep 0, through the real loader and optics (250 m output levels).
ExtinctionVolumes coarseStorm();
/// A grid-free storm on the coarse storm's grid (`like`: its columns, levels and georeference), its
/// columns refined `factor`× horizontally (the fine cells tiling the coarse ones, as
/// nephele_grid_spectrum's band-limited rendition): convective cells and a stratiform shield as
/// smooth analytic functions of position (Gaussians of σ = 1–2 columns), sampled at each cell's
/// centre. Nothing in it varies at the column spacing (a Gaussian of σ ≥ 1.8 columns keeps
/// e^{−2π²σ²} < 1e-27 of its amplitude at 1 cycle per column), so a rendition's power there is the
/// filter's (issue 13's artefact metric, tests/render/grid_artefacts.h).
ExtinctionVolumes analyticStorm(const ExtinctionVolumes& like, int factor = 1);
/// `g` refined `factor`× horizontally with the same outer faces (the grid of analyticStorm and of
/// nephele_grid_spectrum's band-limited rendition); the per-point lon/lat are dropped.
geo::GridGeoreference refinedGeoreference(const geo::GridGeoreference& g, int factor);

/// Per-component |a − b| of two cloud layers of the same size (max and mean over every RGBA
/// value) and b's mean alpha (how much of the frame is cloud).
struct LayerDifference {
  double max = 0.0, mean = 0.0, coverage = 0.0;
};
LayerDifference layerDifference(const scene::RgbaImage& a, const scene::RgbaImage& b);

/// The largest difference of the 8-bit sRGB codes (default exposure, ACES) of two images of the
/// same size, and the share of codes that differ at all.
struct LevelDifference {
  int max = 0;
  double differing = 0.0;
};
LevelDifference levelDifference(const scene::RgbaImage& a, const scene::RgbaImage& b);

}  // namespace nph::test

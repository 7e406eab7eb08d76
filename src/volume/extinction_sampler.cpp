#include "volume/extinction_sampler.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "volume/spline_coefficients.h"

namespace nph::volume {

double ExtinctionSampler::fetch(const std::vector<float>& a, int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= v_->nx || j >= v_->ny || k >= v_->nz) return 0.0;
  return double(a[v_->index(i, j, k)]);
}

ExtinctionSampler::ExtinctionSampler(const ExtinctionVolumes& volumes, const VolumeFrame& frame,
                                     Reconstruction reconstruction, Detail detail)
    : coefficients_(readsSplineCoefficients(reconstruction)
                        ? std::make_shared<const ExtinctionVolumes>(splineCoefficientVolumes(volumes))
                        : nullptr),
      v_(coefficients_ ? coefficients_.get() : &volumes),
      f_(frame),
      r_(reconstruction),
      detail_(detailParameters(detail, frame)) {
  if (!detail_.on()) return;
  controls_ = std::make_shared<const DetailControls>(buildDetailControls(volumes));  // from the data
  correction_ = solveDetailCorrection(measureHalfColumnMasses(kMassPattern));
}

ExtinctionSample ExtinctionSampler::at(const glm::dvec3& world_m) const {
  return detail_.on() ? detailedAt(world_m, true) : plainAt(world_m);
}

// The order of glsl/dlm/volume.glsl extinctionAt: controls at x, displacement from the noise at
// x / 2P, β at the displaced point, density factor from the noise there (glsl/common/detail.glsl),
// the column's mass correction at x (bilinear between column centres, clamped at the edges).
ExtinctionSample ExtinctionSampler::detailedAt(const glm::dvec3& world_m, bool corrected) const {
  const NoiseVolume& noise = noiseVolume();
  const glm::dvec3 g = f_.gridFromWorld(world_m);
  const glm::dvec4 c = controls_->at(g);
  const glm::dvec3 d =
      detailDisplacement(noise.sample(world_m / (2.0 * detail_.period_m)), c.x, detail_.reach_m, noise.stats);
  const glm::dvec3 q = world_m + d;
  ExtinctionSample s = plainAt(q);
  if (!(s.total() > 0.0)) return s;
  const glm::dvec3 qn = q / detail_.period_m;
  const glm::dvec4 n1 = noise.sample(qn), n2 = noise.sample(detailSecondFrame(qn));
  double rho = detailDensity(n1, n2, c, detail_.amplitude, noise.stats);
  rho *= detailShape(coverageAt(world_m + kDetailShapeDisplacementScale * d),
                     detailModulation(n1, n2, c.y, noise.stats), detail_.amplitude);
  if (corrected) {  // constant per column (volume/detail.h), GL_NEAREST with GL_CLAMP_TO_EDGE
    const int i = std::clamp(int(std::floor(g.x)), 0, f_.voxels.x - 1),
              j = std::clamp(int(std::floor(g.y)), 0, f_.voxels.y - 1);
    rho *= double(correction_[std::size_t(j) * std::size_t(f_.voxels.x) + std::size_t(i)]);
  }
  s.ice_per_m *= rho;
  s.water_per_m *= rho;
  return s;
}

// glsl/dlm/volume.glsl detailCoverageAt: the largest C_n of the 3×3 columns around the nearest
// column centre, each column's β at its centre, linear in height (zero outside the grid).
double ExtinctionSampler::coverageAt(const glm::dvec3& world_m) const {
  const glm::dvec3 g = f_.gridFromWorld(world_m);
  const double gz = g.z - 0.5;
  const int k0 = int(std::floor(gz));
  const double tz = gz - double(k0);
  const double column_m = std::max(f_.voxel_size_m.x, f_.voxel_size_m.y);
  const glm::dvec2 c(g.x - 0.5, g.y - 0.5);
  const glm::ivec2 nearest(glm::floor(c + 0.5));
  double coverage = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int i = nearest.x + dx, j = nearest.y + dy;
      double b = 0.0;
      for (const std::vector<float>* a : {&v_->ice_per_m, &v_->water_per_m}) {
        if (a->empty()) continue;
        b += (1.0 - tz) * fetch(*a, i, j, k0) + tz * fetch(*a, i, j, k0 + 1);
      }
      coverage = std::max(coverage, detailColumnCoverage(b, c - glm::dvec2(i, j), column_m));
    }
  return coverage;
}

// The measurement of glsl/render/detail_mass.comp: per half-column, rays_per_axis² vertical rays at
// the centres of a regular sub-grid, midpoint rule on the pattern's lattice over the footprint's
// step range (massStepRanges; the whole grown box without occupied_only).
HalfColumnMasses ExtinctionSampler::measureHalfColumnMasses(const MassPattern& pattern) const {
  HalfColumnMasses m;
  m.nx = f_.voxels.x;
  m.ny = f_.voxels.y;
  const int hx = 2 * m.nx, hy = 2 * m.ny, rays = pattern.rays_per_axis;
  m.plain.assign(std::size_t(hx) * std::size_t(hy), 0.0);
  m.detailed.assign(m.plain.size(), 0.0);
  const int reach = reachVoxels(r_) + detail_.reach_voxels;
  const double g0 = -double(reach), step = pattern.step_layers;
  const std::vector<glm::ivec2> ranges = massStepRanges(*v_, reachVoxels(r_), reach, pattern);
  tbb::parallel_for(0, hy, [&](int l) {
    for (int h = 0; h < hx; ++h) {
      const glm::ivec2 range = ranges[std::size_t(l / 2) * std::size_t(m.nx) + std::size_t(h / 2)];
      double p = 0.0, d = 0.0;
      for (int b = 0; b < rays; ++b)
        for (int a = 0; a < rays; ++a) {
          const double gx = 0.5 * (double(h) + (a + 0.5) / rays), gy = 0.5 * (double(l) + (b + 0.5) / rays);
          for (int k = range.x; k < range.y; ++k) {
            const glm::dvec3 w = f_.worldFromGrid({gx, gy, g0 + (k + 0.5) * step});
            p += plainAt(w).total();
            d += detailedAt(w, false).total();
          }
        }
      m.plain[std::size_t(l) * std::size_t(hx) + std::size_t(h)] = p;
      m.detailed[std::size_t(l) * std::size_t(hx) + std::size_t(h)] = d;
    }
  });
  return m;
}

ExtinctionSample ExtinctionSampler::plainAt(const glm::dvec3& world_m) const {
  const glm::dvec3 g = f_.gridFromWorld(world_m);
  ExtinctionSample s;
  const double reach = reachVoxels(r_);
  if (!(g.x >= -reach && g.y >= -reach && g.z >= -reach && g.x <= v_->nx + reach && g.y <= v_->ny + reach &&
        g.z <= v_->nz + reach)) {
    return s;  // outside (β = 0 there) or NaN
  }
  // Ice and water through the filter together (volume/reconstruction.h), zero outside the grid.
  const bool ice = !v_->ice_per_m.empty(), water = !v_->water_per_m.empty();
  const glm::dvec2 b = reconstructAt(r_, g - 0.5, [&](int i, int j, int k) {
    return glm::dvec2(ice ? fetch(v_->ice_per_m, i, j, k) : 0.0, water ? fetch(v_->water_per_m, i, j, k) : 0.0);
  });
  s.ice_per_m = std::max(b.x, 0.0);  // the interpolating spline's ringing (volume/spline_coefficients.h)
  s.water_per_m = std::max(b.y, 0.0);
  return s;
}

}  // namespace nph::volume

#include "volume/extinction_sampler.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/glsl_cpp.h"
#include "volume/noise.h"
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
  wind_ = std::make_shared<const DetailWind>(buildDetailWind(volumes));
  flow_ = volume::detailFlow(volumes.detail_clock_s, !wind_->empty());
  correction_ = solveDetailCorrection(measureRayMasses(kMassPattern));
}

ExtinctionSample ExtinctionSampler::at(const glm::dvec3& world_m, double footprint_m) const {
  return detail_.on() ? detailedAt(world_m, true, footprint_m) : plainAt(world_m);
}

namespace {
namespace f32 {
using namespace nph::glsl;
using Number = float;
#include "../glsl/common/detail.glsl"

// glsl/common/detail_field.glsl compiled as members: its primitives read the sampler's voxels,
// controls, noise and correction with the GPU's texture rules, and its uniforms are members of the
// same names (filled as render/dlm/volume_textures.cpp fills the VolumeBlock).
struct DetailField {
  const ExtinctionSampler& s;
  const DetailControls& controls;
  const NoiseVolume& noise;
  const std::vector<float>* correction;  ///< nullptr: uncorrected (the mass measurement)
  ivec3 u_voxels;
  vec3 u_box_size_m, u_displacement_m, u_noise_period_m;
  Number u_detail_amplitude;
  vec4 u_noise_stats_ra, u_noise_stats_gs, u_noise_stats_c;
  vec4 u_detail_flow;
  Number reach_voxels;

  DetailField(const ExtinctionSampler& sampler, const DetailControls& c, const std::vector<float>* corr)
      : s(sampler), controls(c), noise(noiseVolume()), correction(corr) {
    const VolumeFrame& f = s.frame();
    const DetailParameters& p = s.detail();
    u_voxels = f.voxels;
    u_box_size_m = vec3(f.size_m());
    u_displacement_m = vec3(p.reach_m);
    u_noise_period_m = vec3(p.period_m);
    u_detail_amplitude = Number(p.amplitude);
    packNoiseStats(noise.stats, u_noise_stats_ra, u_noise_stats_gs, u_noise_stats_c);
    const DetailFlow& flow = s.detailFlow();
    u_detail_flow = vec4(Number(flow.tau_s.x), Number(flow.tau_s.y), Number(flow.weight_a),
                         s.wind().empty() ? Number(0.0) : Number(1.0));
    reach_voxels = Number(reachVoxels(s.reconstruction()) + p.reach_voxels);
  }
  vec3 volumeUvw(vec3 world_m) const {
    return vec3(s.frame().gridFromWorld(glm::dvec3(world_m)) / glm::dvec3(u_voxels));
  }
  bool insideGrownVolume(vec3 uvw) const {
    const vec3 pad = reach_voxels / vec3(u_voxels);
    return glm::all(glm::greaterThanEqual(uvw, -pad)) && glm::all(glm::lessThanEqual(uvw, Number(1.0) + pad));
  }
  vec2 plainExtinctionAt(vec3 world_m) const {
    const ExtinctionSample b = s.plainAt(glm::dvec3(world_m));
    return vec2(b.ice_per_m, b.water_per_m);
  }
  vec4 detailControlsAt(vec3 uvw) const { return vec4(controls.at(glm::dvec3(uvw) * glm::dvec3(u_voxels))); }
  vec4 detailNoiseAt(vec3 q, Number lod) const { return vec4(noise.sampleLod(glm::dvec3(q), double(lod))); }
  vec2 detailWindAt(vec3 uvw) const {
    return s.wind().empty() ? vec2(Number(0.0)) : vec2(s.wind().at(glm::dvec3(uvw) * glm::dvec3(u_voxels)));
  }
  Number columnExtinctionAt(vec2 column_uv, Number w) const {
    const int i = int(std::floor(column_uv.x * Number(u_voxels.x))),
              j = int(std::floor(column_uv.y * Number(u_voxels.y)));
    return Number(s.columnAt(i, j, double(w) * double(u_voxels.z) - 0.5));
  }
  Number detailCorrectionTexel(ivec2 column) const {
    if (!correction) return Number(1.0);
    const int i = std::clamp(column.x, 0, u_voxels.x - 1), j = std::clamp(column.y, 0, u_voxels.y - 1);
    return (*correction)[std::size_t(j) * std::size_t(u_voxels.x) + std::size_t(i)];
  }
#define DETAIL_WIND_ON (u_detail_flow.w != Number(0.0))  // as glsl/dlm/volume.glsl without SPEC_DETAIL_WIND
#include "../glsl/common/detail_field.glsl"
#undef DETAIL_WIND_ON
};
static_assert(kDetailNoiseTexels == kNoiseTexels, "detail_field.glsl's tile size is volume/noise.h's");
}  // namespace f32
}  // namespace

ExtinctionSample ExtinctionSampler::detailedAt(const glm::dvec3& world_m, bool corrected, double footprint_m) const {
  f32::DetailField field(*this, *controls_, corrected ? &correction_ : nullptr);
  const glm::vec2 b = field.detailedExtinctionAt(glm::vec3(world_m), float(footprint_m));
  return {double(b.x), double(b.y)};
}

double ExtinctionSampler::coverageAt(const glm::dvec3& world_m) const {
  f32::DetailField field(*this, *controls_, nullptr);
  return double(field.detailCoverageAt(glm::vec3(world_m)));
}

// β_ice + β_water of column (i, j) at the continuous level index gz (voxel centres at integers),
// linear in height, 0 outside the grid: GL_LINEAR at a column's centre with the zero border.
double ExtinctionSampler::columnAt(int i, int j, double gz) const {
  const int k0 = int(std::floor(gz));
  const double tz = gz - double(k0);
  double b = 0.0;
  for (const std::vector<float>* a : {&v_->ice_per_m, &v_->water_per_m}) {
    if (a->empty()) continue;
    b += (1.0 - tz) * fetch(*a, i, j, k0) + tz * fetch(*a, i, j, k0 + 1);
  }
  return b;
}

// The measurement of glsl/render/detail_mass.comp: per vertical ray, (2·rays_per_axis)² per
// column at the centres of a regular sub-grid, midpoint rule on the pattern's lattice over the
// footprint's step range (massStepRanges; the whole grown box without occupied_only).
RayMasses ExtinctionSampler::measureRayMasses(const MassPattern& pattern) const {
  RayMasses m;
  m.nx = f_.voxels.x;
  m.ny = f_.voxels.y;
  m.rays_per_column = 2 * pattern.rays_per_axis;
  const int R = m.rays_per_column, rx = R * m.nx, ry = R * m.ny;
  m.plain.assign(std::size_t(rx) * std::size_t(ry), 0.0);
  m.detailed.assign(m.plain.size(), 0.0);
  const int reach = reachVoxels(r_) + detail_.reach_voxels;
  const double g0 = -double(reach), step = pattern.step_layers;
  const std::vector<glm::ivec2> ranges = massStepRanges(*v_, reachVoxels(r_), reach, pattern);
  tbb::parallel_for(0, ry, [&](int l) {
    for (int h = 0; h < rx; ++h) {
      const glm::ivec2 range = ranges[std::size_t(l / R) * std::size_t(m.nx) + std::size_t(h / R)];
      double p = 0.0, d = 0.0;
      const double gx = (h + 0.5) / R, gy = (l + 0.5) / R;
      for (int k = range.x; k < range.y; ++k) {
        const glm::dvec3 w = f_.worldFromGrid({gx, gy, g0 + (k + 0.5) * step});
        p += plainAt(w).total();
        d += detailedAt(w, false).total();
      }
      m.plain[std::size_t(l) * std::size_t(rx) + std::size_t(h)] = p;
      m.detailed[std::size_t(l) * std::size_t(rx) + std::size_t(h)] = d;
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

#include "reference/dlm_reference.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "volume/extinction_sampler.h"

namespace nph::reference {

DlmReference::DlmReference(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                           const lighting::LightSpace& lightSpace, const lighting::DlmSettings& settings, double step_m,
                           int steps, int refine, volume::Reconstruction reconstruction)
    : ls_(lightSpace), settings_(settings) {
  const volume::ExtinctionSampler sampler(volumes, frame, reconstruction);
  const lighting::ForwardFractions cp = lighting::forwardFractions(settings);
  // Height exaggeration keeps the data's optical depth along the light (VolumeFrame).
  const double f = frame.opticalDepthScale(ls_.w);
  sub_m_ = step_m / refine;
  samples_ = steps * refine + 1;
  const int nu = ls_.texels.x, nv = ls_.texels.y;
  central_.assign(std::size_t(nu) * std::size_t(nv) * std::size_t(samples_), 1.0);

  // Pass 1: I_{n+1} = I_n·[T + (1 − T)·CP(θ/4)], β at the step midpoint (lighting/dlm_model.h).
  tbb::parallel_for(0, nu * nv, [&](int t) {
    const int a = t % nu, b = t / nu;
    const glm::dvec3 start = ls_.rayStart(a, b);
    double* I = &central_[std::size_t(t) * std::size_t(samples_)];
    I[0] = 1.0;
    for (int n = 0; n + 1 < samples_; ++n) {
      const volume::ExtinctionSample e = sampler.at(start + (double(n) + 0.5) * sub_m_ * ls_.w);
      const double beta = f * e.total();
      const double T = std::exp(-beta * sub_m_);
      I[n + 1] = I[n] * lighting::centralStepFactor(T, cp.centralAt(beta > 0.0 ? f * e.ice_per_m / beta : 0.0));
    }
  });
  final_ = central_;
  const bool peripheral = settings.peripheral && cp.peripheral > 0.0 && steps > 0;
  if (!peripheral) return;

  // Pass 2: scatter map, slice by slice (same geometry as render/dlm/deep_light_map.cpp).
  const int ds = std::max(1, settings.scatter_downsample);
  const int sliceSteps = lighting::scatterSliceSteps(settings, ls_, step_m);  // as the GPU builder
  cells_ = {(nu + ds - 1) / ds, (nv + ds - 1) / ds, (steps + sliceSteps - 1) / sliceSteps + 1};
  slice_m_ = step_m * sliceSteps;
  const int sliceSamples = lighting::scatterSliceSamples(sliceSteps);
  scatter_.assign(std::size_t(cells_.x) * std::size_t(cells_.y) * std::size_t(cells_.z), 0.0);
  const glm::dvec2 extent = ls_.texelSize_m() * glm::dvec2(ls_.texels);
  auto cellCentre = [&](int x, int y) { return (glm::dvec2(x, y) + 0.5) * extent / glm::dvec2(cells_.x, cells_.y); };
  auto at = [&](int x, int y, int k) -> double& {
    return scatter_[(std::size_t(k) * std::size_t(cells_.y) + std::size_t(y)) * std::size_t(cells_.x) + std::size_t(x)];
  };
  for (int k = 1; k < cells_.z; ++k) {
    const double sPrev = (double(k - 1) + 0.5) * slice_m_;
    tbb::parallel_for(0, cells_.x * cells_.y, [&](int c) {
      const int x = c % cells_.x, y = c / cells_.x;
      auto lightAt = [&](int xx, int yy) {
        if (xx < 0 || yy < 0 || xx >= cells_.x || yy >= cells_.y) return 1.0;
        const glm::dvec2 p = cellCentre(xx, yy);
        return centralAtLight(p.x, p.y, sPrev) + at(xx, yy, k - 1);
      };
      const glm::dvec2 p = cellCentre(x, y);
      // β averaged over the slice as the GPU's pass 2 (glsl/dlm/scatter.comp; one sample at k·S
      // for short slices).
      double ice = 0.0, total = 0.0;
      for (int j = 0; j < sliceSamples; ++j) {
        const double z = (double(k) + (double(j) + 0.5) / double(sliceSamples) - 0.5) * slice_m_;
        const volume::ExtinctionSample e = sampler.at(ls_.worldFromLight({p.x, p.y, z}));
        ice += e.ice_per_m;
        total += e.total();
      }
      const double beta = f * total / double(sliceSamples);
      const double T = std::exp(-beta * slice_m_);
      const double around = 0.25 * (lightAt(x + 1, y) + lightAt(x - 1, y) + lightAt(x, y + 1) + lightAt(x, y - 1));
      at(x, y, k) = at(x, y, k - 1) * lighting::centralStepFactor(T, cp.centralAt(total > 0.0 ? ice / total : 0.0)) +
                    around * (1.0 - T) * cp.peripheral;
    });
  }
  // Pass 3: final = central + P (trilinear in the scatter map).
  const glm::dvec2 texel = ls_.texelSize_m();
  tbb::parallel_for(0, nu * nv, [&](int t) {
    const int a = t % nu, b = t / nu;
    const double u = (a + 0.5) * texel.x, v = (b + 0.5) * texel.y;
    double* F = &final_[std::size_t(t) * std::size_t(samples_)];
    for (int n = 0; n < samples_; ++n) F[n] = std::min(F[n] + peripheralAt(u, v, n * sub_m_), 1.0);
  });
}

double DlmReference::peripheralAt(double u, double v, double s) const {
  // GL_LINEAR + GL_CLAMP_TO_EDGE on a cx × cy × cz texture with normalised coordinates
  // (u / extent_u, v / extent_v, s / (slice·cz)).
  const glm::dvec2 extent = ls_.texelSize_m() * glm::dvec2(ls_.texels);
  const glm::dvec3 c(u / extent.x * cells_.x - 0.5, v / extent.y * cells_.y - 0.5, s / slice_m_ - 0.5);
  const glm::dvec3 f0 = glm::floor(c);
  const glm::dvec3 t = c - f0;
  double r = 0.0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int x = std::clamp(int(f0.x) + dx, 0, cells_.x - 1);
        const int y = std::clamp(int(f0.y) + dy, 0, cells_.y - 1);
        const int z = std::clamp(int(f0.z) + dz, 0, cells_.z - 1);
        const double w = (dx ? t.x : 1 - t.x) * (dy ? t.y : 1 - t.y) * (dz ? t.z : 1 - t.z);
        r += w * scatter_[(std::size_t(z) * std::size_t(cells_.y) + std::size_t(y)) * std::size_t(cells_.x) +
                          std::size_t(x)];
      }
  return r;
}

double DlmReference::sampleSeries(const std::vector<double>& series, std::size_t texel, double s) const {
  const double* I = &series[texel * std::size_t(samples_)];
  const double x = s / sub_m_;
  if (x <= 0.0) return I[0];
  if (x >= double(samples_ - 1)) return I[samples_ - 1];
  const int n = int(x);
  const double f = x - n;
  return I[n] + f * (I[n + 1] - I[n]);
}

double DlmReference::texelIntensity(int a, int b, double s) const {
  return sampleSeries(final_, std::size_t(b) * std::size_t(ls_.texels.x) + std::size_t(a), s);
}

double DlmReference::texelCentral(int a, int b, double s) const {
  return sampleSeries(central_, std::size_t(b) * std::size_t(ls_.texels.x) + std::size_t(a), s);
}

double DlmReference::centralAtLight(double u, double v, double s) const {
  return lighting::blendTexels(ls_, {u, v, s}, [&](int a, int b, double z) { return texelCentral(a, b, z); });
}

double DlmReference::intensityAt(const glm::dvec3& world_m) const {
  return lighting::blendTexels(ls_, ls_.lightFromWorld(world_m),
                               [&](int a, int b, double z) { return texelIntensity(a, b, z); });
}

}  // namespace nph::reference

#pragma once
// CPU reference of the deep light map (no GL, double precision, no compression, no empty-space
// skipping): the model of lighting/dlm_model.h integrated with `refine` sub-steps per GPU step Δ.
// With refine = 1 it is the exact arithmetic twin of the GPU build before compression (the GPU
// must then agree within ε plus float rounding); with refine = 8 it approximates the continuum
// and |ref(1) − ref(8)| measures the discretisation term. The yardstick for render/dlm/.
#include <vector>

#include <glm/glm.hpp>

#include "lighting/dlm_model.h"
#include "lighting/light_space.h"
#include "volume/extinction_volumes.h"
#include "volume/reconstruction.h"
#include "volume/volume_frame.h"

namespace nph::reference {

class DlmReference {
 public:
  /// Integrates every texel of `lightSpace` (use the GPU map's, so texels coincide) with the GPU
  /// step `step_m` divided into `refine` sub-steps over `steps` GPU steps.
  DlmReference(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
               const lighting::LightSpace& lightSpace, const lighting::DlmSettings& settings, double step_m, int steps,
               int refine, volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear);

  /// Final light (central + peripheral) of texel (a, b) at depth s [m] from the ray entry
  /// (linear between sub-samples, constant beyond the ends) — what the DLM stores for that texel.
  double texelIntensity(int a, int b, double s_m) const;
  /// Central light only (pass 1).
  double texelCentral(int a, int b, double s_m) const;
  /// Light at a world point with the GPU look-up's rules (bilinear across texels, 1 outside).
  double intensityAt(const glm::dvec3& world_m) const;

  int samplesPerRay() const { return samples_; }
  double subStep_m() const { return sub_m_; }

 private:
  double sampleSeries(const std::vector<double>& series, std::size_t texel, double s_m) const;
  double peripheralAt(double u_m, double v_m, double s_m) const;
  double centralAtLight(double u_m, double v_m, double s_m) const;

  lighting::LightSpace ls_;
  lighting::DlmSettings settings_;
  double sub_m_ = 0.0;
  int samples_ = 0;              // per ray: steps·refine + 1
  std::vector<double> central_;  // [texel][sample]
  std::vector<double> final_;    // central + peripheral
  // scatter map (same geometry as the GPU's)
  glm::ivec3 cells_{0};
  double slice_m_ = 0.0;
  std::vector<double> scatter_;  // [(k·cy + y)·cx + x]
};

}  // namespace nph::reference

#pragma once
// CPU sampling of the extinction volumes with exactly the GPU's rule (glsl/dlm/volume.glsl
// extinctionAt), for either reconstruction (volume/reconstruction.h), with zero outside the grid
// (GL: GL_CLAMP_TO_BORDER with a zero border). β is continuous: it fades to 0 over the
// supportVoxels(r) outside the box (no jump at the faces).
//   - Trilinear: GL_LINEAR between voxel centres.
//   - Cubic: the tricubic B-spline, here with its 4×4×4 weights; the shaders compute the same sum as
//     8 trilinear fetches (Sigg & Hadwiger 2005), equal up to float rounding and the GPU's
//     filtering precision (tests/render: GPU against this sampler).
#include <memory>

#include <glm/glm.hpp>

#include "volume/detail.h"
#include "volume/extinction_volumes.h"
#include "volume/reconstruction.h"
#include "volume/volume_frame.h"

namespace nph::volume {

struct ExtinctionSample {
  double ice_per_m = 0.0;
  double water_per_m = 0.0;
  double total() const { return ice_per_m + water_per_m; }
};

class ExtinctionSampler {
 public:
  /// With `detail` other than None, β is the detailed field of glsl/common/detail.glsl (volume/detail.h):
  /// the controls are built from `volumes` here (O(voxels)), the noise is volume/noise.h's.
  ExtinctionSampler(const ExtinctionVolumes& volumes, const VolumeFrame& frame,
                    Reconstruction reconstruction = Reconstruction::Trilinear, Detail detail = Detail::None);
  /// `footprint_m`: the width of the ray's footprint there (the eye pass: distance × pixel angle);
  /// the detail's noise is read prefiltered to it (glsl/common/detail_field.glsl detailNoiseLod;
  /// 0, the default: full resolution, as the DLM passes and the mass measurement read it).
  ExtinctionSample at(const glm::dvec3& world_m, double footprint_m = 0.0) const;
  /// β without the sub-grid detail (the reconstruction alone).
  ExtinctionSample plainAt(const glm::dvec3& world_m) const;
  const VolumeFrame& frame() const { return f_; }
  /// The voxels the filter reads: the volumes given, or for CubicInterpolating their spline
  /// coefficients (volume/spline_coefficients.h), which this sampler then owns.
  const ExtinctionVolumes& voxels() const { return *v_; }
  Reconstruction reconstruction() const { return r_; }
  const DetailParameters& detail() const { return detail_; }
  /// The per-column mass correction in use (volume/detail.h; empty without detail).
  const std::vector<float>& detailCorrection() const { return correction_; }
  /// The phases of the noise's advection in use (volume/detail.h DetailFlow; world-fixed without U, V).
  const DetailFlow& detailFlow() const { return flow_; }
  /// The wind advecting the noise (empty without detail or without U, V).
  const DetailWind& wind() const { return wind_ ? *wind_ : kNoWind; }
  /// The plain and the uncorrected detailed masses along vertical rays, measured with `pattern`
  /// (volume/detail.h; the correction in use is solved from kMassPattern's).
  RayMasses measureRayMasses(const MassPattern& pattern = kMassPattern) const;
  /// The detail's shape coverage at a world position (glsl/common/detail_field.glsl detailCoverageAt).
  double coverageAt(const glm::dvec3& world_m) const;
  /// β_ice + β_water of column (i, j) at the continuous level index gz (voxel centres at integers),
  /// linear in height, 0 outside the grid (of the voxels the filter reads).
  double columnAt(int i, int j, double gz) const;

 private:
  static inline const DetailWind kNoWind{};
  double fetch(const std::vector<float>& a, int i, int j, int k) const;
  ExtinctionSample detailedAt(const glm::dvec3& world_m, bool corrected, double footprint_m = 0.0) const;
  std::shared_ptr<const ExtinctionVolumes> coefficients_;  ///< for CubicInterpolating
  const ExtinctionVolumes* v_;
  VolumeFrame f_;
  Reconstruction r_;
  DetailParameters detail_;
  std::shared_ptr<const DetailControls> controls_;  ///< when the detail is on
  std::shared_ptr<const DetailWind> wind_;          ///< when the detail is on (empty: no U, V)
  DetailFlow flow_;                                 ///< the noise's advection phases (volume/detail.h)
  std::vector<float> correction_;                   ///< c per model column, when the detail is on
};

}  // namespace nph::volume

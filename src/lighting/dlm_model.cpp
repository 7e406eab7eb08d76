#include "lighting/dlm_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "physics/phase.h"

namespace nph::lighting {

std::string DlmSettings::key() const {
  return fmt::format("eps={:.9g};step={:.9g};texel={:.9g};maxtex={};nodes={};dbl={};theta={:.9g};g={:.9g};per={};sd={};"
                     "ss={};sc={:.9g};cache={:.9g};fi={:.9g};fw={:.9g};grow={};gb={:.9g}",
                     epsilon, step_voxels, texel_voxels, max_texels, max_nodes, max_epsilon_doublings,
                     forward_angle_deg, cornette_shanks_g, peripheral ? 1 : 0, scatter_downsample, scatter_slice_steps,
                     scatter_slice_cells, light_cache_voxels, forward_peak_ice, forward_peak_water, step_growth_max,
                     step_growth_budget);
}

int scatterSliceSteps(const DlmSettings& s, const LightSpace& ls, double step_m) {
  int steps = s.scatter_slice_steps;
  const glm::dvec2 cell = ls.texelSize_m() * double(std::max(1, s.scatter_downsample));
  const double want = s.scatter_slice_cells * std::min(cell.x, cell.y) / step_m;
  // Bounded: a slice longer than the light's whole path is one slice (kMaxSteps in the builder).
  if (want > double(steps) && std::isfinite(want)) steps = 2 * int(std::ceil(std::min(want, double(1 << 22)) / 2.0));
  return steps;
}

ForwardFractions forwardFractions(const DlmSettings& s) {
  const double theta = s.forward_angle_deg * std::numbers::pi / 180.0;
  // Cornette–Shanks for the transport (Nes 2008 §5.2.4); CP(θ) = share scattered within θ.
  const physics::PhaseFunction cs{physics::PhaseModel::CornetteShanks, s.cornette_shanks_g};
  const double cp4 = physics::cumulativePhase(cs, theta / 4.0);
  const double cp2 = physics::cumulativePhase(cs, theta / 2.0);
  return {cp4, cp2 - cp4, s.forward_peak_ice >= 0.0 ? s.forward_peak_ice : cp4,
          s.forward_peak_water >= 0.0 ? s.forward_peak_water : cp4};
}

}  // namespace nph::lighting

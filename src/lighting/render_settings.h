#pragma once
// What the eye pass (glsl/render/clouds.comp; Nes 2008 §5.4 eq. 5.18, §5.5; Muth 2026 §3.4) is
// told: how to sample (quality, set by the presets of lighting/knobs.h) and how clouds and ground
// look (style, which presets never touch). GL-free: the GPU ray caster (render/raycast) and the
// CPU references (reference/ray_marcher.h, accuracy/) read the same structs.
#include <glm/glm.hpp>

#include "lighting/octave_series.h"

namespace nph::lighting {

/// Appearance: the eye phase functions and the ambient light. The knob table (lighting/knobs.h)
/// exposes some fields by name; these defaults are the knobs' defaults.
struct StyleSettings {
  double g_ice = 0.75;                   ///< HG asymmetry of ice crystals (physics/phase.h)
  double g_water = 0.85;                 ///< HG asymmetry of droplets (physics/phase.h)
  glm::dvec3 ambient{0.20, 0.24, 0.30};  ///< uniform sky radiance (sun radiance = 1)
  glm::dvec3 ocean_albedo{0.02, 0.04, 0.07};   ///< ground outside the basemap
  glm::dvec3 limb_radiance{0.30, 0.45, 0.80};  ///< globe: sky glow at the limb (cosmetic; × sun intensity)
};

/// The ray caster's settings: sampling (from QualitySettings, lighting::renderSettingsFor) and
/// style. The sampling defaults equal the broadcast preset (tests/lighting holds them equal).
struct RenderSettings : StyleSettings {
  double step_voxels = 0.5;              ///< view-ray step Δ in units of the smallest voxel side
  double min_transmittance = 0.01;       ///< early ray termination
  bool jitter = true;                    ///< per-pixel start offset against banding
  bool empty_space_skipping = true;
  bool shadows = true;                   ///< cloud shadows on the ground (DLM at z = 0)
  OctaveSeries octaves;                  ///< multiple scattering of sunlight (issue 12); 1 octave = single
};

}  // namespace nph::lighting

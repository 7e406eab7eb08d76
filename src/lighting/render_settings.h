#pragma once
// What the eye pass (glsl/render/clouds.comp; Nes 2008 §5.4 eq. 5.18, §5.5; Muth 2026 §3.4) is
// told: how to sample (quality, set by the presets of lighting/knobs.h) and how clouds and ground
// look (style, which presets never touch). GL-free: the GPU ray caster (render/raycast) and the
// CPU references (reference/ray_marcher.h, accuracy/) read the same structs.
#include <array>
#include <string_view>

#include <glm/glm.hpp>

#include "lighting/octave_series.h"
#include "volume/detail.h"
#include "volume/reconstruction.h"

namespace nph::lighting {

/// The multiple-scattering model of the eye pass (issue 12; glsl/common/cloud_light.glsl
/// cloudSunFactor, docs/light-transport.md): single scattering only, the octave series fitted to the
/// path tracer, or the independent-column two-stream (δ-Eddington) diffuse light from the column
/// depths — the default since issue 12's third phase (docs/accuracy.md) —, or the Monte Carlo
/// radiance volume traced on the GPU with the deep light map (issue 12, sixteenth session:
/// render/dlm/radiance_volume.h; the map's single scattering and forward lobe plus the volume's
/// orders ≥ 2, docs/accuracy.md "Sixteenth session").
enum class MultipleScattering { Single = 0, Octaves = 1, TwoStream = 2, RadianceVolume = 3 };
inline constexpr std::array<std::string_view, 4> kMultipleScatteringNames{"single", "octaves", "two_stream",
                                                                          "radiance_volume"};

/// Appearance: the eye phase functions and the ambient light. The knob table (lighting/knobs.h)
/// exposes some fields by name; these defaults are the knobs' defaults.
struct StyleSettings {
  double g_ice = 0.75;    ///< HG asymmetry of ice crystals (physics/phase.h)
  double g_water = 0.85;  ///< HG asymmetry of droplets (physics/phase.h)
  /// Sky light per channel, × the analytic clear sky at the sun's elevation (lighting/cloud_light.h;
  /// 1 = physical, 0 = no sky light). Issue 12 replaced the former constant ambient radiance.
  glm::dvec3 ambient{1.0, 1.0, 1.0};
  /// Mean ground albedo for the light the ground reflects up into the clouds' bases.
  double ground_albedo = 0.1;
  /// The lower hemisphere is sky too (the accuracy scenes, whose path-traced truth has no ground).
  bool sky_below = false;
  glm::dvec3 ocean_albedo{0.02, 0.04, 0.07};  ///< ground outside the basemap
  glm::dvec3 limb_radiance{
      0.053, 0.080,
      0.141};  ///< globe: sky glow at the limb (cosmetic; × sun intensity; the pre-issue-12 look at +2.5 EV)
  /// The physically based atmosphere (issue 14; atmosphere/atmosphere.h): sky radiance, sunlight
  /// through the air, sky irradiance of the ground, aerial perspective. Off: the uniform ambient
  /// sky, the navy flat-view background and the cosmetic limb of before.
  bool atmosphere = true;
  /// The ground displaced by the model's terrain (issue 14; volume/terrain_field.h), with the
  /// height exaggeration of the clouds. Off: the plane z = 0 of before (the clouds then reach down
  /// to the data's lowest layer wherever the terrain is).
  bool terrain = true;
  /// Ground detail on the terrain (issue 14; glsl/common/ground_tint.glsl): snow above the snow
  /// line and bare rock on steep slopes, from the height field at its own resolution, blended over
  /// the imagery by area. Synthesis, not data: off by default (the imagery as it is), on for a
  /// broadcast look (make demo's terrain shot).
  bool ground_tint = false;
  /// The snow line of ground_tint [m above MSL]: the Alps' late-summer firn line is near 2900 m,
  /// the autumn equinox's snow line near 2700 m (docs/terrain.md "Ground detail").
  double snow_line_m = 2700.0;
  /// City lights on the night side (issue 14; glsl/common/night_lights.glsl): the radiance of a
  /// fully lit texel as a fraction of E/π (a white Lambertian ground under the overhead sun),
  /// faded in as the sun sets at the ground point; 0 = off (the lights raster is then not read).
  /// The default is a look, not physics (real lights are some 10⁶ times dimmer and need a night
  /// exposure): at the day's exposure a city core reads as sunlit dark land.
  double city_lights = 0.1;
};

/// The ray caster's settings: sampling (from QualitySettings, lighting::renderSettingsFor) and
/// style. The sampling defaults equal the broadcast preset (tests/lighting holds them equal).
struct RenderSettings : StyleSettings {
  double step_voxels = 0.5;  ///< view-ray step Δ in units of the smallest voxel side
  /// Adaptive steps (issue 19; Muth 2026 eq. 3.6; glsl/render/clouds.comp adaptiveStep): far away
  /// and in thin cloud the step grows up to this × Δ. 1: the fixed step (the reference path).
  double step_growth_max = 1.0;
  double min_transmittance = 0.01;  ///< early ray termination
  bool jitter = true;               ///< per-pixel start offset against banding
  /// Samples per pixel (the knob `samples_per_pixel`): the eye pass runs this many times at
  /// sub-pixel positions of the R2 sequence (the first at the pixel's centre), each with its own
  /// jitter, and keeps their mean — a box filter over the pixel, so cloud edges, the horizon and
  /// the terrain are anti-aliased and the jitter's noise averages out. The DLM is built once.
  int samples_per_pixel = 1;
  /// The index of a dispatch's first sample (not a knob): 0 starts the images afresh; k > 0 folds
  /// the dispatch's samples into the mean the previous dispatches left (`nephele view` refines a
  /// still frame one sample at a time this way).
  int first_sample = 0;
  /// Temporal accumulation for the interactive path (not a knob; issue 19 item 4; render/raycast/
  /// temporal_accumulation.h): N > 0 gives each dispatch the next sample of the jitter and
  /// sub-pixel sequence and folds it into a history of up to N frames, reprojected when the view
  /// moves. 0: every dispatch stands alone (batch frames are a function of the frame alone).
  /// `nephele view` while the camera moves, the plugin API's `temporal` parameter.
  int temporal_history = 0;
  /// Reduced-resolution clouds (the knob `cloud_resolution`; issue 19 item 4): the eye pass marches
  /// the clouds at W/s × H/s for s = this divisor and a full-resolution pass upsamples them,
  /// guided by the full-resolution geometry (depth-aware upsampling, glsl/render/clouds.comp
  /// upsampleClouds), under the ground and sky it draws at full resolution. 1: the march at every
  /// pixel (bit for bit the pass before the knob).
  int cloud_resolution = 1;
  bool empty_space_skipping = true;
  bool shadows = true;  ///< cloud shadows on the ground (DLM at z = 0)
  /// Multiple scattering of sunlight (issue 12): the octave series fitted to the path tracer
  /// (docs/accuracy.md, `nephele-bench accuracy --fit-octaves`); {1, …} = single scattering only.
  OctaveSeries octaves{3, 0.65, 0.75, 0.0, {}};
  /// Which multiple-scattering term lights the clouds (the knob `multiple_scattering`); the
  /// octaves above are read only by MultipleScattering::Octaves.
  MultipleScattering multiple_scattering = MultipleScattering::TwoStream;
  /// The radiance volume's photons per column of its cells (render::RadianceVolumeSettings::
  /// photons_per_column, the knob `radiance_volume_photons`); 0: the volume settings' photons alone.
  int radiance_volume_photons_per_column = 64;
  /// The extinction filter of the CPU references (reference/ray_marcher.h). The GPU passes take
  /// it from the uploaded volume (render::VolumeTextures::upload); engine::Session keeps both equal.
  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear;
  /// The sub-grid detail of the CPU references (volume/detail.h); the GPU passes take it from the
  /// uploaded volume, as the reconstruction.
  volume::Detail detail = volume::Detail::None;
};

}  // namespace nph::lighting

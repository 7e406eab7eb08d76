#pragma once
// Path-traced ground truth of an accuracy scene (reference/path_tracer.h), cached on disk.
//
// Matching the GPU's radiometry. The eye pass (glsl/render/clouds.comp) adds per step
//   T_acc·(1 − T)·[E·I_DLM·4π·p_v(ψ) + L_ambient],   E = sun colour·intensity,
// i.e. single scattering of a sun whose irradiance is 4π·E (the 4π·p convention: an isotropic
// scatterer returns E), plus a uniform sky of radiance L_ambient from the whole sphere. The path
// tracer is given exactly that light — a sun of irradiance 4π·colour·intensity and a uniform sky
// L_ambient·intensity, no ground — with the same eye phase functions (HG 0.75 ice, 0.85 water)
// and full multiple scattering. Its RGB (no background) and exact alpha are then the cloud layer
// the GPU's approximation tries to produce: the difference is the model's bias (forward
// scattering in a cone from the DLM, no side or back multiple scattering, the ambient term).
//
// Cache: <dir>/<scene>-<key>.gt, key = XXH64 of the volume, frame, camera, sun, light and
// tracer settings; a binary file: magic, width, height, truncated share, rouletted share, tracing
// seconds, then width·height RGBA and RGB standard error floats.
#include <cstdint>
#include <string>
#include <vector>

#include "accuracy/accuracy_scenes.h"
#include "reference/path_tracer.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/output_image.h"

namespace nph::accuracy {

/// Which light the tracer carries (issue 12's bias decomposition, accuracy/decompose.h): the whole
/// truth, only the sky (sun off, every order), or the sun alone up to `max_events` scattering orders
/// (sky off; max_events = 1 is single scattering: the path's first collision with its next-event
/// estimate to the sun, then cut — `truncated_share` is then the share of paths that collided).
enum class TruthPart { Full, SkyOnly, SunOnly };

struct GroundTruthSettings {
  TruthPart part = TruthPart::Full;
  int samples_per_pixel = 256;
  /// Hard cap; paths cut by it are counted (their energy would be the truth's only bias). With the
  /// roulette below a path reaches it with probability ≤ D/max_events, and only if it would
  /// diffuse that long: 2 of 3.7 million paths on the hurricane seen from above at 256 spp.
  int max_events = 100000;
  /// Unbiased Russian roulette past this many collisions (reference/path_tracer.h).
  int roulette_after_events = 1000;
  std::uint64_t seed = 1;
};

struct GroundTruth {
  scene::RgbaImage image;             ///< premultiplied cloud layer (RGB no background, exact α)
  std::vector<float> standard_error;  ///< RGB per pixel
  double seconds = 0.0;               ///< tracing time (0 when read from the cache)
  double truncated_share = 0.0;       ///< paths cut by max_events / paths
  double rouletted_share = 0.0;       ///< paths ended by Russian roulette / paths (unbiased)
  double noise_rmse = 0.0;            ///< RMS over pixels of the luminance standard error
  bool from_cache = false;
  std::string cache_path;
};

/// The tracer's light and phase for the GPU's `render_settings` (see above).
/// The sun is the scene's (irradiance E; docs/rendering.md "Conventions"), the sky a uniform sphere
/// of the eye pass's clear-sky radiance (lighting::skyLightFor).
reference::PathTracerSettings pathTracerSettingsForGpu(const render::RenderSettings& render_settings,
                                                       const scene::Sun& sun, const GroundTruthSettings& settings);

std::string groundTruthKey(const AccuracyScene& scene, const render::RenderSettings& render_settings,
                           const GroundTruthSettings& settings);

/// From `cache_dir` when present, else traced and written there.
GroundTruth groundTruth(const AccuracyScene& scene, const render::RenderSettings& render_settings,
                        const GroundTruthSettings& settings, const std::string& cache_dir);

}  // namespace nph::accuracy

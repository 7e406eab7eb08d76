#pragma once
// CPU Monte Carlo volumetric path tracer: the ground truth for nephele's cloud model (issue 6).
// It solves the full radiative transfer equation (Nes 2008 eq. 2.16-2.17, 5.5 without the
// "forward scattering only" simplification of eq. 5.6-5.11) for the ice and water extinction
// volumes, in double precision, with the same volume frame, camera and sun as the GPU renderer.
//
// Medium: β_ext = β_ice + β_water [1/m] sampled by the renderer's rule (path_tracer_field.h);
// single-scattering albedo 1 (Nes §5.2.2: β_sca = β_ext); at a collision the phase function is
// the ice one with probability β_ice/(β_ice + β_water), else the water one — an exact sample of
// Nes eq. 5.12's β_sca-weighted mixture (physics/phase.h PhaseMix).
// Lights: a directional sun, a delta light of irradiance E = intensity·colour on a plane normal
// to the beam [radiance units·sr]; a uniform sky of radiance L_sky from every direction that
// escapes (with ground, only the upper hemisphere can be reached); optional Lambertian ground
// plane z = ground_height_m with albedo ρ (constant or a function of world x, y).
//
// Estimators (per camera sample, Pharr/Jakob/Humphreys PBRT 4th ed. ch. 14; Novák et al. 2018
// "Monte Carlo methods for volumetric light transport simulation"):
//  * free flights by delta tracking against the majorant grid (majorant_grid.h); throughput stays
//    1 at medium collisions (albedo 1, phase sampled exactly), is multiplied by ρ at the ground;
//  * next-event estimation to the sun at every medium collision (E·p(cos ψ)·T) and ground hit
//    (E·ρ/π·max(0, n·ω_sun)·T), T by ratio tracking (unbiased, Russian roulette below 0.1) or,
//    optionally, exactly (path_tracer_field.h) — the sun is a delta light, so NEE is its only
//    estimator and nothing is double counted;
//  * the sky is reached by paths escaping the volume (no NEE for the sky).
//  * Russian roulette past a depth (PBRT 4th ed. §14.1.4; Novák et al. 2018 §5.3): albedo 1
//    keeps the throughput at 1, so paths in optically thick cores would diffuse for O(τ²)
//    collisions; from the D-th collision on (D = `roulette_after_events`) the n-th survives with
//    probability q_n = n/(n + 1) and the survivor's throughput is divided by q_n. Unbiased
//    (E[weight] = 1 at every depth); a path survives to its N-th collision with probability
//    D/(N + 1) and then carries the weight (N + 1)/D — linear in its length, so a path of natural
//    length N costs ≈ D·(1 + ln(N/D)) collisions and the estimator's variance stays finite
//    however long the paths of a thick deck diffuse. (A constant survival q = 1 − 1/D, used until
//    the thirtieth session, gives weights q^−K ≈ e^{K/D}: infinite variance once paths diffuse for
//    more than ~D collisions — single pixels 400× their neighbours on the hurricane from above.)
//  Paths end when they escape, are rouletted, or after `max_events` collisions (medium + ground);
//  the number of paths cut by that hard cap is reported (their missing energy would be the only
//  bias of the tracer; with roulette on, a path reaches the cap with probability
//  D/max_events at most, and only if it would naturally diffuse that long).
//
// Output convention (premultiplied, linear — what the compositor layers over the ground):
//  * alpha = 1 − T(primary ray), T = exp(−τ) with τ integrated exactly through the volume box
//    (to the ground plane when it is on): the cloud layer's coverage. Noise-free.
//  * RGB  = radiance towards the camera of the paths whose primary ray collides in the cloud:
//    everything the cloud scatters to the eye (sun, sky and ground light, any number of bounces).
//    The background seen through the cloud (sky, or ground with its cloud shadows), T·L_bg, is
//    not included unless `include_background` is set; then RGB is the full radiance.
//  Hence: full radiance = RGB + (1 − alpha)·L_bg, the "over" operator with a premultiplied layer.
//  White furnace: no sun, no ground, sky L ⇒ RGB = alpha·L exactly (and L with background).
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "physics/phase.h"
#include "reference/majorant_grid.h"
#include "scene/camera.h"
#include "scene/sun.h"
#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::reference {

enum class SunTransmittance { RatioTracking, Exact };

struct PathTracerSettings {
  int samples_per_pixel = 64;
  std::uint64_t seed = 1;
  /// Collisions (medium scatterings + ground bounces) per path; 1 = single scattering only.
  int max_events = 100000;
  /// Russian roulette from this many collisions on (the n-th survives with n/(n + 1), weight ÷
  /// survival; header comment): unbiased, the weight grows linearly with the path's length.
  /// 0 = off (paths run to max_events).
  int roulette_after_events = 1000;
  physics::PhaseMix phase;  ///< ice/water phase functions (defaults: HG 0.75 / 0.85)
  bool sun_enabled = true;
  SunTransmittance sun_transmittance = SunTransmittance::RatioTracking;
  glm::dvec3 sky_radiance{0.0};  ///< uniform sky radiance (linear RGB)
  bool ground_enabled = false;
  double ground_height_m = 0.0;   ///< world z of the ground plane (0 = mean sea level)
  glm::dvec3 ground_albedo{0.1};  ///< Lambertian albedo, used when ground_albedo_at is empty
  /// Optional per-point albedo (world x, y in metres) — e.g. the reprojected basemap.
  std::function<glm::dvec3(double x_m, double y_m)> ground_albedo_at;
  bool include_background = false;  ///< add T·L_bg (uncollided primary paths) to RGB
  bool pixel_jitter = false;        ///< false: every sample through the pixel centre, like the GPU
  int brick_voxels = kDefaultBrickVoxels;
  /// The extinction filter (volume/reconstruction.h), as in the GPU renderer; the majorants and
  /// the exact optical depth follow it.
  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear;
  int threads = 0;        ///< 0 = TBB's default
  bool progress = false;  ///< progress lines on stderr (through core/log)
};

struct PathTracerStats {
  std::uint64_t paths = 0;
  std::uint64_t truncated_paths = 0;  ///< cut by max_events (biased: their energy is lost)
  std::uint64_t rouletted_paths = 0;  ///< ended by Russian roulette (unbiased)
  std::uint64_t medium_collisions = 0;
  std::uint64_t ground_hits = 0;
  double max_path_weight = 1.0;  ///< largest throughput component after a roulette (≤ (N + 1)/D)
  double seconds = 0.0;
};

/// Mean and standard error of one pixel's (or ray's) estimate.
struct PixelEstimate {
  glm::dvec3 rgb{0.0};
  glm::dvec3 standard_error{0.0};  ///< sample standard deviation / √N per channel
  double alpha = 0.0;
  PathTracerStats stats;
};

struct PathTracedImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;            ///< premultiplied linear RGBA, row 0 = top, 4 per pixel
  std::vector<float> standard_error;  ///< per pixel, RGB standard error of the mean, 3 per pixel
  PathTracerStats stats;
  glm::vec4 pixel(int x, int y) const {
    const std::size_t i = 4 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
};

class PathTracer {
 public:
  /// Keeps a reference to `volumes`. Throws InputError for NaN/Inf/negative voxels.
  PathTracer(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame, const scene::Sun& sun,
             PathTracerSettings settings);
  // The majorant grid refers to the field member: not copyable or movable.
  PathTracer(const PathTracer&) = delete;
  PathTracer& operator=(const PathTracer&) = delete;

  /// The whole image of `camera` (TBB over rows; deterministic for a given seed).
  PathTracedImage render(const scene::Camera& camera) const;
  /// One pixel of `camera` with the same RNG stream as render() uses for it.
  PixelEstimate renderPixel(const scene::Camera& camera, int x, int y) const;
  /// `samples` paths along one explicit ray (unit dir), RNG stream `stream`.
  PixelEstimate estimateRay(const glm::dvec3& origin_m, const glm::dvec3& dir, int samples, std::uint64_t stream) const;
  /// 1 − exp(−τ) along a ray, τ exact, to the ground plane when it is on.
  double alpha(const glm::dvec3& origin_m, const glm::dvec3& dir) const;
  /// The exact alpha of every pixel-centre ray of `camera` (row 0 = top), without tracing paths:
  /// the yardstick for the GPU renderer's alpha channel.
  std::vector<float> renderAlpha(const scene::Camera& camera) const;

  const PathTracerSettings& settings() const { return settings_; }
  const MajorantGrid& majorants() const { return majorants_; }
  const ExtinctionField& field() const { return field_; }

 private:
  class Path;
  PixelEstimate estimate(const scene::Camera* camera, int px, int py, glm::dvec3 origin, glm::dvec3 dir, int samples,
                         std::uint64_t stream) const;
  double groundDistance(const glm::dvec3& origin_m, const glm::dvec3& dir) const;

  ExtinctionField field_;
  MajorantGrid majorants_;
  scene::Sun sun_;
  glm::dvec3 sun_irradiance_{0.0};
  glm::dvec3 to_sun_{0.0, 0.0, 1.0};
  PathTracerSettings settings_;
};

}  // namespace nph::reference

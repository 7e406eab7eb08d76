#include "reference/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/log.h"
#include "reference/path_tracer_rng.h"
#include "reference/path_tracer_sampling.h"

namespace nph::reference {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Ratio tracking: below this transmittance, Russian roulette with survival ½ (weight ×2).
constexpr double kRouletteTransmittance = 0.1;
/// Ground bounces: throughput below this is rouletted with survival = max component.
constexpr double kRouletteThroughput = 0.25;

/// Free-flight distance of an exponential distribution with rate μ̄ [1/m].
double freeFlight(PathRng& rng, double majorant_per_m) { return -std::log1p(-rng.uniform()) / majorant_per_m; }

double maxComponent(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

void add(PathTracerStats& into, const PathTracerStats& s) {
  into.paths += s.paths;
  into.truncated_paths += s.truncated_paths;
  into.rouletted_paths += s.rouletted_paths;
  into.medium_collisions += s.medium_collisions;
  into.ground_hits += s.ground_hits;
  into.max_path_weight = std::max(into.max_path_weight, s.max_path_weight);
}

}  // namespace

// One camera path: the estimators of the header comment, with the RNG stream of its pixel.
class PathTracer::Path {
 public:
  Path(const PathTracer& pt, PathRng& rng, PathTracerStats& stats) : pt_(pt), rng_(rng), stats_(stats) {}

  glm::dvec3 radiance(glm::dvec3 o, glm::dvec3 d) {
    const PathTracerSettings& s = pt_.settings_;
    glm::dvec3 l{0.0}, beta{1.0};
    bool primary = true;
    int events = 0;
    ++stats_.paths;
    for (;;) {
      const double tGround = pt_.groundDistance(o, d);
      double tHit = 0.0;
      Extinction e;
      if (deltaTrack(o, d, tGround, tHit, e)) {
        ++events;
        ++stats_.medium_collisions;
        primary = false;
        const glm::dvec3 x = o + tHit * d;
        if (s.sun_enabled) {
          // NEE with the full eq. 5.12 mixture; the photon travels −ω_sun → −d: cos ψ = ω_sun·d.
          const double t = sunTransmittance(x);
          if (t > 0.0) {
            const double p = s.phase.eval(glm::dot(pt_.to_sun_, d), e.ice_per_m, e.water_per_m);
            l += beta * pt_.sun_irradiance_ * (p * t);
          }
        }
        if (events >= s.max_events) {
          ++stats_.truncated_paths;
          break;
        }
        if (!survivesRoulette(events, beta)) break;
        const bool ice = rng_.uniform() < physics::PhaseMix::iceWeight(e.ice_per_m, e.water_per_m);
        const physics::PhaseFunction& phase = ice ? s.phase.ice : s.phase.water;
        const double mu = phase.sampleCos(rng_);
        d = aroundAxis(d, mu, 2.0 * std::numbers::pi * rng_.uniform());
        o = x;
        continue;
      }
      if (tGround < kInfinity) {
        if (primary && !s.include_background) break;  // the ground itself is background
        primary = false;
        ++events;
        ++stats_.ground_hits;
        glm::dvec3 x = o + tGround * d;
        x.z = s.ground_height_m;
        const glm::dvec3 albedo = s.ground_albedo_at ? s.ground_albedo_at(x.x, x.y) : s.ground_albedo;
        if (s.sun_enabled && pt_.to_sun_.z > 0.0) {
          const double t = sunTransmittance(x);
          if (t > 0.0) l += beta * albedo * pt_.sun_irradiance_ * (pt_.to_sun_.z * t / std::numbers::pi);
        }
        if (events >= s.max_events) {
          ++stats_.truncated_paths;
          break;
        }
        beta *= albedo;
        const double m = maxComponent(beta);
        if (!(m > 0.0)) break;
        if (m < kRouletteThroughput) {
          if (rng_.uniform() >= m) break;
          beta /= m;
        }
        // Cosine-weighted hemisphere about +z: the Lambertian BRDF·cos/pdf = albedo exactly.
        const double u = rng_.uniform();
        d = aroundAxis(glm::dvec3(0.0, 0.0, 1.0), std::sqrt(u), 2.0 * std::numbers::pi * rng_.uniform());
        o = x;
        continue;
      }
      if (!primary || s.include_background) l += beta * s.sky_radiance;
      break;
    }
    return l;
  }

 private:
  // Russian roulette past the depth (header comment): the n-th collision (n ≥ D) survives with
  // q_n = n/(n + 1) and the throughput is divided by q_n, so after N collisions it is (N + 1)/D —
  // growing linearly with the path, not as q^−K (e^{K/D}) as with a constant survival, whose
  // variance is infinite where paths diffuse for more than ~D collisions (the hurricane's fireflies).
  bool survivesRoulette(int events, glm::dvec3& beta) {
    const int depth = pt_.settings_.roulette_after_events;
    if (depth <= 0 || events < depth) return true;
    const double q = rouletteSurvival(events);
    if (rng_.uniform() >= q) {
      ++stats_.rouletted_paths;
      return false;
    }
    beta /= q;
    stats_.max_path_weight = std::max(stats_.max_path_weight, maxComponent(beta));
    return true;
  }

  // Delta tracking (Woodcock): tentative collisions at rate μ̄ per brick, real with μ/μ̄.
  // Height exaggeration keeps the data's optical depth: along d both β and μ̄ are scaled by
  // f(d) (VolumeFrame::opticalDepthScale), so the free flights shrink by f and the real/null
  // ratio β/μ̄ is unchanged.
  bool deltaTrack(const glm::dvec3& o, const glm::dvec3& d, double tMax, double& tHit, Extinction& e) {
    bool hit = false;
    const double f = pt_.field_.frame().opticalDepthScale(d);
    pt_.majorants_.traverse(o, d, 0.0, tMax, [&](double mu, double ta, double tb) {
      if (!(mu > 0.0)) return true;
      for (double t = ta;;) {
        t += freeFlight(rng_, mu * f);
        if (t >= tb) return true;
        e = pt_.field_.at(o + t * d);
        if (rng_.uniform() * mu < e.total()) {
          tHit = t;
          hit = true;
          return false;
        }
      }
    });
    return hit;
  }

  // Transmittance from x to the sun: ratio tracking (Cramer 1978; Novák et al. 2014) or exact.
  double sunTransmittance(const glm::dvec3& x) {
    const PathTracerSettings& s = pt_.settings_;
    if (s.ground_enabled && pt_.to_sun_.z <= 0.0) return 0.0;  // the ground blocks the sun
    if (s.sun_transmittance == SunTransmittance::Exact) {
      return std::exp(-pt_.field_.opticalDepth(x, pt_.to_sun_, 0.0, kInfinity));
    }
    double tr = 1.0;
    const double f = pt_.field_.frame().opticalDepthScale(pt_.to_sun_);
    pt_.majorants_.traverse(x, pt_.to_sun_, 0.0, kInfinity, [&](double mu, double ta, double tb) {
      if (!(mu > 0.0)) return true;
      for (double t = ta;;) {
        t += freeFlight(rng_, mu * f);
        if (t >= tb) return true;
        tr *= 1.0 - pt_.field_.at(x + t * pt_.to_sun_).total() / mu;
        if (tr < kRouletteTransmittance) {
          if (!(tr > 0.0) || rng_.uniform() < 0.5) {
            tr = 0.0;
            return false;
          }
          tr *= 2.0;
        }
      }
    });
    return tr;
  }

  const PathTracer& pt_;
  PathRng& rng_;
  PathTracerStats& stats_;
};

PathTracer::PathTracer(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame, const scene::Sun& sun,
                       PathTracerSettings settings)
    : field_(volumes, frame, settings.reconstruction),
      majorants_(field_, settings.brick_voxels),
      sun_(sun),
      settings_(std::move(settings)) {
  if (settings_.samples_per_pixel < 1) throw UsageError("PathTracer: samples_per_pixel must be at least 1");
  if (settings_.max_events < 1) throw UsageError("PathTracer: max_events must be at least 1");
  if (settings_.roulette_after_events < 0 || settings_.roulette_after_events == 1) {
    throw UsageError("PathTracer: roulette_after_events must be 0 (off) or at least 2");
  }
  for (const auto* p : {&settings_.phase.ice, &settings_.phase.water}) {
    if (!(p->g > -1.0 && p->g < 1.0)) throw UsageError("PathTracer: phase asymmetry g must lie in (-1, 1)");
  }
  to_sun_ = glm::normalize(sun.toSun());
  sun_irradiance_ = sun.intensity * sun.colour;
}

double PathTracer::groundDistance(const glm::dvec3& origin_m, const glm::dvec3& dir) const {
  if (!settings_.ground_enabled || !(dir.z < 0.0) || !(origin_m.z > settings_.ground_height_m)) return kInfinity;
  return (settings_.ground_height_m - origin_m.z) / dir.z;
}

double PathTracer::alpha(const glm::dvec3& origin_m, const glm::dvec3& dir) const {
  return -std::expm1(-field_.opticalDepth(origin_m, dir, 0.0, groundDistance(origin_m, dir)));
}

std::vector<float> PathTracer::renderAlpha(const scene::Camera& camera) const {
  if (camera.width < 1 || camera.height < 1) throw UsageError("PathTracer::renderAlpha: empty image");
  std::vector<float> out(std::size_t(camera.width) * std::size_t(camera.height), 0.0f);
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, camera.height), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y < r.end(); ++y)
        for (int x = 0; x < camera.width; ++x)
          out[std::size_t(y) * std::size_t(camera.width) + std::size_t(x)] =
              float(alpha(camera.position_m, camera.rayDirection(double(x) + 0.5, double(y) + 0.5)));
    });
  });
  return out;
}

PixelEstimate PathTracer::estimate(const scene::Camera* camera, int px, int py, glm::dvec3 origin, glm::dvec3 dir,
                                   int samples, std::uint64_t stream) const {
  PathRng rng(settings_.seed, stream);
  PixelEstimate est;
  Path path(*this, rng, est.stats);
  const bool jitter = camera != nullptr && settings_.pixel_jitter;
  glm::dvec3 sum{0.0}, sumSq{0.0};
  double alphaSum = 0.0;
  const double centreAlpha = jitter ? 0.0 : alpha(origin, dir);
  for (int i = 0; i < samples; ++i) {
    if (jitter) {
      const double jx = rng.uniform(), jy = rng.uniform();
      dir = camera->rayDirection(double(px) + jx, double(py) + jy);
      alphaSum += alpha(origin, dir);
    }
    const glm::dvec3 l = path.radiance(origin, dir);
    sum += l;
    sumSq += l * l;
  }
  const double n = double(samples);
  est.rgb = sum / n;
  if (samples > 1) {
    const glm::dvec3 var = glm::max(glm::dvec3(0.0), (sumSq - n * est.rgb * est.rgb) / (n - 1.0));
    est.standard_error = glm::sqrt(var / n);
  }
  est.alpha = jitter ? alphaSum / n : centreAlpha;
  return est;
}

PixelEstimate PathTracer::estimateRay(const glm::dvec3& origin_m, const glm::dvec3& dir, int samples,
                                      std::uint64_t stream) const {
  if (samples < 1) throw UsageError("PathTracer::estimateRay: samples must be at least 1");
  return estimate(nullptr, 0, 0, origin_m, glm::normalize(dir), samples, stream);
}

PixelEstimate PathTracer::renderPixel(const scene::Camera& camera, int x, int y) const {
  if (x < 0 || y < 0 || x >= camera.width || y >= camera.height) {
    throw UsageError("PathTracer::renderPixel: pixel outside the image");
  }
  const std::uint64_t stream = std::uint64_t(y) * std::uint64_t(camera.width) + std::uint64_t(x);
  return estimate(&camera, x, y, camera.position_m, camera.rayDirection(double(x) + 0.5, double(y) + 0.5),
                  settings_.samples_per_pixel, stream);
}

PathTracedImage PathTracer::render(const scene::Camera& camera) const {
  if (camera.width < 1 || camera.height < 1) throw UsageError("PathTracer::render: empty image");
  const auto start = std::chrono::steady_clock::now();
  PathTracedImage img;
  img.width = camera.width;
  img.height = camera.height;
  const std::size_t pixels = std::size_t(camera.width) * std::size_t(camera.height);
  img.rgba.assign(4 * pixels, 0.0f);
  img.standard_error.assign(3 * pixels, 0.0f);
  std::vector<PathTracerStats> rowStats(std::size_t(camera.height));
  std::atomic<int> rowsDone{0};
  const int step = std::max(1, camera.height / 10);
  auto rows = [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      for (int x = 0; x < camera.width; ++x) {
        const PixelEstimate e = renderPixel(camera, x, y);
        const std::size_t i = std::size_t(y) * std::size_t(camera.width) + std::size_t(x);
        for (int c = 0; c < 3; ++c) {
          img.rgba[4 * i + std::size_t(c)] = float(e.rgb[c]);
          img.standard_error[3 * i + std::size_t(c)] = float(e.standard_error[c]);
        }
        img.rgba[4 * i + 3] = float(e.alpha);
        add(rowStats[std::size_t(y)], e.stats);
      }
      const int done = ++rowsDone;
      if (settings_.progress && (done % step == 0 || done == camera.height)) {
        log::info("path tracer: {}/{} rows ({:.0f} %)", done, camera.height, 100.0 * done / camera.height);
      }
    }
  };
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<int>(0, camera.height), rows); });
  for (const PathTracerStats& s : rowStats) add(img.stats, s);
  img.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (settings_.progress) {
    log::info("path tracer: {}x{} at {} spp in {:.2f} s, {} paths, {} cut at max_events, {} rouletted "
              "(largest weight {:.1f}), {:.2f} collisions/path",
              camera.width, camera.height, settings_.samples_per_pixel, img.stats.seconds, img.stats.paths,
              img.stats.truncated_paths, img.stats.rouletted_paths, img.stats.max_path_weight,
              double(img.stats.medium_collisions + img.stats.ground_hits) /
                  double(std::max<std::uint64_t>(1, img.stats.paths)));
  }
  return img;
}

}  // namespace nph::reference

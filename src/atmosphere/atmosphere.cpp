#include "atmosphere/atmosphere.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nph::atmosphere {
namespace {

constexpr double kPi = std::numbers::pi;

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

glm::dvec3 expNeg(const glm::dvec3& tau) { return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)}; }

// ∫_0^Δ e^{−σ t} dt per channel = (1 − e^{−σΔ})/σ, Δ as σ → 0 (Hillaire 2020 §5.1).
glm::dvec3 stepIntegral(const glm::dvec3& sigma, double delta) {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    const double x = sigma[c] * delta;
    out[c] = x > 1e-9 ? -std::expm1(-x) / sigma[c] : delta;
  }
  return out;
}

// Altitude and sun zenith cosine at distance t along a ray (spherical or plane-parallel world).
struct Sample {
  double r_m, mu_s;
};
Sample sampleAt(const glm::dvec3& origin, const glm::dvec3& dir, double t, const glm::dvec3& to_sun,
                bool plane_parallel) {
  if (plane_parallel) return {glm::length(origin) + t * dir.z, to_sun.z};
  const glm::dvec3 x = origin + t * dir;
  const double r = glm::length(x);
  return {r, glm::dot(x, to_sun) / r};
}

}  // namespace

glm::dvec3 ozoneAbsorption(const Parameters& p, double h) {
  return std::max(0.0, 1.0 - std::abs(h - p.ozone_center_m) / p.ozone_half_width_m) * p.ozone_absorption_per_m;
}

Medium mediumAt(const Parameters& p, double h) {
  const double rayleigh = std::exp(-h / p.rayleigh_scale_height_m);
  const double mie = std::exp(-h / p.mie_scale_height_m);
  Medium m;
  m.rayleigh_scattering_per_m = rayleigh * p.rayleigh_scattering_per_m;
  m.mie_scattering_per_m = mie * p.mie_scattering_per_m;
  m.extinction_per_m =
      m.rayleigh_scattering_per_m + mie * (p.mie_scattering_per_m + p.mie_absorption_per_m) + ozoneAbsorption(p, h);
  return m;
}

double rayleighPhase(double c) { return 3.0 / (16.0 * kPi) * (1.0 + c * c); }

double miePhase(double c, double g) {
  const double g2 = g * g;
  return 3.0 / (8.0 * kPi) * (1.0 - g2) * (1.0 + c * c) / ((2.0 + g2) * std::pow(1.0 + g2 - 2.0 * g * c, 1.5));
}

// Bruneton 2017 §"Distance to the top/bottom atmosphere boundary": the roots of
// t² + 2rμ·t + r² − R² = 0, the discriminant written r²(μ² − 1) + R².
double distanceToTop(const Parameters& p, double r, double mu) {
  const double disc = r * r * (mu * mu - 1.0) + p.top_radius_m * p.top_radius_m;
  return std::max(0.0, -r * mu + std::sqrt(std::max(disc, 0.0)));
}

double distanceToGround(const Parameters& p, double r, double mu) {
  const double disc = r * r * (mu * mu - 1.0) + p.bottom_radius_m * p.bottom_radius_m;
  return std::max(0.0, -r * mu - std::sqrt(std::max(disc, 0.0)));
}

bool rayHitsGround(const Parameters& p, double r, double mu) {
  return mu < 0.0 && r * r * (mu * mu - 1.0) + p.bottom_radius_m * p.bottom_radius_m >= 0.0;
}

glm::dvec3 transmittanceToTop(const Parameters& p, double r, double mu, int steps) {
  const double length = distanceToTop(p, r, mu);
  const double dt = length / steps;
  glm::dvec3 tau(0.0);
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * dt;
    // Radius at t by the law of cosines (Bruneton 2017 ComputeOpticalLengthToTopAtmosphereBoundary).
    const double ri = std::sqrt(t * t + 2.0 * r * mu * t + r * r);
    tau += mediumAt(p, ri - p.bottom_radius_m).extinction_per_m * dt;
  }
  return expNeg(tau);
}

double sunVisibility(const Parameters& p, double r, double mu_s) {
  const double sin_h = p.bottom_radius_m / r;
  const double cos_h = -std::sqrt(std::max(1.0 - sin_h * sin_h, 0.0));
  const double a = sin_h * p.sun_angular_radius_rad;
  return smoothstep(-a, a, mu_s - cos_h);
}

glm::dvec3 sunTransmittance(const Parameters& p, double r, double mu_s, int steps) {
  const double v = sunVisibility(p, r, mu_s);
  return v > 0.0 ? v * transmittanceToTop(p, r, mu_s, steps) : glm::dvec3(0.0);
}

glm::dvec3 multipleScattering(const Parameters& p, double r, double mu_s, const Quadrature& q) {
  if (!p.multiple_scattering) return glm::dvec3(0.0);
  const glm::dvec3 x(0.0, 0.0, r);
  const glm::dvec3 to_sun(std::sqrt(std::max(1.0 - mu_s * mu_s, 0.0)), 0.0, mu_s);
  const double isotropic = 1.0 / (4.0 * kPi);  // p_u
  const double cell_sr = 4.0 * kPi / (q.ms_directions_mu * q.ms_directions_phi);
  glm::dvec3 second(0.0), transfer(0.0);  // L_2nd and f_ms (eqs. 6, 7)
  for (int i = 0; i < q.ms_directions_mu; ++i) {
    const double cos_t = -1.0 + (i + 0.5) * 2.0 / q.ms_directions_mu;  // equal-area bands
    const double sin_t = std::sqrt(1.0 - cos_t * cos_t);
    for (int j = 0; j < q.ms_directions_phi; ++j) {
      const double phi = (j + 0.5) * 2.0 * kPi / q.ms_directions_phi;
      const glm::dvec3 w(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
      const bool ground = rayHitsGround(p, r, cos_t);
      const double length = ground ? distanceToGround(p, r, cos_t) : distanceToTop(p, r, cos_t);
      const double dt = length / q.ms_steps;
      glm::dvec3 throughput(1.0), lum(0.0), lf(0.0);
      for (int k = 0; k < q.ms_steps; ++k) {
        const double t = (k + 0.5) * dt;
        const glm::dvec3 y = x + t * w;
        const double ry = glm::length(y);
        const Medium m = mediumAt(p, ry - p.bottom_radius_m);
        const glm::dvec3 sigma_s = m.rayleigh_scattering_per_m + m.mie_scattering_per_m;
        const glm::dvec3 sun = sunTransmittance(p, ry, glm::dot(y, to_sun) / ry, q.ms_transmittance_steps);
        const glm::dvec3 piece = throughput * stepIntegral(m.extinction_per_m, dt);
        lum += piece * sigma_s * sun * isotropic;  // L': once-scattered sunlight, isotropic phase
        lf += piece * sigma_s;                     // L_f: unit isotropic light, scattered once
        throughput *= expNeg(m.extinction_per_m * dt);
      }
      if (ground) {  // the lit Lambertian ground at the end of the ray (Hillaire §5.2)
        const glm::dvec3 g = x + length * w;
        const glm::dvec3 n = glm::normalize(g);
        const double cos_sun = glm::dot(n, to_sun);
        const glm::dvec3 sun = sunTransmittance(p, glm::length(g), cos_sun, q.ms_transmittance_steps);
        lum += throughput * sun * std::max(cos_sun, 0.0) * p.ground_albedo / kPi;
      }
      second += lum * isotropic * cell_sr;
      transfer += lf * isotropic * cell_sr;
    }
  }
  return second / (glm::dvec3(1.0) - transfer);  // Ψ_ms = L_2nd · 1/(1 − f_ms) (eqs. 8–10)
}

double planeParallelOzoneCap(const Parameters& p, double mu) {
  const double layer_m = 2.0 * p.ozone_half_width_m;
  const double chord_m = 2.0 * std::sqrt(2.0 * p.bottom_radius_m * layer_m);
  return std::min(1.0, std::abs(mu) * chord_m / layer_m);
}

Segment integrateSegment(const Parameters& p, const glm::dvec3& origin, const glm::dvec3& dir, double length,
                         const glm::dvec3& to_sun, const Quadrature& q, bool plane_parallel, bool flat_sun) {
  Segment s;
  if (length <= 0.0) return s;
  const double cos_theta = glm::dot(dir, to_sun);  // scattering angle: sunlight → towards the eye is −dir
  const double phase_r = rayleighPhase(cos_theta), phase_m = miePhase(cos_theta, p.mie_g);
  const double dt = length / q.view_steps;
  const double ozone_cap = plane_parallel ? planeParallelOzoneCap(p, dir.z) : 1.0;
  for (int i = 0; i < q.view_steps; ++i) {
    Sample x = sampleAt(origin, dir, (i + 0.5) * dt, to_sun, plane_parallel);
    // A straight ray between two points in the air dips below the ground when they lie beyond
    // each other's horizon (flatPointAlongRoundPlanet): the air there is taken as the ground's.
    if (!plane_parallel) x.r_m = std::max(x.r_m, p.bottom_radius_m);
    if (flat_sun) x.mu_s = to_sun.z;
    Medium m = mediumAt(p, x.r_m - p.bottom_radius_m);
    if (plane_parallel) m.extinction_per_m -= (1.0 - ozone_cap) * ozoneAbsorption(p, x.r_m - p.bottom_radius_m);
    const glm::dvec3 sun = sunTransmittance(p, x.r_m, x.mu_s, q.transmittance_steps);
    const glm::dvec3 ms = multipleScattering(p, x.r_m, x.mu_s, q);
    const glm::dvec3 source = m.rayleigh_scattering_per_m * (sun * phase_r + ms) +  // S(x), eq. 11
                              m.mie_scattering_per_m * (sun * phase_m + ms);
    s.inscattered += s.transmittance * source * stepIntegral(m.extinction_per_m, dt);
    s.transmittance *= expNeg(m.extinction_per_m * dt);
  }
  return s;
}

RoundChord flatPointOnRoundPlanet(const Parameters& p, double eye_altitude_m, const glm::dvec3& dir, double length_m) {
  const double horizontal = std::hypot(dir.x, dir.y);
  const double d = length_m * horizontal;  // the ground distance
  const double h = eye_altitude_m + length_m * dir.z;
  const double theta = d / p.bottom_radius_m, r = p.bottom_radius_m + h;
  const glm::dvec2 e = horizontal > 0.0 ? glm::dvec2(dir.x, dir.y) / horizontal : glm::dvec2(0.0);
  // P − E with the vertical difference in closed form: (R + h)cos θ − (R + h0) = (h − h0) − 2(R + h)sin²(θ/2).
  const double s = std::sin(0.5 * theta);
  const glm::dvec3 v(r * std::sin(theta) * e, (h - eye_altitude_m) - 2.0 * r * s * s);
  RoundChord c;
  c.origin_m = observerAt(p, eye_altitude_m);
  c.length_m = glm::length(v);
  c.dir = c.length_m > 0.0 ? v / c.length_m : dir;
  return c;
}

Segment aerialPerspectiveOfFlatPoint(const Parameters& p, double eye_altitude_m, const glm::dvec3& dir, double length_m,
                                     const glm::dvec3& to_sun, const Quadrature& q) {
  const RoundChord c = flatPointOnRoundPlanet(p, eye_altitude_m, dir, length_m);
  // The part of the chord inside the atmosphere's top sphere.
  const double b = glm::dot(c.origin_m, c.dir);
  const double disc = b * b - (glm::dot(c.origin_m, c.origin_m) - p.top_radius_m * p.top_radius_m);
  if (disc <= 0.0) return {};
  const double t0 = std::max(-b - std::sqrt(disc), 0.0), t1 = std::min(-b + std::sqrt(disc), c.length_m);
  if (t1 <= t0) return {};
  return integrateSegment(p, c.origin_m + t0 * c.dir, c.dir, t1 - t0, to_sun, q, false, true);
}

glm::dvec3 skyRadiance(const Parameters& p, const glm::dvec3& origin, const glm::dvec3& dir, const glm::dvec3& to_sun,
                       const Quadrature& q) {
  double r = glm::length(origin);
  double mu = glm::dot(origin, dir) / r;
  glm::dvec3 start = origin;
  if (r > p.top_radius_m) {  // from space: move to where the ray enters the atmosphere
    const double disc = r * r * (mu * mu - 1.0) + p.top_radius_m * p.top_radius_m;
    if (mu >= 0.0 || disc < 0.0) return glm::dvec3(0.0);
    start = origin + (-r * mu - std::sqrt(disc)) * dir;
    r = glm::length(start);
    mu = glm::dot(start, dir) / r;
  }
  const double length = rayHitsGround(p, r, mu) ? distanceToGround(p, r, mu) : distanceToTop(p, r, mu);
  return integrateSegment(p, start, dir, length, to_sun, q).inscattered;
}

glm::dvec3 skyIrradiance(const Parameters& p, double altitude_m, double sun_elevation_rad, const Quadrature& q) {
  const glm::dvec3 x = observerAt(p, altitude_m);
  const glm::dvec3 to_sun(std::cos(sun_elevation_rad), 0.0, std::sin(sun_elevation_rad));
  // The hemisphere in equal-cos-θ bands (dΩ·cos θ integrated exactly per band: ∫cos θ d(cos θ))
  // and azimuth cells over [0, π], mirrored (the sky is symmetric about the sun's vertical).
  glm::dvec3 e(0.0);
  const double dphi = kPi / q.irradiance_phi;
  for (int i = 0; i < q.irradiance_mu; ++i) {
    const double c0 = double(i) / q.irradiance_mu, c1 = double(i + 1) / q.irradiance_mu;
    const double cos_t = 0.5 * (c0 + c1), sin_t = std::sqrt(1.0 - cos_t * cos_t);
    const double weight = 0.5 * (c1 * c1 - c0 * c0) * dphi * 2.0;  // ∫cos θ d(cos θ) · Δφ, both halves
    for (int j = 0; j < q.irradiance_phi; ++j) {
      const double phi = (j + 0.5) * dphi;
      const glm::dvec3 w(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
      e += skyRadiance(p, x, w, to_sun, q) * weight;
    }
  }
  return e;
}

double horizontalIlluminance(const Parameters& p, double altitude_m, double sun_elevation_rad) {
  const glm::dvec3 e = horizontalIrradiance(p, altitude_m, sun_elevation_rad);
  return 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
}

glm::dvec3 horizontalIrradiance(const Parameters& p, double altitude_m, double sun_elevation_rad) {
  Parameters once = p;
  once.multiple_scattering = false;
  Quadrature q;
  q.irradiance_mu = q.irradiance_phi = 6;
  q.view_steps = q.transmittance_steps = 48;
  const double mu_s = std::sin(sun_elevation_rad);
  const glm::dvec3 direct =
      std::max(mu_s, 0.0) * sunTransmittance(p, p.bottom_radius_m + altitude_m, mu_s, q.transmittance_steps);
  return direct + skyIrradiance(once, altitude_m, sun_elevation_rad, q);
}

}  // namespace nph::atmosphere

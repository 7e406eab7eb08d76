#include "render/raycast/globe.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"

namespace nph::render {
namespace {

constexpr double kR = volume::kEarthRadius_m;

glm::dvec3 ecefFromRotated(const GlobeMapping& m, glm::dvec2 ab) {
  const glm::dvec3 local{std::cos(ab.y) * std::sin(ab.x), std::sin(ab.y), std::cos(ab.y) * std::cos(ab.x)};
  return glm::transpose(m.local_from_ecef) * local;  // rotation: inverse = transpose
}

/// Largest singular value of the 2×2 matrix with columns c0, c1.
double spectralNorm(glm::dvec2 c0, glm::dvec2 c1) {
  const double a = glm::dot(c0, c0), b = glm::dot(c0, c1), d = glm::dot(c1, c1);
  return std::sqrt(0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b));
}

}  // namespace

glm::dvec2 rotatedLonLat(const GlobeMapping& m, const glm::dvec3& p) {
  const glm::dvec3 q = m.local_from_ecef * p;  // (east, north, up)
  return {std::atan2(q.x, q.z), std::asin(std::clamp(q.y / glm::length(q), -1.0, 1.0))};
}

GlobeMapping buildGlobeMapping(const scene::SceneGeoreference& geo, int long_side) {
  if (long_side < 2) throw UsageError(fmt::format("globe: look-up table of {} texels", long_side));
  const volume::VolumeFrame& f = geo.frame();
  const glm::dvec3 pad = f.voxel_size_m;  // β fades to 0 over one voxel outside the box
  const glm::dvec3 lo = f.min_m() - pad, hi = f.max_m() + pad;
  GlobeMapping m;
  const scene::LonLat centre = geo.footprintCentre();
  m.local_from_ecef = glm::transpose(scene::ecefFromEnu(centre));
  m.cap_axis = scene::ecefFromLonLat(centre, 0.0, 1.0);
  m.shell_min_m = kR + lo.z;
  m.shell_max_m = kR + hi.z;

  // Outline of the grown footprint: its (a, b) box and its cone around the centre's axis.
  constexpr int kSamplesPerEdge = 128;
  glm::dvec2 abLo(std::numeric_limits<double>::max()), abHi(-std::numeric_limits<double>::max());
  double minCos = 1.0;
  for (int k = 0; k <= kSamplesPerEdge; ++k) {
    const double t = double(k) / kSamplesPerEdge;
    const double x = glm::mix(lo.x, hi.x, t), y = glm::mix(lo.y, hi.y, t);
    for (glm::dvec2 w : {glm::dvec2{x, lo.y}, glm::dvec2{x, hi.y}, glm::dvec2{lo.x, y}, glm::dvec2{hi.x, y}}) {
      const glm::dvec3 p = geo.ecefFromWorld({w.x, w.y, 0.0});
      const glm::dvec2 ab = rotatedLonLat(m, p);
      abLo = glm::min(abLo, ab);
      abHi = glm::max(abHi, ab);
      minCos = std::min(minCos, glm::dot(glm::normalize(p), m.cap_axis));
    }
  }
  if (abHi.x - abLo.x > 3.0 || abHi.y - abLo.y > 3.0) {
    throw InputError("globe: the footprint spans more than a hemisphere; the globe view needs a regional domain");
  }
  // The outline between samples bulges by far less than 2 % of the box; the cone likewise.
  const glm::dvec2 grow = 0.02 * (abHi - abLo);
  m.ab_min_rad = abLo - grow;
  m.ab_max_rad = abHi + grow;
  m.margin_rad = std::min(grow.x, grow.y);
  m.cap_cos = std::cos(std::min(1.02 * std::acos(std::min(minCos, 1.0)), 1.5));

  const glm::dvec2 extent = m.ab_max_rad - m.ab_min_rad;
  const double longer = std::max(extent.x, extent.y);
  m.width = std::max(2, int(std::lround(long_side * extent.x / longer)));
  m.height = std::max(2, int(std::lround(long_side * extent.y / longer)));
  const glm::dvec2 cell = extent / glm::dvec2(m.width, m.height);
  auto exact = [&](glm::dvec2 ab) {
    const scene::LonLat ll = scene::lonLatFromEcef(ecefFromRotated(m, ab));
    return geo.worldFromLonLat(ll);
  };
  m.world_xy_m.resize(std::size_t(m.width) * std::size_t(m.height) * 2);
  std::vector<glm::dvec2> w(std::size_t(m.width) * std::size_t(m.height));
  for (int j = 0; j < m.height; ++j) {
    for (int i = 0; i < m.width; ++i) {
      const glm::dvec2 ab = m.ab_min_rad + (glm::dvec2(i, j) + 0.5) * cell;
      const std::size_t k = std::size_t(j) * std::size_t(m.width) + std::size_t(i);
      w[k] = exact(ab);
      m.world_xy_m[2 * k] = float(w[k].x);
      m.world_xy_m[2 * k + 1] = float(w[k].y);
    }
  }
  // L_h: the bilinear patch's Jacobian (world metres per metre of arc on the sphere R) is largest
  // at a cell corner; convert arc on R to ECEF distance at the lowest radius of the shell.
  double maxNorm = 0.0;
  for (int j = 0; j + 1 < m.height; ++j) {
    for (int i = 0; i + 1 < m.width; ++i) {
      const auto at = [&](int ii, int jj) { return w[std::size_t(jj) * std::size_t(m.width) + std::size_t(ii)]; };
      for (int cj = 0; cj < 2; ++cj) {
        for (int ci = 0; ci < 2; ++ci) {
          const double b = m.ab_min_rad.y + (j + cj + 0.5) * cell.y;
          const glm::dvec2 da = (at(i + 1, j + cj) - at(i, j + cj)) / (kR * std::cos(b) * cell.x);
          const glm::dvec2 db = (at(i + ci, j + 1) - at(i + ci, j)) / (kR * cell.y);
          maxNorm = std::max(maxNorm, spectralNorm(da, db));
        }
      }
    }
  }
  constexpr double kSafety = 1.01;  // finite differences vs the true derivative, float rounding
  m.horizontal_lipschitz = kSafety * maxNorm * kR / std::min(m.shell_min_m, kR);
  // Interpolation error at cell centres (the farthest points from the texel centres), every 4th.
  for (int j = 0; j + 1 < m.height; j += 4) {
    for (int i = 0; i + 1 < m.width; i += 4) {
      const glm::dvec2 ab = m.ab_min_rad + (glm::dvec2(i, j) + 1.0) * cell;
      const glm::dvec2 t = worldXyFromTable(m, ecefFromRotated(m, ab));
      m.max_interpolation_error_m = std::max(m.max_interpolation_error_m, glm::length(t - exact(ab)));
    }
  }
  log::debug(
      "globe: look-up table {}x{} over {:.2f}x{:.2f} deg, interpolation error <= {:.2f} m, L_h {:.4f}, cap {:.2f} deg",
      m.width, m.height, glm::degrees(extent.x), glm::degrees(extent.y), m.max_interpolation_error_m,
      m.horizontal_lipschitz, glm::degrees(std::acos(m.cap_cos)));
  return m;
}

glm::dvec2 worldXyFromTable(const GlobeMapping& m, const glm::dvec3& ecef_m) {
  const glm::dvec2 uv = (rotatedLonLat(m, ecef_m) - m.ab_min_rad) / (m.ab_max_rad - m.ab_min_rad);
  if (uv.x < 0.0 || uv.y < 0.0 || uv.x > 1.0 || uv.y > 1.0) return glm::dvec2(std::nan(""));
  // GL_LINEAR with GL_CLAMP_TO_EDGE: texel centres at (i + ½)/width.
  const glm::dvec2 t = uv * glm::dvec2(m.width, m.height) - 0.5;
  const glm::ivec2 i0 = glm::clamp(glm::ivec2(glm::floor(t)), glm::ivec2(0), glm::ivec2(m.width - 1, m.height - 1));
  const glm::ivec2 i1 = glm::min(i0 + 1, glm::ivec2(m.width - 1, m.height - 1));
  const glm::dvec2 f = glm::clamp(t - glm::dvec2(i0), 0.0, 1.0);
  const auto at = [&](int i, int j) {
    const std::size_t k = 2 * (std::size_t(j) * std::size_t(m.width) + std::size_t(i));
    return glm::dvec2(m.world_xy_m[k], m.world_xy_m[k + 1]);
  };
  return glm::mix(glm::mix(at(i0.x, i0.y), at(i1.x, i0.y), f.x), glm::mix(at(i0.x, i1.y), at(i1.x, i1.y), f.x), f.y);
}

}  // namespace nph::render

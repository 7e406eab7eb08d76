#include "volume/detail.h"

#include <algorithm>
#include <cmath>

#include "core/glsl_cpp.h"

namespace nph::volume {

namespace detail_f32 {
using namespace nph::glsl;
using Number = float;
#include "../glsl/common/detail.glsl"
static_assert(double(kDetailShapeDisplacement) == kDetailShapeDisplacementScale,
              "volume/detail.h and detail.glsl must agree on the shape's displacement");
}  // namespace detail_f32

void packNoiseStats(const NoiseStats& s, glm::vec4& ra, glm::vec4& gs, glm::vec4& c) {
  ra = glm::vec4(s.r.mean, s.r.half_range, s.a.mean, s.a.half_range);
  gs = glm::vec4(s.g.mean, s.g.half_range, s.stratiform.mean, s.stratiform.half_range);
  c = glm::vec4(s.convective.mean, s.convective.half_range, 0.0f, 0.0f);
}

DetailParameters detailParameters(Detail detail, const VolumeFrame& frame) {
  DetailParameters p;
  p.detail = detail;
  p.amplitude = detail == Detail::Full ? 1.0 : detail == Detail::Subtle ? 0.5 : 0.0;
  const glm::dvec3 voxel = frame.voxel_size_m;
  const double column_m = std::max(voxel.x, voxel.y);
  p.period_m = glm::dvec3(2.0 * column_m);
  p.reach_m = p.amplitude * glm::dvec3(0.25 * voxel.x, 0.25 * voxel.y, std::min(0.25 * column_m, voxel.z));
  const glm::dvec3 r = p.reach_m / voxel;
  p.reach_voxels = int(std::ceil(std::max({r.x, r.y, r.z}) - 1e-9));
  return p;
}

namespace {
// GL_LINEAR with GL_CLAMP_TO_EDGE on an nx × ny × nz grid at continuous grid coordinates g (voxel
// centres at i + ½): the 8 texels' weights, `texel(q)` the value of voxel index q (x fastest).
template <class T, class Texel>
T linearClampToEdge(const glm::dvec3& g, int nx, int ny, int nz, Texel texel) {
  const glm::dvec3 c = g - 0.5;
  const glm::dvec3 fl = glm::floor(c);
  const glm::dvec3 t = c - fl;
  const glm::ivec3 i0(fl);
  T r(0.0);
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double w = (dx ? t.x : 1.0 - t.x) * (dy ? t.y : 1.0 - t.y) * (dz ? t.z : 1.0 - t.z);
        if (w == 0.0) continue;
        const int i = std::clamp(i0.x + dx, 0, nx - 1), j = std::clamp(i0.y + dy, 0, ny - 1),
                  k = std::clamp(i0.z + dz, 0, nz - 1);
        r += w * texel((std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx) + std::size_t(i));
      }
  return r;
}
}  // namespace

glm::dvec4 DetailControls::at(const glm::dvec3& g) const {
  return linearClampToEdge<glm::dvec4>(g, nx, ny, nz,
                                       [&](std::size_t q) {
                                         return glm::dvec4(rgba[4 * q], rgba[4 * q + 1], rgba[4 * q + 2],
                                                           rgba[4 * q + 3]);
                                       }) /
         255.0;
}

double detailClock_s(const geo::OptionalUtcTime& time_utc) {
  static const geo::UtcTime epoch = geo::UtcTime::parse("2000-01-01T00:00:00Z");
  return time_utc ? time_utc->secondsSince(epoch) : 0.0;
}

DetailFlow detailFlow(double clock_s, bool has_wind) {
  DetailFlow f;
  if (!has_wind || !std::isfinite(clock_s)) return f;  // τ = 0, weight 1: the world-fixed noise
  const double phi = clock_s / kDetailFlowPeriod_s - std::floor(clock_s / kDetailFlowPeriod_s);
  const double phi_b = phi + 0.5 - std::floor(phi + 0.5);
  f.tau_s = glm::dvec2(phi, phi_b) * kDetailFlowPeriod_s;
  f.weight_a = 1.0 - std::abs(2.0 * phi - 1.0);
  return f;
}

glm::dvec2 DetailWind::at(const glm::dvec3& g) const {
  return linearClampToEdge<glm::dvec2>(g, nx, ny, nz,
                                       [&](std::size_t q) { return glm::dvec2(uv[2 * q], uv[2 * q + 1]); });
}

DetailWind buildDetailWind(const ExtinctionVolumes& v) {
  DetailWind w;
  const std::size_t n = v.voxelCount();
  if (v.wind_u_m_per_s.size() != n || v.wind_v_m_per_s.size() != n || n == 0) return w;
  w.nx = v.nx;
  w.ny = v.ny;
  w.nz = v.nz;
  w.uv.resize(2 * n);
  for (std::size_t q = 0; q < n; ++q) {
    // Non-finite winds (a broken file the loader let through) would poison the noise: read as calm.
    w.uv[2 * q] = std::isfinite(v.wind_u_m_per_s[q]) ? v.wind_u_m_per_s[q] : 0.0f;
    w.uv[2 * q + 1] = std::isfinite(v.wind_v_m_per_s[q]) ? v.wind_v_m_per_s[q] : 0.0f;
  }
  return w;
}

namespace {
double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
}  // namespace

DetailControls buildDetailControls(const ExtinctionVolumes& v) {
  DetailControls c;
  c.nx = v.nx;
  c.ny = v.ny;
  c.nz = v.nz;
  const std::size_t n = v.voxelCount();
  c.rgba.assign(4 * n, 0);
  std::vector<float> beta(n, 0.0f);
  for (std::size_t q = 0; q < n; ++q) {
    beta[q] = (v.ice_per_m.size() == n ? v.ice_per_m[q] : 0.0f) + (v.water_per_m.size() == n ? v.water_per_m[q] : 0.0f);
  }
  const bool hasTke = v.tke_m2_per_s2.size() == n, hasW = v.wind_w_m_per_s.size() == n,
             hasFraction = v.cloud_fraction.size() == n;
  const auto b = [&](int i, int j, int k) -> double {
    if (i < 0 || j < 0 || k < 0 || i >= v.nx || j >= v.ny || k >= v.nz) return 0.0;
    return double(beta[v.index(i, j, k)]);
  };
  constexpr double kCondensate_per_m = 1e-5;  // optical depth 0.01 per km
  // Per column: max β, condensate depth, max |W|, vertical optical depth (for the contrast proxy).
  const std::size_t columns = std::size_t(v.nx) * std::size_t(v.ny);
  std::vector<double> colMax(columns, 0.0), depth_m(columns, 0.0), maxW(columns, 0.0), tau(columns, 0.0);
  for (int j = 0; j < v.ny; ++j)
    for (int i = 0; i < v.nx; ++i) {
      const std::size_t col = std::size_t(j) * std::size_t(v.nx) + std::size_t(i);
      for (int k = 0; k < v.nz; ++k) {
        const std::size_t q = v.index(i, j, k);
        colMax[col] = std::max(colMax[col], double(beta[q]));
        if (double(beta[q]) > kCondensate_per_m) depth_m[col] += v.dz_m;
        tau[col] += double(beta[q]) * v.dz_m;
        if (hasW) maxW[col] = std::max(maxW[col], std::abs(double(v.wind_w_m_per_s[q])));
      }
    }
  for (int j = 0; j < v.ny; ++j)
    for (int i = 0; i < v.nx; ++i) {
      const std::size_t col = std::size_t(j) * std::size_t(v.nx) + std::size_t(i);
      double convective;
      if (hasW) {
        convective = smoothstep(0.5, 3.0, maxW[col]);
      } else {
        // Proxy: a deep column that stands out from the 5×5 columns around it (a convective cell
        // in a shield or in clear air); a uniform deck, however deep, is stratiform.
        double around = 0.0;
        int count = 0;
        for (int jj = std::max(j - 2, 0); jj <= std::min(j + 2, v.ny - 1); ++jj)
          for (int ii = std::max(i - 2, 0); ii <= std::min(i + 2, v.nx - 1); ++ii) {
            around += tau[std::size_t(jj) * std::size_t(v.nx) + std::size_t(ii)];
            ++count;
          }
        around /= double(count);
        const double contrast = around > 0.0 ? tau[col] / around : 0.0;
        convective = smoothstep(3000.0, 7000.0, depth_m[col]) * smoothstep(1.2, 2.0, contrast);
      }
      for (int k = 0; k < v.nz; ++k) {
        const std::size_t q = v.index(i, j, k);
        double s = 0.0;
        if (hasTke) s = std::max(s, std::sqrt(std::max(double(v.tke_m2_per_s2[q]), 0.0) / 5.0));
        if (hasW) s = std::max(s, std::abs(double(v.wind_w_m_per_s[q])) / 2.0);
        if (!hasTke && !hasW) {
          const double centre = b(i, j, k);
          const double x0 = b(i - 1, j, k), x1 = b(i + 1, j, k), y0 = b(i, j - 1, k), y1 = b(i, j + 1, k),
                       z0 = b(i, j, k - 1), z1 = b(i, j, k + 1);
          const double m = std::max({centre, x0, x1, y0, y1, z0, z1});
          s = m > 0.0 ? (std::abs(x1 - x0) + std::abs(y1 - y0) + std::abs(z1 - z0)) / (2.0 * m) : 0.0;
        }
        const double turbulence = 0.25 + 0.75 * std::clamp(s, 0.0, 1.0);
        const double fraction = hasFraction ? std::clamp(double(v.cloud_fraction[q]), 0.0, 1.0) : 1.0;
        const double core = colMax[col] > 0.0 ? double(beta[q]) / colMax[col] : 0.0;
        const std::array<double, 4> ch{turbulence, convective, fraction, core};
        for (std::size_t k4 = 0; k4 < 4; ++k4) c.rgba[4 * q + k4] = unormCode(float(ch[k4]));
      }
    }
  return c;
}

int massSteps(int nz, int reach_voxels, double step_layers) {
  return int(std::ceil((double(nz) + 2.0 * double(reach_voxels)) / step_layers));
}

std::vector<glm::ivec2> massStepRanges(const ExtinctionVolumes& v, int filter_reach, int reach_voxels,
                                       const MassPattern& pattern) {
  const int steps = massSteps(v.nz, reach_voxels, pattern.step_layers);
  const std::size_t columns = std::size_t(v.nx) * std::size_t(v.ny);
  if (!pattern.occupied_only) return std::vector<glm::ivec2>(columns, glm::ivec2(0, steps));
  // The occupied layers [first, last] of every column (first > last: no cloud).
  const std::size_t n = v.voxelCount();
  std::vector<glm::ivec2> layers(columns, glm::ivec2(v.nz, -1));
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const std::size_t q = v.index(i, j, k);
        const float b =
            (v.ice_per_m.size() == n ? v.ice_per_m[q] : 0.0f) + (v.water_per_m.size() == n ? v.water_per_m[q] : 0.0f);
        if (!(b > 0.0f)) continue;
        glm::ivec2& l = layers[std::size_t(j) * std::size_t(v.nx) + std::size_t(i)];
        l = glm::ivec2(std::min(l.x, k), std::max(l.y, k));
      }
  // Union over the square of half-width r around (i, j).
  const auto around = [&](int i, int j, int r) {
    glm::ivec2 u(v.nz, -1);
    for (int jj = std::max(j - r, 0); jj <= std::min(j + r, v.ny - 1); ++jj)
      for (int ii = std::max(i - r, 0); ii <= std::min(i + r, v.nx - 1); ++ii) {
        const glm::ivec2& l = layers[std::size_t(jj) * std::size_t(v.nx) + std::size_t(ii)];
        u = glm::ivec2(std::min(u.x, l.x), std::max(u.y, l.y));
      }
    return u;
  };
  std::vector<glm::ivec2> ranges(columns, glm::ivec2(0));
  const double h = double(reach_voxels);
  for (int j = 0; j < v.ny; ++j)
    for (int i = 0; i < v.nx; ++i) {
      // A plain sample in the footprint reads voxels within the filter's reach of the column: none
      // occupied → P_J = 0 and c_J = 1, nothing to measure.
      if (around(i, j, filter_reach).x > v.nz - 1) continue;
      // A detailed sample reads β at x + d (|d| ≤ the displacement's reach): non-zero only within H
      // of an occupied voxel; one more layer absorbs rounding at the lattice's ends.
      const glm::ivec2 u = around(i, j, reach_voxels);
      const double z0 = double(u.x) - h - 1.0, z1 = double(u.y) + 1.0 + h + 1.0;  // grid z
      const int first = std::clamp(int(std::floor((z0 + h) / pattern.step_layers)), 0, steps);
      const int last = std::clamp(int(std::ceil((z1 + h) / pattern.step_layers)), 0, steps);
      ranges[std::size_t(j) * std::size_t(v.nx) + std::size_t(i)] = glm::ivec2(first, std::max(first, last));
    }
  return ranges;
}

double massSampleCount(const std::vector<glm::ivec2>& ranges, const MassPattern& pattern) {
  double steps = 0.0;
  for (const glm::ivec2& r : ranges) steps += double(r.y - r.x);
  return steps * 4.0 * double(pattern.rays_per_axis * pattern.rays_per_axis);
}

double RayMasses::plainOf(int i, int j) const {
  double sum = 0.0;
  for (int b = 0; b < rays_per_column; ++b)
    for (int a = 0; a < rays_per_column; ++a) sum += plain[index(i, j, a, b)];
  return sum;
}

double RayMasses::detailedOf(int i, int j) const {
  double sum = 0.0;
  for (int b = 0; b < rays_per_column; ++b)
    for (int a = 0; a < rays_per_column; ++a) sum += detailed[index(i, j, a, b)];
  return sum;
}

namespace {
/// detail.glsl's blend weights at continuous column index g: the 2 × 2 columns floor(g) + (0|1)
/// and their bilinear weights, in float as the shaders compute them.
struct CorrectionStencil {
  glm::ivec2 base{0};
  double w[4] = {0.0, 0.0, 0.0, 0.0};  // (0,0), (1,0), (0,1), (1,1)
};
CorrectionStencil correctionStencil(const glm::dvec2& g) {
  CorrectionStencil s;
  s.base = glm::ivec2(glm::floor(g));
  const glm::dvec2 f(detail_f32::detailCorrectionBlend(glm::vec2(g)));
  s.w[0] = (1.0 - f.x) * (1.0 - f.y);
  s.w[1] = f.x * (1.0 - f.y);
  s.w[2] = (1.0 - f.x) * f.y;
  s.w[3] = f.x * f.y;
  return s;
}
}  // namespace

double correctionAt(const std::vector<float>& c, int nx, int ny, const glm::dvec2& g) {
  const CorrectionStencil s = correctionStencil(g);
  double sum = 0.0;
  for (int q = 0; q < 4; ++q) {
    const int i = std::clamp(s.base.x + q % 2, 0, nx - 1), j = std::clamp(s.base.y + q / 2, 0, ny - 1);
    sum += s.w[q] * double(c[std::size_t(j) * std::size_t(nx) + std::size_t(i)]);
  }
  return sum;
}

std::vector<float> solveDetailCorrection(const RayMasses& m) {
  const int nx = m.nx, ny = m.ny, R = m.rays_per_column;
  const std::size_t columns = std::size_t(nx) * std::size_t(ny);
  std::vector<double> plain(columns, 0.0), detailed(columns, 0.0);
  double maxPlain = 0.0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t J = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      plain[J] = m.plainOf(i, j);
      detailed[J] = m.detailedOf(i, j);
      maxPlain = std::max(maxPlain, plain[J]);
    }
  // The stencil of every ray position within a column (the same in every column).
  std::vector<CorrectionStencil> stencils;
  for (int b = 0; b < R; ++b)
    for (int a = 0; a < R; ++a) {
      CorrectionStencil s = correctionStencil(glm::dvec2((a + 0.5) / R - 0.5, (b + 0.5) / R - 0.5));
      stencils.push_back(s);  // base relative to the column: (−1|0, −1|0)
    }
  std::vector<double> c(columns, 1.0);
  std::vector<std::size_t> active;
  for (std::size_t J = 0; J < columns; ++J) {
    if (!(plain[J] > 1e-6 * maxPlain) || !(detailed[J] > 0.0)) continue;        // no cloud: left at 1
    c[J] = std::clamp(plain[J] / detailed[J], kMinCorrection, kMaxCorrection);  // the start: no blend
    active.push_back(J);
  }
  // Gauss–Seidel: c_J = (P_J − Σ_r d_r·Σ_{K≠J} w_K c_K) / Σ_r d_r·w_J, clamped. Each footprint's own
  // weight is ≥ ½·½ at its rays, and its neighbours' share lies in a quarter column of band, so the
  // sweeps contract; 1e-7 relative is reached in a few dozen on the storms (docs/detail.md).
  for (int sweep = 0; sweep < 200; ++sweep) {
    double change = 0.0;
    for (const std::size_t J : active) {
      const int i = int(J % std::size_t(nx)), j = int(J / std::size_t(nx));
      double own = 0.0, others = 0.0;
      for (int b = 0; b < R; ++b)
        for (int a = 0; a < R; ++a) {
          const double d = m.detailed[m.index(i, j, a, b)];
          if (d == 0.0) continue;
          const CorrectionStencil& s = stencils[std::size_t(b) * std::size_t(R) + std::size_t(a)];
          for (int q = 0; q < 4; ++q) {
            if (s.w[q] == 0.0) continue;
            const int ki = std::clamp(i + s.base.x + q % 2, 0, nx - 1),
                      kj = std::clamp(j + s.base.y + q / 2, 0, ny - 1);
            const std::size_t K = std::size_t(kj) * std::size_t(nx) + std::size_t(ki);
            (K == J ? own : others) += d * s.w[q] * (K == J ? 1.0 : c[K]);
          }
        }
      if (!(own > 0.0)) continue;
      const double next = std::clamp((plain[J] - others) / own, kMinCorrection, kMaxCorrection);
      change = std::max(change, std::abs(next - c[J]) / c[J]);
      c[J] = next;
    }
    if (change < 1e-7) break;
  }
  return std::vector<float>(c.begin(), c.end());
}

glm::dvec3 detailDisplacement(const glm::dvec4& nd, double turbulence, const glm::dvec3& reach_m, const NoiseStats& s) {
  return glm::dvec3(detail_f32::detailDisplacement(
      glm::vec4(nd), float(turbulence), glm::vec3(reach_m),
      glm::vec4(float(s.r.mean), float(s.r.half_range), float(s.a.mean), float(s.a.half_range)),
      glm::vec2(float(s.g.mean), float(s.g.half_range))));
}

double detailDensity(const glm::dvec4& n1, const glm::dvec4& n2, const glm::dvec4& controls, double amplitude,
                     const NoiseStats& s) {
  return double(detail_f32::detailDensity(glm::vec4(n1), glm::vec4(n2), glm::vec4(controls), float(amplitude),
                                          glm::vec2(float(s.stratiform.mean), float(s.stratiform.half_range)),
                                          glm::vec2(float(s.convective.mean), float(s.convective.half_range))));
}

double detailModulation(const glm::dvec4& n1, const glm::dvec4& n2, double convective, const NoiseStats& s) {
  return double(detail_f32::detailModulation(glm::vec4(n1), glm::vec4(n2), float(convective),
                                             glm::vec2(float(s.stratiform.mean), float(s.stratiform.half_range)),
                                             glm::vec2(float(s.convective.mean), float(s.convective.half_range))));
}

double detailColumnCoverage(double beta_per_m, const glm::dvec2& d_columns, double column_m) {
  return double(detail_f32::detailColumnCoverage(float(beta_per_m), glm::vec2(d_columns), float(column_m)));
}

double detailShape(double coverage, double m, double amplitude) {
  return double(detail_f32::detailShape(float(coverage), float(m), float(amplitude)));
}

glm::dvec3 detailSecondFrame(const glm::dvec3& q) { return glm::dvec3(detail_f32::detailSecondFrame(glm::vec3(q))); }

}  // namespace nph::volume

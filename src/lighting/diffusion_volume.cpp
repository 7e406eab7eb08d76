#include "lighting/diffusion_volume.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "lighting/cloud_light.h"

namespace nph::lighting {
namespace {

// Per cell: the conductances 1/(R·h_i) to the +x, +y, +z neighbours (0 where there is none or
// the axis is off), the diagonal (all six faces, Marshak leaks and σ_a) and the right-hand side,
// all divided by the cell volume (uniform cells, so the system stays symmetric).
struct System {
  std::vector<glm::dvec3> up;  // conductance to the + neighbour per axis
  std::vector<double> diag, rhs;
  // For the face fluxes afterwards: half-cell resistances per axis and the drift terms.
  std::vector<glm::dvec3> half;
};

glm::dvec3 driftOf(const DiffusionProblem& p, std::size_t c) { return p.drift.empty() ? glm::dvec3(0.0) : p.drift[c]; }

constexpr std::size_t kVacuum = std::size_t(-1);

// Calls face(c, axis, side, neighbour, R, drift) for every face of every cell (both sides of the
// interior faces): the outward face flux is (φ_c − φ_neighbour + drift)/R, with
// drift = r_c·G_c·n + r_n·G_n·n and neighbour = kVacuum (φ = 0, r = 2, G = 0: Marshak) outside.
// With `limiter` (the previous pass's φ; DiffusionSolveOptions::flux_limited_passes) an interior
// face's resistance is divided by 3λ(R) of Levermore & Pomraning (1981), λ = (2 + R)/(6 + 3R + R²),
// R = |∇φ|/(σ_tr·φ) = |Δφ|/(φ̄·a·(r_c + r_n)): 1 in the diffusion limit, and in clear air
// |Δφ|/(3a·φ̄), so that |F| ≤ 3a·φ̄ (free streaming) instead of a short circuit.
double limitedResistance(double r, double a, double phiC, double phiN) {
  const double mean = 0.5 * (std::abs(phiC) + std::abs(phiN)), diff = std::abs(phiC - phiN);
  if (mean <= 0.0 || diff <= 0.0) return r;
  const double ratio = diff / (mean * a * std::max(r, 1e-300));
  const double lambda = ratio > 1e6 ? 1.0 / ratio : (2.0 + ratio) / (6.0 + 3.0 * ratio + ratio * ratio);
  return std::max(r / (3.0 * lambda), diff / (3.0 * a * mean));
}

template <class Face>
void forEachFace(const DiffusionProblem& p, const std::vector<glm::dvec3>& half, const DiffusionSolveOptions& o,
                 const std::vector<double>* limiter, Face face) {
  const glm::ivec3 m = p.cells;
  for (int k = 0; k < m.z; ++k)
    for (int j = 0; j < m.y; ++j)
      for (int i = 0; i < m.x; ++i) {
        const std::size_t c = p.index(i, j, k);
        for (int a = 0; a < 3; ++a) {
          if (a < 2 && !o.horizontal) continue;  // independent columns: no side faces at all
          for (int side : {-1, +1}) {
            glm::ivec3 nb(i, j, k);
            nb[a] += side;
            const double rc = half[c][a];
            const double gc = side * driftOf(p, c)[a];  // c's drift along the outward normal
            if (nb[a] < 0 || nb[a] >= m[a]) {
              face(c, a, side, kVacuum, std::max(rc + 2.0, o.min_resistance), rc * gc);
              continue;
            }
            const std::size_t nc = p.index(nb.x, nb.y, nb.z);
            const double rn = half[nc][a], gn = side * driftOf(p, nc)[a];
            double r = rc + rn;
            if (limiter != nullptr) r = limitedResistance(r, p.anisotropy[a], (*limiter)[c], (*limiter)[nc]);
            face(c, a, side, nc, std::max(r, o.min_resistance), rc * gc + rn * gn);
          }
        }
      }
}

System assemble(const DiffusionProblem& p, const DiffusionSolveOptions& o, const std::vector<double>* limiter) {
  System s;
  const std::size_t n = p.size();
  s.up.assign(n, glm::dvec3(0.0));
  s.diag.assign(n, 0.0);
  s.rhs.assign(n, 0.0);
  s.half.assign(n, glm::dvec3(0.0));
  for (std::size_t c = 0; c < n; ++c) {
    const double st = std::max(p.sigma_tr[c], 0.0);
    for (int a = 0; a < 3; ++a) s.half[c][a] = 0.5 * st * p.cell_m[a] / p.anisotropy[a];
    s.diag[c] = p.sigma_a.empty() ? 0.0 : std::max(p.sigma_a[c], 0.0);
    s.rhs[c] = std::max(p.source[c], 0.0);
  }
  forEachFace(p, s.half, o, limiter, [&](std::size_t c, int a, int side, std::size_t nc, double r, double drift) {
    const double h = p.cell_m[a];
    s.diag[c] += 1.0 / (r * h);
    s.rhs[c] -= drift / (r * h);
    if (side > 0 && nc != kVacuum) s.up[c][a] = 1.0 / (r * h);
  });
  return s;
}

void apply(const DiffusionProblem& p, const System& s, const std::vector<double>& x, std::vector<double>& y) {
  const glm::ivec3 m = p.cells;
  const std::size_t sx = 1, sy = std::size_t(m.x), sz = std::size_t(m.x) * std::size_t(m.y);
  for (int k = 0; k < m.z; ++k)
    for (int j = 0; j < m.y; ++j)
      for (int i = 0; i < m.x; ++i) {
        const std::size_t c = p.index(i, j, k);
        double v = s.diag[c] * x[c];
        if (i + 1 < m.x) v -= s.up[c].x * x[c + sx];
        if (i > 0) v -= s.up[c - sx].x * x[c - sx];
        if (j + 1 < m.y) v -= s.up[c].y * x[c + sy];
        if (j > 0) v -= s.up[c - sy].y * x[c - sy];
        if (k + 1 < m.z) v -= s.up[c].z * x[c + sz];
        if (k > 0) v -= s.up[c - sz].z * x[c - sz];
        y[c] = v;
      }
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

namespace {
// One linear solve (preconditioned conjugate gradients, Jacobi, from φ = 0) with the faces of
// `limiter` (nullptr: plain diffusion); fills out.fluence and out.flux.
void solveLinear(const DiffusionProblem& p, const DiffusionSolveOptions& o, const std::vector<double>* limiter,
                 DiffusionSolution& out) {
  const std::size_t n = p.size();
  const System s = assemble(p, o, limiter);
  std::vector<double>& x = out.fluence;
  x.assign(n, 0.0);
  out.flux.assign(n, glm::dvec3(0.0));
  std::vector<double> r = s.rhs, z(n), d(n), q(n);
  const double bnorm = std::sqrt(dot(s.rhs, s.rhs));
  if (bnorm == 0.0) return;
  for (std::size_t i = 0; i < n; ++i) z[i] = r[i] / s.diag[i];
  d = z;
  double rz = dot(r, z);
  int it = 0;
  double rel = 1.0;
  for (; it < o.max_iterations; ++it) {
    apply(p, s, d, q);
    const double alpha = rz / dot(d, q);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += alpha * d[i];
      r[i] -= alpha * q[i];
    }
    rel = std::sqrt(dot(r, r)) / bnorm;
    if (rel < o.tolerance) {
      ++it;
      break;
    }
    for (std::size_t i = 0; i < n; ++i) z[i] = r[i] / s.diag[i];
    const double rzNew = dot(r, z);
    const double beta = rzNew / rz;
    rz = rzNew;
    for (std::size_t i = 0; i < n; ++i) d[i] = z[i] + beta * d[i];
  }
  out.iterations += it;
  out.relative_residual = rel;
  // Cell fluxes: the mean of the two face fluxes per axis (in the + direction).
  forEachFace(p, s.half, o, limiter,
              [&](std::size_t c, int a, int side, std::size_t nc, double resistance, double drift) {
                const double outward = (x[c] - (nc == kVacuum ? 0.0 : x[nc]) + drift) / resistance;
                out.flux[c][a] += 0.5 * side * outward;
              });
}
}  // namespace

DiffusionSolution solveDiffusion(const DiffusionProblem& p, const DiffusionSolveOptions& o) {
  DiffusionSolution out;
  out.fluence.assign(p.size(), 0.0);
  out.flux.assign(p.size(), glm::dvec3(0.0));
  if (p.size() == 0) return out;
  solveLinear(p, o, nullptr, out);
  for (int pass = 0; pass < o.flux_limited_passes; ++pass) {
    const std::vector<double> previous = out.fluence;
    solveLinear(p, o, &previous, out);
  }
  return out;
}

DiffusionProblem diffusionProblemFor(const ExtinctionVolumes& v, const volume::VolumeFrame& frame,
                                     const glm::dvec3& to_sun,
                                     const std::function<double(const glm::dvec3&, double)>& sunlight,
                                     const DiffusionVolumeOptions& o) {
  DiffusionProblem p;
  const int cxy = std::max(o.coarsen_xy, 1), cz = std::max(o.coarsen_z, 1);
  p.cells = glm::ivec3((v.nx + cxy - 1) / cxy, (v.ny + cxy - 1) / cxy, (v.nz + cz - 1) / cz);
  const double e = std::max(frame.height_exaggeration, 1.0);
  p.cell_m = glm::dvec3(frame.voxel_size_m.x * cxy, frame.voxel_size_m.y * cxy, frame.voxel_size_m.z / e * cz);
  const glm::dvec3 sunFrame = twoStreamSunFrame(to_sun.z, e);
  const double az = sunFrame.z / 3.0;
  p.anisotropy = glm::dvec3(0.5 * (1.0 - az), 0.5 * (1.0 - az), az);
  const double beam = sunFrame.y;
  glm::dvec3 towardsSun(to_sun.x, to_sun.y, to_sun.z / e);
  const double len = glm::length(towardsSun);
  const glm::dvec3 omega0 = len > 0.0 ? -towardsSun / len : glm::dvec3(0.0, 0.0, -1.0);
  const std::size_t n = p.size();
  p.sigma_tr.assign(n, 0.0);
  p.source.assign(n, 0.0);
  p.drift.assign(n, glm::dvec3(0.0));
  std::vector<double> count(n, 0.0), drift(n, 0.0);  // drift: Σ g'·S
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const std::size_t f = v.index(i, j, k);
        const std::size_t c = p.index(i / cxy, j / cxy, k / cz);
        count[c] += 1.0;
        const double ice = f < v.ice_per_m.size() ? double(v.ice_per_m[f]) : 0.0;
        const double water = f < v.water_per_m.size() ? double(v.water_per_m[f]) : 0.0;
        const double beta = ice + water;
        if (beta <= 0.0) continue;
        const double g = o.g_water + (o.g_ice - o.g_water) * ice / beta;
        const double I = sunFrame.x > 0.0 ? sunlight(frame.worldFromGrid(glm::dvec3(i, j, k) + 0.5), g) : 0.0;
        p.sigma_tr[c] += (1.0 - g) * beta;
        p.source[c] += (1.0 - g * g) * beta * beam * I;
        drift[c] += g * (1.0 - g) * beta * beam * I;  // g'·S = g·(1 − g)·β·B·I
      }
  for (std::size_t c = 0; c < n; ++c) {
    if (count[c] <= 0.0) continue;
    if (p.sigma_tr[c] > 0.0) {
      // Σ q_i·S / Σ σ_tr: q = g' (physical), or g' + 3a_i − 1 (the two_stream term's convention).
      glm::dvec3 q(drift[c]);
      if (o.drift == DiffusionDrift::TwoStream) q += (3.0 * p.anisotropy - 1.0) * p.source[c];
      p.drift[c] = omega0 * q / p.sigma_tr[c];
    }
    p.sigma_tr[c] /= count[c];
    p.source[c] /= count[c];
  }
  return p;
}

namespace {
template <class T, class Get>
T trilinear(const DiffusionVolume& dv, const glm::dvec3& world_m, Get get) {
  const glm::dvec3 q = dv.frame.gridFromWorld(world_m) / glm::dvec3(dv.coarsen) - 0.5;
  const glm::ivec3 m = dv.problem.cells;
  const glm::dvec3 fl = glm::floor(q);
  const glm::dvec3 t = q - fl;
  T sum{};
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const glm::ivec3 c = glm::clamp(glm::ivec3(fl) + glm::ivec3(dx, dy, dz), glm::ivec3(0), m - 1);
        const double w = (dx ? t.x : 1.0 - t.x) * (dy ? t.y : 1.0 - t.y) * (dz ? t.z : 1.0 - t.z);
        sum += w * get(dv.problem.index(c.x, c.y, c.z));
      }
  return sum;
}
}  // namespace

double DiffusionVolume::fluenceAt(const glm::dvec3& world_m) const {
  return trilinear<double>(*this, world_m, [&](std::size_t c) { return solution.fluence[c]; });
}

glm::dvec3 DiffusionVolume::fluxAt(const glm::dvec3& world_m) const {
  return trilinear<glm::dvec3>(*this, world_m, [&](std::size_t c) { return solution.flux[c]; });
}

double DiffusionVolume::radianceAt(const glm::dvec3& world_m, const glm::dvec3& to_eye_data, double g) const {
  const double phi = fluenceAt(world_m);
  const glm::dvec3 f = fluxAt(world_m);
  return std::max(phi + 3.0 * g * glm::dot(f, to_eye_data), 0.0) / (4.0 * std::numbers::pi);
}

}  // namespace nph::lighting

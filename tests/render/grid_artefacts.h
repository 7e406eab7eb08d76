#pragma once
// The artefact metric of issue 13 (docs/rendering.md "Reconstruction"): how much of a rendered
// cloud's brightness varies with the period of the model's grid columns.
//
// Every pixel's ray is cut with the horizontal plane z = z_plane_m (world metres, exaggerated;
// the middle of the cloud layer) and the hit's continuous grid coordinates (gx, gy) are taken as
// the pixel's position in grid units. Along each image row, every run of opaque pixels (alpha ≥
// 0.98: the cloud's lit surface, not its silhouette, whose step edges are equally sharp with any
// filter) has its luminance a(px) (minus the run's mean, under a Hann window) projected onto
// frequencies f in cycles per column with a non-uniform DFT, for each axis g ∈ {gx, gy}:
//   A(f) = Σ_px w(px) (a(px) − ā) exp(−2πi f g(px)),   power(f) += |A(f)|² / Σ w².
// The metric sums power(f) over the band 0.75 … 1.25 cycles per column (the band absorbs the
// perspective's stretch of the period across a run and between the cloud's surface and the
// plane). The model carries no information above ½ cycle per column (its Nyquist frequency), so
// power there is made by the reconstruction: the steps and kinks that trilinear filtering puts on
// every column — and by the lighting's own sampling, which the test keeps out of the band with
// deep-light-map texels of ¼ voxel (1-voxel texels put light stripes at the column spacing with
// either filter: docs/rendering.md).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera.h"
#include "scene/output_image.h"
#include "volume/volume_frame.h"

namespace nph::test {

/// Σ over image rows, opaque runs and both grid axes of |A(f)|² / Σw² at each frequency of `freqs`
/// [cycles per column], of the channel `channel` of `layer` (0 = red: the luminance of a white
/// cloud). A run is a stretch of ≥ `min_run` pixels of a row with alpha ≥ `min_alpha` whose plane
/// hits lie over the grid; each run gets its own mean and Hann window.
inline std::vector<double> gridPowerSpectrum(const scene::RgbaImage& layer, const scene::Camera& camera,
                                             const volume::VolumeFrame& frame, double z_plane_m,
                                             const std::vector<double>& freqs, int channel = 0, double min_alpha = 0.98,
                                             std::size_t min_run = 24) {
  const int w = layer.width, h = layer.height;
  std::vector<double> power(freqs.size(), 0.0);
  std::vector<glm::dvec2> g;
  std::vector<double> a;
  auto flush = [&] {
    const std::size_t n = a.size();
    if (n >= min_run) {
      double mean = 0.0, norm = 0.0;
      std::vector<double> hann(n);
      for (std::size_t i = 0; i < n; ++i) {
        mean += a[i] / double(n);
        hann[i] = std::pow(std::sin(std::numbers::pi * (double(i) + 0.5) / double(n)), 2.0);
        norm += hann[i] * hann[i];
      }
      for (int axis = 0; axis < 2; ++axis) {
        for (std::size_t k = 0; k < freqs.size(); ++k) {
          double re = 0.0, im = 0.0;
          for (std::size_t i = 0; i < n; ++i) {
            const double v = hann[i] * (a[i] - mean);
            const double phase = -2.0 * std::numbers::pi * freqs[k] * g[i][axis];
            re += v * std::cos(phase);
            im += v * std::sin(phase);
          }
          power[k] += (re * re + im * im) / norm;
        }
      }
    }
    g.clear();
    a.clear();
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t px = (std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4;
      const glm::dvec3 d = camera.rayDirection(x + 0.5, y + 0.5);
      const double t = d.z < 0.0 ? (z_plane_m - camera.position_m.z) / d.z : -1.0;
      const glm::dvec3 grid = frame.gridFromWorld(camera.position_m + t * d);
      const bool over =
          t > 0.0 && grid.x >= 0.0 && grid.y >= 0.0 && grid.x <= frame.voxels.x && grid.y <= frame.voxels.y;
      if (!over || double(layer.rgba[px + 3]) < min_alpha) {  // (min_alpha 0: every pixel over the grid)
        flush();
        continue;
      }
      g.push_back({grid.x, grid.y});
      a.push_back(double(layer.rgba[px + std::size_t(channel)]));
    }
    flush();
  }
  return power;
}

/// a − b in colour, the smaller alpha (so the metric's opaque runs are opaque in both): the
/// spectrum of a rendition's difference from a reference.
inline scene::RgbaImage layerMinus(const scene::RgbaImage& a, const scene::RgbaImage& b) {
  scene::RgbaImage d = a;
  for (std::size_t i = 0; i < d.rgba.size(); i += 4) {
    for (std::size_t c = 0; c < 3; ++c) d.rgba[i + c] = a.rgba[i + c] - b.rgba[i + c];
    d.rgba[i + 3] = std::min(a.rgba[i + 3], b.rgba[i + 3]);
  }
  return d;
}

/// The metric: the power of gridPowerSpectrum summed over `f_lo` … `f_hi` cycles per column in
/// steps of 0.05 (default: the band 0.75 … 1.25 around the column spacing).
inline double gridArtefactPower(const scene::RgbaImage& layer, const scene::Camera& camera,
                                const volume::VolumeFrame& frame, double z_plane_m, double f_lo = 0.75,
                                double f_hi = 1.25) {
  std::vector<double> f;
  for (int k = 0; f_lo + 0.05 * k <= f_hi + 1e-9; ++k) f.push_back(f_lo + 0.05 * k);
  double p = 0.0;
  for (double x : gridPowerSpectrum(layer, camera, frame, z_plane_m, f)) p += x;
  return p;
}

}  // namespace nph::test

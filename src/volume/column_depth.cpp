#include "volume/column_depth.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "core/error.h"
#include "volume/spline_coefficients.h"

namespace nph {
namespace {
// The value the GPU stores: half precision (RG16F), clamped to the largest finite half.
// Clamped at 0: the interpolating spline's coefficients (volume/spline_coefficients.h) ring below 0
// above a cloud top, so a partial sum may dip a little below 0 (never for voxels ≥ 0).
std::uint16_t halfBits(double x) { return glm::packHalf1x16(float(std::clamp(x, 0.0, 65504.0))); }
// β_ice + β_water of column c of a layer times the layer thickness (double: a column of 100 layers
// of small β keeps its sum). An absent phase reads 0 (ExtinctionSlices), which adds nothing.
double betaDz(const ExtinctionSlices::Slice& s, std::size_t c, double dz_m) {
  return (double(s.ice[c]) + double(s.water[c])) * dz_m;
}
}  // namespace

ColumnDepthSlices::ColumnDepthSlices(const ExtinctionVolumes& v)
    : ColumnDepthSlices(std::make_unique<VolumeSlices>(v), VolumeSlices(v), {}) {}

ColumnDepthSlices::ColumnDepthSlices(const ExtinctionSlices& slices) : ColumnDepthSlices(nullptr, slices, {}) {}

ColumnDepthSlices::ColumnDepthSlices(const ExtinctionSlices& slices,
                                     const std::function<void(int, const ExtinctionSlices::Slice&)>& see)
    : ColumnDepthSlices(nullptr, slices, see) {}

ColumnDepthSlices::ColumnDepthSlices(std::unique_ptr<VolumeSlices> own, const ExtinctionSlices& slices,
                                     const std::function<void(int, const ExtinctionSlices::Slice&)>& see)
    : own_(std::move(own)),
      src_(own_ ? own_.get() : &slices),
      dz_m_(slices.volumes().dz_m),
      total_(std::size_t(slices.volumes().nx) * std::size_t(slices.volumes().ny), 0.0),
      below_(total_.size(), 0.0),
      slice_(2 * total_.size()),
      next_k_(0) {
  for (int k = 0; k < slices.volumes().nz; ++k) {
    const ExtinctionSlices::Slice s = src_->slice(k, scratch_);
    if (see) see(k, s);
    for (std::size_t c = 0; c < total_.size(); ++c) total_[c] += betaDz(s, c, dz_m_);
  }
}

const std::vector<std::uint16_t>& ColumnDepthSlices::next(int k) {
  if (k != next_k_ || k >= src_->volumes().nz) {
    throw UsageError(fmt::format("ColumnDepthSlices::next: slice {} asked for, {} is next", k, next_k_));
  }
  beta_ = src_->slice(k, scratch_);
  for (std::size_t c = 0; c < total_.size(); ++c) {
    const double full = betaDz(beta_, c, dz_m_), half = 0.5 * full;
    slice_[2 * c] = halfBits(std::max(total_[c] - below_[c] - half, 0.0));
    slice_[2 * c + 1] = halfBits(total_[c]);
    below_[c] += full;
  }
  ++next_k_;
  return slice_;
}

std::vector<std::uint16_t> columnDepthsHalf(const ExtinctionVolumes& v) {
  std::vector<std::uint16_t> rg(2 * v.voxelCount());
  ColumnDepthSlices slices(v);
  const std::size_t columns = std::size_t(v.nx) * std::size_t(v.ny);
  for (int k = 0; k < v.nz; ++k) {
    const std::vector<std::uint16_t>& s = slices.next(k);
    std::copy(s.begin(), s.end(), rg.begin() + std::ptrdiff_t(2 * std::size_t(k) * columns));
  }
  return rg;
}

ColumnDepths columnDepths(const ExtinctionVolumes& v, volume::Reconstruction reconstruction) {
  if (volume::readsSplineCoefficients(reconstruction)) {  // the sums of what the filter reads
    ColumnDepths c = columnDepths(volume::splineCoefficientVolumes(v), volume::Reconstruction::Cubic);
    c.reconstruction = reconstruction;
    return c;
  }
  ColumnDepths d;
  d.reconstruction = reconstruction;
  d.nx = v.nx;
  d.ny = v.ny;
  d.nz = v.nz;
  const std::vector<std::uint16_t> rg = columnDepthsHalf(v);
  d.up.resize(v.voxelCount());
  d.down.resize(v.voxelCount());
  // τ_down = T − τ_up in float from the two halves, as the shaders form it (glsl/dlm/volume.glsl
  // packedTexel, glsl/render/clouds.comp columnDepthAt) after filtering both.
  for (std::size_t i = 0; i < d.up.size(); ++i) {
    d.up[i] = glm::unpackHalf1x16(rg[2 * i]);
    d.down[i] = glm::unpackHalf1x16(rg[2 * i + 1]) - d.up[i];
  }
  return d;
}

glm::dvec2 columnDepthAt(const ColumnDepths& d, const volume::VolumeFrame& frame, const glm::dvec3& world_m) {
  if (d.nx <= 0 || d.ny <= 0 || d.nz <= 0) return glm::dvec2(0.0);
  // The extinction's own filter (volume/reconstruction.h), clamped to the edge (see the header).
  const glm::ivec3 last(d.nx - 1, d.ny - 1, d.nz - 1);
  return volume::reconstructAt(d.reconstruction, frame.gridFromWorld(world_m) - 0.5, [&](int i, int j, int k) {
    const glm::ivec3 idx = glm::clamp(glm::ivec3(i, j, k), glm::ivec3(0), last);
    const std::size_t n =
        (std::size_t(idx.z) * std::size_t(d.ny) + std::size_t(idx.y)) * std::size_t(d.nx) + std::size_t(idx.x);
    return glm::dvec2(d.up[n], d.down[n]);
  });
}

}  // namespace nph

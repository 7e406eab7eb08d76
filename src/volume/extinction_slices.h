#pragma once
// One timestep's extinctions read one horizontal layer at a time (issue 19, docs/benchmarks.md
// "Memory"). The upload of a single frame (render/dlm/volume_textures.cpp) checks the voxels,
// builds the occupancy and the column depths and writes the packed texture slice by slice, so
// the float volume (8 bytes per voxel) never has to exist whole: a `.nph` timestep is decoded a
// layer at a time from its chunk as the file is read (cache::NphReader::readSlices: a zstd stream,
// no code of the timestep held beyond the layer), with the file's own rule (cache/quantize.h
// dequantise), the same floats NphReader::read makes. Sources read upwards at the cost of one
// decode per pass; the upload's passes all go from k = 0 up.
#include <memory>
#include <vector>

#include "volume/extinction_volumes.h"

namespace nph {

class ExtinctionSlices {
 public:
  /// Layer k's β [1/m], nx·ny values each, x fastest (ExtinctionVolumes::index with k fixed).
  /// Never null: an absent phase reads as zeros.
  struct Slice {
    const float* ice = nullptr;
    const float* water = nullptr;
  };

  virtual ~ExtinctionSlices() = default;
  /// The grid, georeference, terrain, time, provenance and maxima; its fields (ice_per_m,
  /// water_per_m, the detail fields) may be empty (a decoded-by-layer source) or whole (whole()).
  virtual const ExtinctionVolumes& volumes() const = 0;
  /// Layer k (0 ≤ k < nz) into pointers that stay valid until the next call with the same
  /// `scratch` (which the source may resize and fill, or leave alone when it holds the floats).
  virtual Slice slice(int k, std::vector<float>& scratch) const = 0;
  /// Bytes of voxel data the source holds (its floats, or its codes): the memory it costs while
  /// an upload reads it.
  virtual std::size_t heldBytes() const = 0;
  /// The whole float volume when the source holds it (no copy), else null.
  virtual const ExtinctionVolumes* whole() const { return nullptr; }
  /// The whole float volume: whole() copied, or every layer decoded (paths that need the grid at
  /// once: the cubic filter's and the detail's separate textures, VolumeStorage::Reference).
  ExtinctionVolumes materialise() const;
};

/// Over an ExtinctionVolumes held elsewhere (`volumes` must outlive this) or shared with it.
class VolumeSlices final : public ExtinctionSlices {
 public:
  explicit VolumeSlices(const ExtinctionVolumes& volumes) : v_(&volumes) {}
  explicit VolumeSlices(std::shared_ptr<const ExtinctionVolumes> volumes)
      : v_(volumes.get()), owned_(std::move(volumes)) {}
  const ExtinctionVolumes& volumes() const override { return *v_; }
  Slice slice(int k, std::vector<float>& scratch) const override;
  const ExtinctionVolumes* whole() const override { return v_; }
  std::size_t heldBytes() const override { return (v_->ice_per_m.size() + v_->water_per_m.size()) * sizeof(float); }

 private:
  const ExtinctionVolumes* v_;
  std::shared_ptr<const ExtinctionVolumes> owned_;
};

}  // namespace nph

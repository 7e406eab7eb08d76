#pragma once
// A dataset opened for rendering: a `.nph` extinction cache (read lazily, one timestep at a time),
// a WRF/ICON model file or a series of them (each timestep converted on load with the default
// optics; convert to .nph first for speed, docs/conversion.md). Loads are thread-safe (model
// files are read one at a time: NetCDF-C is not thread-safe), so a prefetch thread may decode the
// next timestep while the current one renders (Nes 2008 §5.1.2; timestep_cache.h).
//
// Fractional time (Thomann 2021 §5.5; Nes 2008 §5.1.2): the state at time index t ∈ [i, i+1] is
// the linear blend of the extinction volumes of timesteps i and i+1, β(t) = (1−w)·β_i + w·β_{i+1},
// w = t − i. Linear in extinction keeps optical depths linear in w and never creates condensate
// where neither timestep has any; its artefact is that a cloud that *moves* between timesteps
// fades out at the old place while it fades in at the new one (a double image at w = ½) instead of
// translating — model output every 5–15 minutes keeps that small; hourly output shows it.
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/model_fields.h"
#include "volume/extinction_slices.h"
#include "volume/extinction_volumes.h"

namespace nph::engine {

class Dataset {
 public:
  /// Opens `path`: a .nph cache, a model file io::openModelFile recognises, or a folder of model
  /// files (openSeries). InputError names the file and what is wrong.
  static std::shared_ptr<const Dataset> open(const std::string& path);
  /// Several model files as one time-ordered list of timesteps (io::ModelSeries); one path is
  /// open(path). Folders and patterns are expanded (io::expandModelInputs). Only the headers are read here: a file
  /// damaged after its header fails in load().
  static std::shared_ptr<const Dataset> openSeries(const std::vector<std::string>& paths);
  /// Extinction volumes already in memory, one per timestep (the Python module's arrays, issue
  /// #16): `name` stands for the path in messages. Every timestep is checked as a .nph cache
  /// would hold it — sizes nx·ny·nz, dx, dy, dz > 0, finite β ≥ 0 — and InputError names `name`,
  /// the timestep and the array; the volumes' maxima are recomputed.
  static std::shared_ptr<const Dataset> fromVolumes(std::string name, std::vector<ExtinctionVolumes> timesteps);
  /// Model fields already in memory, one io::ModelTimestep per timestep (the Python module's
  /// hydrometeor arrays, issue #16), converted on load exactly as a model file's timesteps are
  /// (convertModelTimestep). `name` stands for the path in messages; the optics' and the vertical
  /// resampling's checks name it and the variable (InputError).
  static std::shared_ptr<const Dataset> fromModelFields(std::string name, std::vector<io::ModelTimestep> timesteps);
  virtual ~Dataset() = default;

  const std::string& path() const { return path_; }
  std::size_t timestepCount() const { return times_.size(); }
  /// The time of every timestep, parsed by the loaders; none where the data does not say.
  const std::vector<geo::OptionalUtcTime>& times() const { return times_; }
  /// Timestep t's time as ISO 8601, "" for none; the string lives as long as the dataset (C API).
  const std::string& isoTime(std::size_t t) const { return iso_times_.at(t); }
  /// Reads (and for model files converts) timestep t; thread-safe. InputError on bad data.
  virtual ExtinctionVolumes load(std::size_t t) const = 0;
  /// Timestep t read one layer at a time (volume/extinction_slices.h; issue 19, memory): a .nph
  /// cache decodes each layer from its file as load() would, holding no more than a layer
  /// (cache::NphReader::readSlices streams the chunk);
  /// other datasets wrap load(t). For a one-shot upload that never needs the floats whole.
  virtual std::unique_ptr<ExtinctionSlices> loadSlices(std::size_t t) const;
  /// Timestep t's grid, georeference, terrain, time and maxima without its volumes, where that
  /// is cheap (a .nph cache: from its index); std::nullopt otherwise (use load()).
  virtual std::optional<ExtinctionVolumes> loadHeader(std::size_t t) const;
  /// Names the content of timestep t (absolute path + index) for the DLM cache key.
  std::string identity(std::size_t t) const;
  /// The file timestep t is read from (the dataset's path unless it is a series).
  const std::string& sourceFile(std::size_t t) const { return sources_.empty() ? path_ : sources_.at(t); }

 protected:
  Dataset(std::string path, std::vector<geo::OptionalUtcTime> times, std::vector<std::string> sources = {});

 private:
  std::string path_;
  std::vector<geo::OptionalUtcTime> times_;
  std::vector<std::string> iso_times_;
  std::vector<std::string> sources_;  ///< per timestep, for series; empty otherwise
};

/// One timestep of model fields converted as `nephele render FILE` converts it: the default
/// optics (Nes 2008 eq. 5.3), the default vertical grid (cropped above the condensate).
ExtinctionVolumes convertModelTimestep(const io::ModelTimestep& fields);
/// The same from fields the caller gives up: each is freed after its last stage
/// (physics::buildExtinctionVolumes(ModelTimestep&&); a model file read for one frame).
ExtinctionVolumes convertModelTimestep(io::ModelTimestep&& fields);

/// How a volume between two timesteps is made (issue 13; docs/animation.md "Between two timesteps").
enum class TimeBlend {
  /// Cross-fade: β = (1−w)·β_a + w·β_b. A cloud the model moved fades out at its old place and
  /// in at its new one (a translucent double image mid-interval).
  Linear,
  /// Motion-compensated: each timestep is carried along its own horizontal wind to the frame's
  /// time before the cross-fade (semi-Lagrangian trajectories, Staniforth & Côté 1991),
  ///   β(x, w) = (1−w)·β_a(x − d_a) + w·β_b(x + d_b),
  /// d_a ≈ w·Δt·u_a (backward from the frame to timestep a), d_b ≈ (1−w)·Δt·u_b (forward to
  /// timestep b), each a midpoint trajectory iterated twice, sampled bilinearly in the horizontal.
  /// u is each column's cloud-weighted wind over its levels (and the columns around it), so a cloud
  /// column moves as one: a tower in a wind sheared with height stays upright (docs/animation.md
  /// "Clouds move as columns"). Falls back to Linear (the same volume bit for bit) where it has no motion: Δt
  /// unknown or ≤ 0 (a timestep without a time), or either timestep without U, V (a .nph cache,
  /// a host volume).
  Motion
};
/// Names in the order of the enum values (messages, docs).
inline constexpr std::array<std::string_view, 2> kTimeBlendNames{"linear", "motion"};
/// What a Session blends with unless told otherwise: motion-compensated, which is the linear blend
/// where the data has no wind (docs/animation.md "Between two timesteps": measured).
inline constexpr TimeBlend kDefaultTimeBlend = TimeBlend::Motion;

/// The volume at weight w between timesteps a and b, on the union of both columns: the grids must
/// agree horizontally and in dz, and their bottoms must lie on one dz lattice (layer counts and
/// bottoms may differ: missing layers count as zeros). UsageError otherwise.
/// w is clamped to [0, 1]; w = 0 and w = 1 return a and b exactly. Ice, water and the detail
/// fields (volume/detail.h) are blended alike; the detail clock is the blend of both clocks.
/// `blend` has no default: the Session's (kDefaultTimeBlend) is the one callers should think of.
ExtinctionVolumes blendVolumes(const ExtinctionVolumes& a, const ExtinctionVolumes& b, double w, TimeBlend blend);
/// Whether TimeBlend::Motion moves anything between a and b (both carry U, V and a time, b later
/// than a); false: it is the linear blend.
bool blendHasMotion(const ExtinctionVolumes& a, const ExtinctionVolumes& b);

/// The timestep pair and weight of fractional time index `t` among `count` timesteps:
/// t is clamped to [0, count−1]; returns {i, i+1 (or i at the end), w}.
struct TimeBracket {
  std::size_t first = 0, second = 0;
  double weight = 0.0;  ///< of `second`
};
TimeBracket bracketTime(double t, std::size_t count);

}  // namespace nph::engine

#pragma once
// ICON model-level output as GRIB2 (DWD ICON-D2 / ICON-EU open data, and single files holding all
// variables, levels and steps): the messages of any number of files are indexed together and
// grouped by validity time into timesteps, so DWD's one-file-per-variable-level-and-step layout
// (icon-d2_germany_regular-lat-lon_model-level_<run>_<step>_<level>_<var>.grib2, heights in the
// run's time-invariant ..._hhl.grib2, native-grid cell centres in ..._clon/clat.grib2) and one
// multi-message file read the same.
// Variables are recognised by discipline.category.number (GRIB2 code table 4.2 and DWD's local
// entries, as ecCodes' definitions/grib2/localConcepts/edzw/shortName.def names them), so they
// are found whatever shortName table a writer used: QC 0.1.22, QI 0.1.82, QR 0.1.24, QS 0.1.25,
// QG 0.1.32, QH 0.1.71, QV 0.1.0, T 0.0.0, P 0.3.0, HHL 0.3.6, CLC 0.6.22 [%], CLON 0.191.2,
// CLAT 0.191.1 [deg]. Model levels are typeOfFirstFixedSurface 150 (generalized vertical height),
// level 1 at the model top; HHL holds nz + 1 half levels. The fields go through the same
// assembly as the NetCDF loader (icon_fields.h): same checks, same vertical order, same heights.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "grib2_reader.h"
#include "icon_fields.h"
#include "load_options.h"
#include "model_fields.h"

namespace nph::io {

/// The role of a message in an ICON data set (Other: anything nephele does not read).
enum class Grib2Role : std::uint8_t { Q, QV, T, P, HHL, CLC, CLON, CLAT, Other };

/// Messages of one or more GRIB2 files, indexed and checked for one ICON grid.
class Grib2Dataset {
 public:
  /// Scans every file (InputError for unreadable, truncated or non-GRIB2 files) and checks that
  /// the data set is complete: temperature, pressure, heights (HHL), a condensate; every level of
  /// every variable; one grid (InputError "mixed grids" naming two messages otherwise); for the
  /// native grid, CLON/CLAT with the fields' uuidOfHGrid.
  static std::shared_ptr<const Grib2Dataset> open(const std::vector<std::string>& files);

  bool native() const { return grid_.type == "unstructured_grid"; }
  const Grib2Grid& grid() const { return grid_; }
  const std::vector<std::string>& files() const { return files_; }
  std::size_t messageCount() const { return message_count_; }
  std::size_t levels() const { return nz_; }
  /// Validity times of the timesteps (ISO 8601), in time order.
  const std::vector<std::string>& times() const { return times_; }
  /// The file holding timestep t's first temperature message (for logs and progress).
  const std::string& firstFileOf(std::size_t t) const;
  /// "QC 20 levels x 2 times, ..." for `nephele info`.
  std::string variableSummary() const;

  ModelTimestep load(std::size_t t, const LoadOptions& options) const;

 private:
  struct Key {
    Grib2Role role = Grib2Role::Other;
    int hydrometeor = -1;  // Hydrometeor for Q, else -1
    auto operator<=>(const Key&) const = default;
  };
  /// role -> validity time -> level -> message
  using LevelMap = std::map<long, Grib2Message>;
  std::map<Key, std::map<std::string, LevelMap>> index_;
  std::vector<std::string> files_, times_;
  Grib2Grid grid_;
  std::map<std::string, std::size_t> ignored_;  ///< shortName -> messages not read
  std::size_t nz_ = 0, message_count_ = 0;

  const LevelMap& levelsAt(const Key& key, const std::string& time, bool time_invariant) const;
  /// Levels 1 .. `levels` of `key` at `time`, each message checked as `quantity` on reading.
  std::vector<float> readLevels(const Key& key, const std::string& time, std::size_t levels, bool time_invariant,
                                IconQuantity quantity, LoadRepairs& repairs) const;
};

}  // namespace nph::io

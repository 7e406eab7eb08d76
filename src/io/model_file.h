#pragma once
// Entry point of io/: recognise a model file, list its timesteps, load one lazily; and series of
// files (several times per file, several files) as one list of timesteps.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "load_options.h"
#include "model_fields.h"

namespace nph::io {

class Grib2Dataset;

enum class FileFormat : std::uint8_t {
  WrfOut,            ///< WRF ARW wrfout (dims Time/bottom_top/south_north/west_east)
  IconRegular,       ///< ICON on a regular lat-lon grid (dims lat, lon)
  IconNative,        ///< ICON on its native triangular grid (dim ncells, clon/clat)
  Grib2IconRegular,  ///< ICON model levels as GRIB2 on a regular lat-lon grid (grib2_loader.h)
  Grib2IconNative    ///< ICON model levels as GRIB2 on the native grid, CLON/CLAT by uuidOfHGrid
};
const char* formatName(FileFormat format);

/// Recognises a file from its NetCDF header or its GRIB signature (a GRIB file is scanned: its
/// grid decides); InputError for a file that is neither, or a NetCDF file that is neither wrfout
/// nor ICON (the message says what was looked for).
FileFormat sniffFormat(const std::string& path);

/// One timestep of one file.
struct TimestepRef {
  std::string file;
  std::int64_t index = 0;         ///< inside `file`
  geo::OptionalUtcTime time_utc;  ///< none when the file does not say
  FileFormat format = FileFormat::WrfOut;
  /// GRIB2: the data set the timestep belongs to (its messages may span many files; `file` is the
  /// one holding its first temperature message and `index` the timestep in the data set).
  std::shared_ptr<const Grib2Dataset> grib;
};

/// True when `path` is a regular file starting with a model file's signature: NetCDF classic, 64-bit offset or CDF-5
/// ("CDF" 1|2|5), HDF5 (netCDF-4) or GRIB.
bool hasModelFileSignature(const std::string& path);

/// Command-line inputs to files: a folder becomes the GRIB2 and NetCDF files in it (sorted), a
/// pattern with * ? [ that names no file is expanded (glob(3), sorted); other paths pass as
/// they are. InputError for a folder without model files or a pattern that matches nothing.
std::vector<std::string> expandModelInputs(const std::vector<std::string>& inputs);

/// A recognised model file; cheap to keep, loads a timestep on demand.
class ModelFile {
 public:
  ModelFile(std::string path, FileFormat format, std::vector<TimestepRef> timesteps, LoadOptions options);
  const std::string& path() const { return path_; }
  FileFormat format() const { return format_; }
  const std::vector<TimestepRef>& timesteps() const { return timesteps_; }
  /// Loads timestep `i` (0-based within this file).
  ModelTimestep load(std::size_t i) const;

 private:
  std::string path_;
  FileFormat format_;
  std::vector<TimestepRef> timesteps_;
  LoadOptions options_;
};

/// Sniffs `path` and lists its timesteps (reads only the header and the time axis; a GRIB2 file
/// is indexed on its own, see ModelSeries for GRIB2 spread over files).
ModelFile openModelFile(const std::string& path, const LoadOptions& options = {});

/// Loads one timestep described by `ref`.
ModelTimestep loadTimestep(const TimestepRef& ref, const LoadOptions& options = {});

/// Reads the sub-grid detail's fields of a timestep loaded with LoadOptions::defer_detail (its
/// `detail_deferred` is then cleared); nothing for one that has them.
void loadDeferredDetail(ModelTimestep& ts, const LoadOptions& options = {});

/// Timesteps of several files in time order (stable: files without times keep their order).
/// GRIB2 files among `paths` are indexed together as one data set (DWD writes one file per
/// variable, level and step), whatever their order.
class ModelSeries {
 public:
  static ModelSeries open(const std::vector<std::string>& paths, const LoadOptions& options = {});
  std::size_t size() const { return timesteps_.size(); }
  const TimestepRef& at(std::size_t i) const { return timesteps_.at(i); }
  const std::vector<TimestepRef>& timesteps() const { return timesteps_; }
  ModelTimestep load(std::size_t i) const;

 private:
  std::vector<TimestepRef> timesteps_;
  LoadOptions options_;
};

}  // namespace nph::io
